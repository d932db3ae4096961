// The link reconstruction (reconstruct.h): what it gathers, and why, is described there.
#include "readout/reconstruct.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <tuple>

#include "radiosity/cluster.h"
#include "radiosity/cluster_nodes.h"
#include "radiosity/elements.h"
#include "readout/gather.h"
#include "radiosity/punctual_lights.h"

namespace radbake {
namespace {

// Where rays go, measured against the exhaustive gather with tools/bench_reconstruct
// (2 threads, CPU time; RMS of the relative error over covered texels / vertices). Rays for
// every link not proven visible, pieces split as the exhaustive gather splits them: 580 us a
// texel of the Cornell Box at 64 texels/m for 1.7 % RMS. Rays for the sources with the most
// unoccluded light until the rest could bring at most 5 % of the point's light (the
// solver's visibility for that rest), a partly visible piece opened down to 0.05 radius /
// distance and split at most once below a leaf: 55 us a texel for 2.2 %; vertices of the
// tessellated Cornell box 190 us for 8.6 % (the block bottom edges, where the exhaustive
// gather is itself 30-60 % off a path tracer), house.wrl 130 us. A per-source share of
// 0.3 % instead of a bound on the rest: 45 us a texel for 1.8 % but 26 % on the
// tessellated box (light leaking under its blocks through many small links); no rays at
// all: 10 us a texel for 34 %. (Figures from before the gather's horizon-clipped rays and
// its opening where the light varies, gather.h: since, 1.8 % at the same cost.)
constexpr double kRayShare = 0.05;
// With ReadoutOptions::probe_coarse_opening, a partly visible source (its link's rays
// disagreed) that may bring more than this share of the point's light is opened as the
// exhaustive gather's coarse rule opens it (its unanimous rays trusted only on pieces small
// enough): 2 x 2 rays from a point under a lamp to a large piece of floor can all meet beams
// where a quarter of it shows (docs/readout.md has what it costs and buys).
constexpr double kCoarseShare = 0.02;
constexpr double kLinkVisibilityRatio = 0.05;
// A separable cluster link whose source holds at most this many roots is read member by
// member at the point: the product form is first-order in the nodes' extents, and it read
// the tessellated Cornell box's walls 0.2 % low more than the element links do (output
// vertices 2.51 % RMS, 2.40 % with this; 2.37 % with `--no-clustering`), for 10 % more form
// factors on house.wrl's vertices and no measurable time.
constexpr uint32_t kExactSeparableMembers = 64;
// Where a point touches a face that meets its own at a concave edge or corner, the gather
// takes that face's leaf beside it at its mean radiosity; but a concave corner darkens toward
// its edge, and from a point on the edge the form factor is concentrated there (the
// tessellated Cornell box's room corners read +9 %, its wall-ceiling edges +3 %). The
// correction models that leaf's radiosity as linear in the distance h from the line the two
// planes share, equal on the line to what that face gets at this very point (E + rho H, read
// through its own links) and keeping the leaf's mean, and adds what that changes in the
// leaf's light: sum over pieces f (h / h_mean - 1) (B_mean - B_line). Exact (zero) where the
// radiosity is uniform. Pieces: the leaf split three times (64 for a quad).
constexpr int kEdgeCorrectionSplits = 3;
// Further splits of the pieces nearest the point (each makes 3 more pieces): enough to go from
// a 1/8 of a leaf down to a few lifts on a leaf 1e4 lifts across.
constexpr size_t kEdgeNearSplits = 48;
constexpr double kEdgeCorrectionShare = 0.01;
// A point whose way in runs along the edge it shares with a face beside (more than this
// cosine) is at the end of that edge: a block's corner on a floor, where the floor's light
// turns with the direction around it (a shadow wedge starts at the corner: the tessellated
// Cornell box's tall block's corner read -18 % and -16 % on its two faces from one read of the
// floor). The floor is read in kCornerSectors sectors there.
constexpr double kCornerAlongLine = 0.1;
// Read in two halves first, and in kCornerSectors sectors when those differ by more than
// kCornerAgreement in some channel (a bench run over house.wrl's vertices made about 1,800
// sector reads: furniture stands on its floors).
constexpr int kCornerSectors = 6;
constexpr double kCornerAgreement = 0.05;
constexpr int kLinkVisibilitySplits = 1;

// The light of another face at the point, given by the caller, for a face of this normal.
const LinkReconstruction::SideLight* sideLightOf(std::span<const LinkReconstruction::SideLight> side_light,
                                                 const DVec3& normal) {
    for (const auto& l : side_light)
        if (glm::dot(l.normal, normal) > 1.0 - LinkReconstruction::kSameNormal) return &l;
    return nullptr;
}

// The polygon among `candidates` that holds p: the first within a rounding tolerance of it
// (1e-6 of its size: a point on the edge two children share, a chart edge's sample, goes to
// the first whatever the scene's scale), else the nearest.
template <class Range>
uint32_t nearest(const Solution& s, const Range& candidates, const DVec3& p) {
    uint32_t best = kNoElement;
    double best_distance = 0.0;
    for (uint32_t e : candidates) {
        const double d = pointPolygonDistance(p, polygonOf(s, s.elements[e]));
        if (d <= 1e-6 * s.elements[e].radius) return e;
        if (best == kNoElement || d < best_distance) {
            best = e;
            best_distance = d;
        }
    }
    return best;
}

}  // namespace

namespace {

std::atomic<uint64_t> g_reconstructions{0};

// A point read on a root lies within this many lifts of its polygon (gather.h, liftOffSurfaces);
// and its normal within this angle (radians) of the root's.
constexpr double kRootMarginLifts = 8.0;
constexpr double kRootNormalSlack = 1e-2;
constexpr size_t kCachedRoots = 8;

// Whether `source` can face some point near `root`'s polygon with a vertex above that point's
// horizon (the gather's inFront), with the margins above: false only when it cannot.
bool canFace(const Solution& s, const Element& source, const Element& root, double margin) {
    const PolygonView sp = polygonOf(s, source), rp = polygonOf(s, root);
    double in_front = -std::numeric_limits<double>::infinity();
    for (const DVec3& v : rp.vertices) in_front = std::max(in_front, glm::dot(source.normal, v - sp.vertices[0]));
    if (in_front + margin <= 0.0) return false;
    for (const DVec3& v : sp.vertices) {
        const double slack = margin + kRootNormalSlack * (glm::length(v - root.centroid) + root.radius);
        if (glm::dot(root.normal, v - rp.vertices[0]) + slack > 0.0) return true;
    }
    return false;
}

}  // namespace

LinkReconstruction::LinkReconstruction(const Solution& solution, const ReadoutOptions& options, ParallelRunner& runner)
    : s_(solution), o_(options), id_(++g_reconstructions) {
    const Solution& s = s_;
    link_begin_.assign(s.elements.size() + 1, 0);
    for (const Link& link : s.links) ++link_begin_[link.receiver + 1];
    for (size_t i = 0; i < s.elements.size(); ++i) link_begin_[i + 1] += link_begin_[i];
    roots_.reserve(s.root_count);
    for (uint32_t r = 0; r < s.root_count; ++r) roots_.push_back({s.elements[r].mesh, s.elements[r].polygon, r});
    std::sort(roots_.begin(), roots_.end(), [](const RootKey& a, const RootKey& b) {
        return std::tie(a.mesh, a.polygon, a.root) < std::tie(b.mesh, b.polygon, b.root);
    });
    if (s.cluster_links.empty()) return;
    const size_t keys = s.root_count + s.clusters.size();
    cluster_begin_.assign(keys + 1, 0);
    for (const ClusterLink& link : s.cluster_links) ++cluster_begin_[keyOf(s, link.receiver) + 1];
    for (size_t k = 0; k < keys; ++k) cluster_begin_[k + 1] += cluster_begin_[k];
    // Separable links: the source's weighted radiosity towards the receiver's centroid, as
    // the solve's ClusterTransfer computes it.
    separable_flux_.assign(s.cluster_links.size(), DVec3(0.0));
    runner.forEach(s.cluster_links.size(), 64,
                   [&](size_t l) { separable_flux_[l] = separableFlux(s, s.cluster_links[l]); });
}

template <class F>
void LinkReconstruction::forClusterPairs(uint32_t root, F&& f) const {
    const Solution& s = s_;
    if (cluster_begin_.empty()) return;
    const auto visit = [&](uint32_t node) {
        const size_t key = keyOf(s, node);
        for (size_t l = cluster_begin_[key]; l < cluster_begin_[key + 1]; ++l) {
            const ClusterLink& link = s.cluster_links[l];
            if (link.visibility < 0.0f || link.kernel == kNoKernel) continue;
            const NodeMembers rm = membersOf(s, link.receiver), sm = membersOf(s, link.source);
            const uint32_t j = s.member_position[root] - rm.first;
            for (uint32_t i = 0; i < sm.count; ++i) {
                f(s.cluster_members[sm.first + i], pairKernelOf(s, link, i * rm.count + j), link);
            }
        }
    };
    visit(root);
    for (uint32_t c = s.root_leaf_cluster[root]; c != kNoElement; c = s.clusters[c].parent) visit(c | kClusterNode);
}

const LinkReconstruction::RootPairs& LinkReconstruction::pairsOf(uint32_t root) const {
    // A few roots a thread: a vertex reads the faces of several roots around it.
    thread_local std::array<RootPairs, kCachedRoots> cache;
    thread_local size_t next = 0;
    for (const RootPairs& entry : cache)
        if (entry.owner == id_ && entry.root == root) return entry;
    RootPairs& cached = cache[next];
    next = (next + 1) % kCachedRoots;
    cached.owner = id_;
    cached.root = root;
    cached.lit.clear();
    cached.near.clear();
    const Solution& s = s_;
    const Element& r = s.elements[root];
    const double margin = kRootMarginLifts * gather::kLift * s.scene_extent;
    forClusterPairs(root, [&](uint32_t member, double kernel, const ClusterLink& link) {
        const Element& m = s.elements[member];
        if (kernel > 0.0 || canFace(s, m, r, margin))
            cached.lit.push_back({member, static_cast<uint32_t>(&link - s.cluster_links.data()), kernel});
        if (glm::length(m.centroid - r.centroid) <= m.radius + r.radius + margin) cached.near.push_back(member);
    });
    return cached;
}

// Gathers what needs no rays into g.sum (or `separable`), and lists in `pending` what does.
void LinkReconstruction::gatherLinks(uint32_t leaf, gather::Gatherer& g, std::vector<PendingSource>& pending,
                                     DVec3& separable) const {
    const Solution& s = s_;
    // A source whose visibility from the point is not known: its unoccluded light f B is
    // what decides whether rays are worth casting. Without them it brings f V B, V its link's
    // visibility; a cluster pair's V is 1 (it carries light only where its one ray was open,
    // and its kernel, that ray times the form factor averaged over the receiver, is read at
    // the point as the point's own form factor).
    // Deferred sources are listed first, then their form factors taken together (listDeferred).
    thread_local std::vector<std::pair<uint32_t, double>> deferred;  // source, its link's visibility
    deferred.clear();
    const auto defer = [&](uint32_t source_index, double visibility) {
        if (maxChannel(s.elements[source_index].radiosity) > 0.0) deferred.emplace_back(source_index, visibility);
    };
    for (uint32_t a = leaf; a != kNoElement; a = s.elements[a].parent)
        for (size_t l = link_begin_[a]; l < link_begin_[a + 1]; ++l) {
            const Link& link = s.links[l];
            // Occluded by its shaft: nothing. Every one of its few rays blocked is not proof:
            // a penumbra narrower than the receiver passes between them (the ground beside
            // a beam in scenes/paper/shadow.wrl read black where the lamp's edge shows).
            if (!(link.visibility > 0.0f) && !link.by_rays) continue;
            if (!s.rays || (link.visibility >= 1.0f && !link.by_rays)) {
                g.use_rays = false;
                g.visit(link.source);
            } else {
                defer(link.source, link.visibility);
            }
        }
    if (cluster_begin_.empty()) return listDeferred(deferred, g, pending);
    const uint32_t root = s.elements[leaf].root;
    const auto visit = [&](uint32_t node) {
        const size_t key = keyOf(s, node);
        for (size_t l = cluster_begin_[key]; l < cluster_begin_[key + 1]; ++l) {
            const ClusterLink& link = s.cluster_links[l];
            if (!(link.visibility > 0.0f) || link.kernel != kNoKernel) continue;
            // Separable (far, wholly visible): a source of few members read member by member
            // at the point, without rays; a larger one by the solve's product form, its
            // receiver cosine taken at the point.
            const NodeMembers sm = membersOf(s, link.source);
            if (sm.count <= kExactSeparableMembers) {
                g.use_rays = false;
                for (uint32_t i = 0; i < sm.count; ++i) g.visit(s.cluster_members[sm.first + i]);
                continue;
            }
            const DVec3 c_s = centroidOf(s, link.source), c_r = centroidOf(s, link.receiver);
            const DVec3 u = c_s - g.point;
            const double d2 = glm::dot(u, u), cos_d = glm::dot(g.normal, u);
            if (cos_d > 0.0 && d2 > 0.0) {
                const DVec3 w = c_s - c_r;
                separable += cos_d / std::sqrt(d2) * (glm::dot(w, w) / d2) * separable_flux_[l];
            }
        }
    };
    visit(root);
    for (uint32_t c = s.root_leaf_cluster[root]; c != kNoElement; c = s.clusters[c].parent) visit(c | kClusterNode);
    // Whether a source polygon can light the point at all (kernel 0 also marks the pairs
    // that face away: most of them, and a form factor each is the cost of the read-out).
    const auto inFront = [&](const Element& source) {
        const PolygonView poly = polygonOf(s, source);
        if (!(glm::dot(source.normal, g.point - poly.vertices[0]) > 0.0)) return false;
        for (const DVec3& v : poly.vertices)
            if (glm::dot(g.normal, v - g.point) > 0.0) return true;
        return false;
    };
    // Pairwise (near): each member pair read like an element link from the source member:
    // no rays when the link's shaft proved it visible (it then keeps no candidate list);
    // else deferred with its one ray's answer (open: as wholly visible, blocked: dark), so
    // that rays at the point decide where it matters. A pair whose ray was blocked is not
    // proof either: a ceiling tile whose ray met the lamp hanging under it still sees the
    // floor past the lamp's edge (dropping them read the tessellated Cornell box's output
    // vertices at 4.2 % RMS, 2.6 % with them, against 2.8 % without clustering).
    for (const RootPair& pair : pairsOf(root).lit) {
        const double kernel = pair.kernel;
        if (!s.rays || s.cluster_links[pair.link].candidates == kNoList) {
            if (!(kernel > 0.0)) continue;  // faces away
            g.use_rays = false;
            g.visit(pair.member);
        } else {
            if (!(kernel > 0.0) && !inFront(s.elements[pair.member])) continue;
            defer(pair.member, kernel > 0.0 ? 1.0 : 0.0);
        }
    }
    listDeferred(deferred, g, pending);
}

// The deferred sources into `pending`, in order, with their unoccluded light at the point: the
// far-field kernel where it holds, else the exact form factor (two sources at a time).
void LinkReconstruction::listDeferred(std::span<const std::pair<uint32_t, double>> deferred, gather::Gatherer& g,
                                      std::vector<PendingSource>& pending) const {
    const Solution& s = s_;
    thread_local std::vector<double> f;
    thread_local std::vector<PolygonView> exact_polygons;
    thread_local std::vector<double> exact_f;
    f.resize(deferred.size());
    exact_polygons.clear();
    for (size_t k = 0; k < deferred.size(); ++k) {
        const Element& source = s.elements[deferred[k].first];
        const PolygonView poly = polygonOf(s, source);
        f[k] = gather::farFormFactor(g.point, g.normal, source, poly.vertices);
        if (f[k] < 0.0) exact_polygons.push_back(poly);
    }
    exact_f.resize(exact_polygons.size());
    pointPolygonFormFactorsTo(g.point, g.normal, exact_polygons, exact_f.data());
    if (g.counters) g.counters->form_factors += exact_polygons.size();
    size_t next = 0;
    for (size_t k = 0; k < deferred.size(); ++k) {
        const auto [source_index, visibility] = deferred[k];
        const Element& source = s.elements[source_index];
        double exact = -1.0;
        if (f[k] < 0.0) f[k] = exact = exact_f[next++];
        if (!(f[k] > 0.0)) continue;
        pending.push_back({source_index, exact, f[k] * maxChannel(source.radiosity),
                           f[k] * visibility * source.radiosity, visibility > 0.0 && visibility < 1.0});
    }
}

uint32_t LinkReconstruction::leafAt(uint32_t mesh, uint32_t triangle, const DVec3& p_world) const {
    const Solution& s = s_;
    if (!s.scene || mesh >= s.scene->meshes.size()) return kNoElement;
    const Mesh& m = s.scene->meshes[mesh];
    if (triangle >= m.triangles.size()) return kNoElement;
    const uint32_t polygon = m.triangle_polygon.empty() ? triangle : m.triangle_polygon[triangle];
    const auto [lo, hi] = std::equal_range(roots_.begin(), roots_.end(), RootKey{mesh, polygon, 0},
                                           [](const RootKey& a, const RootKey& b) {
                                               return std::tie(a.mesh, a.polygon) < std::tie(b.mesh, b.polygon);
                                           });
    if (lo == hi) return kNoElement;
    std::vector<uint32_t> candidates;
    for (auto it = lo; it != hi; ++it) candidates.push_back(it->root);
    return leafBelow(nearest(s, candidates, p_world), p_world);
}

uint32_t LinkReconstruction::leafBelow(uint32_t e, const DVec3& p_world) const {
    const Solution& s = s_;
    while (!s.elements[e].isLeaf()) {
        const Element& element = s.elements[e];
        std::array<uint32_t, 8> children{};
        const uint32_t count = std::min<uint32_t>(element.child_count, 8);
        for (uint32_t c = 0; c < count; ++c) children[c] = element.first_child + c;
        e = nearest(s, std::span<const uint32_t>(children.data(), count), p_world);
    }
    return e;
}

uint32_t LinkReconstruction::readingLeaf(uint32_t mesh, uint32_t triangle, const DVec3& p_world,
                                         const DVec3& normal) const {
    const uint32_t leaf = leafAt(mesh, triangle, p_world);
    // Only a point on its element's front side reads that element's links (a black receiver
    // has links too: oracleReflectance in refine.h).
    if (leaf == kNoElement || !(glm::dot(s_.elements[leaf].normal, normal) > 0.5)) return kNoElement;
    return leaf;
}

void LinkReconstruction::tally(const ProbeCounters& c, size_t points) const {
    points_.fetch_add(points, std::memory_order_relaxed);
    rays_.fetch_add(c.rays, std::memory_order_relaxed);
    form_factors_.fetch_add(c.form_factors, std::memory_order_relaxed);
    pieces_.fetch_add(c.pieces, std::memory_order_relaxed);
}

LinkReconstruction::Work LinkReconstruction::work() const {
    return {.points = points_.load(),
            .counts = {.rays = rays_.load(), .form_factors = form_factors_.load(), .pieces = pieces_.load()}};
}

DVec3 LinkReconstruction::evaluate(uint32_t mesh, uint32_t triangle, const DVec3& p_world, const DVec3& normal,
                                   ProbeCounters* counters, bool edges) const {
    const Solution& s = s_;
    ProbeCounters c;
    const uint32_t leaf = readingLeaf(mesh, triangle, p_world, normal);
    DVec3 h(0.0);
    if (leaf == kNoElement) h = surfaceIrradiance(s, o_, p_world, normal, mesh, triangle, &c);
    else
        h = evaluateLeaf(leaf, p_world, normal, &c, edges) +
            gather::punctualInside(s, mesh, triangle, p_world, normal, nullptr) + skyInElement(s, leaf, p_world);
    tally(c, 1);
    if (counters) {
        counters->rays += c.rays;
        counters->form_factors += c.form_factors;
        counters->pieces += c.pieces;
    }
    return h;
}

DVec3 LinkReconstruction::irradianceExhaustive(uint32_t mesh, uint32_t triangle, const DVec3& p_world,
                                               const DVec3& normal) const {
    ProbeCounters c;
    // The sky as every other vertex takes it, from the corners of a leaf of its face at the point
    // (the solve read it there from inside the face), not by a quadrature of its own.
    const bool sky = s_.scene && s_.scene->sky.shines();
    const uint32_t leaf = sky ? readingLeaf(mesh, triangle, p_world, normal) : kNoElement;
    DVec3 h(0.0);
    if (leaf != kNoElement) {
        ReadoutOptions without_sky = o_;
        without_sky.sky.grid = 0;
        h = surfaceIrradiance(s_, without_sky, p_world, normal, mesh, triangle, &c) + skyInElement(s_, leaf, p_world);
    } else {
        h = surfaceIrradiance(s_, o_, p_world, normal, mesh, triangle, &c);
    }
    tally(c, 1);
    return h;
}

DVec3 LinkReconstruction::irradianceUncorrected(uint32_t mesh, uint32_t triangle, const DVec3& p_world,
                                                const DVec3& normal) const {
    return evaluate(mesh, triangle, p_world, normal, nullptr, false);
}

DVec3 LinkReconstruction::EdgeTerms::correction(std::span<const SideLight> beside) const {
    DVec3 sum(0.0);
    for (const Face& f : faces) {
        const SideLight* known = sideLightOf(beside, f.normal);
        sum += f.weighted_mean - f.weight * (f.emission + f.reflectance * (known ? known->h : f.h_read));
    }
    return sum;
}

LinkReconstruction::EdgeTerms LinkReconstruction::edgeTermsAt(uint32_t mesh, uint32_t triangle, const DVec3& p_world,
                                                              const DVec3& normal, const DVec3& h,
                                                              std::span<const SideLight> beside,
                                                              const DVec3& interior) const {
    if (o_.edge_correction == EdgeCorrection::Off) return {};
    // Shared: only faces beside that `beside` gives, so none unless it holds another plane.
    if (o_.edge_correction == EdgeCorrection::Shared &&
        std::none_of(beside.begin(), beside.end(), [&](const SideLight& l) {
            return glm::length(glm::cross(l.normal, normal)) > 1e-6;
        }))
        return {};
    const uint32_t leaf = readingLeaf(mesh, triangle, p_world, normal);
    if (leaf == kNoElement) return {};
    const Touched touched = touchedRoots(leaf, p_world);
    if (touched.count < 2) return {};
    ProbeCounters c;
    EdgeTerms terms = edgeTerms(leaf, p_world, p_world + gather::kLift * s_.scene_extent * touched.direction, normal,
                                h, std::span<const uint32_t>(touched.roots.data(), touched.count), beside,
                                o_.edge_correction == EdgeCorrection::Shared, interior, &c);
    tally(c, 0);
    return terms;
}

LinkReconstruction::Touched LinkReconstruction::touchedRoots(uint32_t leaf, const DVec3& p_world) const {
    const Solution& s = s_;
    const uint32_t root = s.elements[leaf].root;
    const double lift = gather::kLift * s.scene_extent;
    Touched t;
    const auto touch = [&](uint32_t r) {
        for (size_t k = 0; k < t.count; ++k)
            if (t.roots[k] == r) return;
        if (t.count < t.roots.size()) t.roots[t.count++] = r;
        gather::addLiftDirection(s, r, p_world, lift, t.direction);
    };
    touch(root);
    for (uint32_t a = leaf; a != kNoElement; a = s.elements[a].parent)
        for (size_t l = link_begin_[a]; l < link_begin_[a + 1]; ++l) {
            const Element& source = s.elements[s.links[l].source];
            // A source polygon can touch the point only if it comes within lift of it.
            if (glm::length(source.centroid - p_world) <= source.radius + lift) touch(source.root);
        }
    // And the members of pairwise cluster links (a neighbouring tile of a tessellated wall).
    for (const uint32_t member : pairsOf(root).near) {
        const Element& source = s.elements[member];
        if (glm::length(source.centroid - p_world) <= source.radius + lift) touch(member);
    }
    return t;
}

LinkReconstruction::EdgeTerms LinkReconstruction::edgeTerms(uint32_t leaf, const DVec3& p_world, const DVec3& lifted,
                                                            const DVec3& normal, const DVec3& h,
                                                            std::span<const uint32_t> touched,
                                                            std::span<const SideLight> side_light, bool beside_only,
                                                            const DVec3& interior, ProbeCounters* counters) const {
    const Solution& s = s_;
    const double lift = gather::kLift * s.scene_extent;
    const Element& own = s.elements[leaf];
    std::vector<std::pair<uint32_t, size_t>> faces;  // touched concave neighbour root, its leaves' count
    std::vector<std::pair<double, DVec3>> weights;   // per touching leaf: weight, B_mean
    double potential = 0.0;
    for (const uint32_t r : touched) {
        if (r == own.root) continue;
        const Element& other = s.elements[r];
        // Concave (each in front of the other), not coplanar, and touching the point. In front
        // by any vertex, not the centroid: a floor piece cut around a block's corner lies on
        // both sides of the block face's plane, and the part in front is what the point sees
        // (the tessellated Cornell box's tall block read -16 % at such a corner).
        const PolygonView other_polygon = polygonOf(s, other);
        const bool other_in_front = std::any_of(other_polygon.vertices.begin(), other_polygon.vertices.end(),
                                                [&](const DVec3& v) { return glm::dot(normal, v - p_world) > lift; });
        if (!other_in_front || !(glm::dot(other.normal, own.centroid - p_world) > 0.0)) continue;
        const DVec3 axis = glm::cross(normal, other.normal);
        if (!(glm::length(axis) > 1e-6)) continue;
        if (!(std::abs(glm::dot(other.normal, p_world - other_polygon.vertices[0])) < lift) ||
            !(pointPolygonDistance(p_world, other_polygon) < lift))
            continue;
        if (beside_only && !sideLightOf(side_light, other.normal)) continue;
        const DVec3 line = glm::normalize(axis);
        // The form factors from where the gather reads them: off every plane the point touches
        // (from off these two only, a room's corner saw a quarter of the hemisphere in each
        // face beside, where the gather sees 3/8: the corner's correction was 2/3 of its due).
        const DVec3& origin = lifted;
        // Every leaf of that face the point touches (on the border between two, both): one
        // chosen would make the correction jump with the rounding of the point.
        const size_t before = weights.size();
        std::vector<uint32_t> stack{r};
        while (!stack.empty()) {
            const uint32_t k = stack.back();
            stack.pop_back();
            const Element& e = s.elements[k];
            if (!(pointPolygonDistance(p_world, polygonOf(s, e)) < lift)) continue;
            if (!e.isLeaf()) {
                for (uint32_t c = e.child_count; c-- > 0;) stack.push_back(e.first_child + c);
                continue;
            }
            const PolygonView poly = polygonOf(s, e);
            std::vector<std::vector<DVec3>> pieces{std::vector<DVec3>(poly.vertices.begin(), poly.vertices.end())};
            for (int level = 0; level < kEdgeCorrectionSplits; ++level) {
                std::vector<std::vector<DVec3>> next;
                for (const auto& piece : pieces)
                    for (auto& child : splitPolygon(piece)) next.push_back(std::move(child));
                pieces = std::move(next);
            }
            // The form factor of a piece beside the point is concentrated within a few lifts of
            // it, where the model's radiosity is B_line, not its value at the piece's centroid:
            // pieces near the point are split on (about 3 more a level) until they are small
            // against their distance or a few lifts across.
            for (size_t i = 0, splits = 0; i < pieces.size() && splits < kEdgeNearSplits;) {
                const DVec3 c = polygonCentroid(pieces[i]);
                double radius = 0.0;
                for (const DVec3& q : pieces[i]) radius = std::max(radius, glm::length(q - c));
                if (radius > 4.0 * lift && glm::length(c - p_world) < 2.0 * radius) {
                    std::vector<std::vector<DVec3>> children = splitPolygon(pieces[i]);
                    pieces[i] = std::move(children.front());
                    for (size_t k = 1; k < children.size(); ++k) pieces.push_back(std::move(children[k]));
                    ++splits;
                } else {
                    ++i;
                }
            }
            double area = 0.0, area_h = 0.0, weight = 0.0;
            std::vector<double> height(pieces.size()), f(pieces.size());
            for (size_t i = 0; i < pieces.size(); ++i) {
                Element piece;
                setElementGeometry(piece, pieces[i]);
                const DVec3 v = piece.centroid - p_world;
                height[i] = glm::length(v - glm::dot(v, line) * line);
                area += piece.area;
                area_h += piece.area * height[i];
                f[i] = pointPolygonFormFactor(origin, normal, pieces[i], e.normal);
                if (counters) ++counters->form_factors;
            }
            if (!(area_h > 0.0)) continue;
            for (size_t i = 0; i < pieces.size(); ++i) weight += f[i] * (height[i] * area / area_h - 1.0);
            weights.push_back({weight, e.radiosity});
            potential += std::abs(weight) * maxChannel(e.radiosity);
        }
        if (weights.size() > before) faces.push_back({r, weights.size() - before});
    }
    // What each face gets at this very point (uncorrected) is a second reconstruction there:
    // only where the correction could move the point's light by kEdgeCorrectionShare
    // (B_line lies between 0 and about B_mean).
    EdgeTerms terms;
    if (!(potential > kEdgeCorrectionShare * maxChannel(h))) return terms;
    size_t w = 0;
    for (const auto& [r, count] : faces) {
        const uint32_t beside = leafBelow(r, p_world);
        const Element& b = s.elements[beside];
        EdgeTerms::Face face{.normal = b.normal, .weighted_mean = DVec3(0.0), .emission = b.emission,
                             .reflectance = b.reflectance, .h_read = DVec3(0.0), .leaf = beside};
        if (!sideLightOf(side_light, b.normal)) {
            // Read where the point's own value is the limit from: a few lifts into its face
            // along `interior` and off its plane, on the face beside (the floor before a block's
            // foot). At the end of the edge the two faces share (a block's corner) the face
            // beside's light turns with the direction around the point, so it is read in sectors
            // (sectorRead); once per plane.
            const DVec3 line = glm::normalize(glm::cross(normal, b.normal));  // the edge they share
            if (const auto same = std::find_if(terms.faces.begin(), terms.faces.end(),
                                               [&](const EdgeTerms::Face& o) {
                                                   return glm::dot(o.normal, b.normal) > 1.0 - kSameNormal;
                                               });
                same != terms.faces.end()) {
                face.h_read = same->h_read;
            } else if (glm::length(interior) > 0.0 && std::abs(glm::dot(interior, line)) > kCornerAlongLine) {
                std::vector<uint32_t> plane_roots;
                for (const auto& [o, n] : faces)
                    if (glm::dot(s.elements[o].normal, b.normal) > 1.0 - kSameNormal) plane_roots.push_back(o);
                face.h_read = sectorRead(p_world, normal, b.normal, interior, plane_roots, counters);
            } else if (glm::length(interior) > 0.0) {
                const DVec3 into = 10.0 * lift * (interior + normal);
                const DVec3 q = p_world + into - glm::dot(into, b.normal) * b.normal;
                face.h_read = evaluateLeaf(leafBelow(r, q), q, b.normal, counters, false);
            } else {
                face.h_read = evaluateLeaf(beside, p_world, b.normal, counters, false);
            }
        }
        for (size_t k = 0; k < count; ++k, ++w) {
            face.weight += weights[w].first;
            face.weighted_mean += weights[w].first * weights[w].second;
        }
        terms.faces.push_back(face);
    }
    return terms;
}

DVec3 LinkReconstruction::sectorRead(const DVec3& p_world, const DVec3& normal, const DVec3& beside_normal,
                                     const DVec3& interior, std::span<const uint32_t> plane_roots,
                                     ProbeCounters* counters) const {
    const Solution& s = s_;
    const double lift = gather::kLift * s.scene_extent;
    // The half-plane of the face beside in front of the point's face, from `line` (the edge
    // they share) round to -line, in sectors. Each sector's weight: the form factor of its
    // wedge (apex at the point, far reaching) from the point a little way in along `interior`,
    // where the vertex's value is the limit from; its light: read a few lifts out along its
    // middle, through the leaf there.
    const DVec3 line = glm::normalize(glm::cross(normal, beside_normal));
    const DVec3 out = glm::normalize(normal - glm::dot(normal, beside_normal) * beside_normal);
    const DVec3 from = p_world + 10.0 * lift * interior;
    const double reach = 1e4 * lift;
    const auto direction = [&](double a) { return std::cos(a) * line + std::sin(a) * out; };
    struct Sector {
        double weight;
        DVec3 h;
        double middle;  // the angle its light was read at
    };
    // `known`: sectors read already; one whose middle a new sector shares is not read again
    // (the halves' middles are the 2nd and 5th of six sectors').
    const auto read = [&](int count, const std::vector<Sector>& known) {
        std::vector<Sector> sectors;
        for (int k = 0; k < count; ++k) {
            const double a0 = kPi * k / count, a1 = kPi * (k + 1) / count, middle = 0.5 * (a0 + a1);
            const std::array<DVec3, 3> wedge{p_world, p_world + reach * direction(a1), p_world + reach * direction(a0)};
            const double w = pointPolygonFormFactor(from, normal, wedge, beside_normal);
            if (counters) ++counters->form_factors;
            if (!(w > 0.0)) continue;
            const auto same = std::find_if(known.begin(), known.end(),
                                           [&](const Sector& o) { return std::abs(o.middle - middle) < 1e-12; });
            if (same != known.end()) {
                sectors.push_back({w, same->h, middle});
                continue;
            }
            const DVec3 q = p_world + 10.0 * lift * direction(middle);
            const auto holder = std::find_if(plane_roots.begin(), plane_roots.end(), [&](uint32_t r) {
                return pointPolygonDistance(q, polygonOf(s, s.elements[r])) < 1e-3 * lift;
            });
            if (holder == plane_roots.end()) continue;  // not this face there (another object's foot)
            sectors.push_back({w, evaluateLeaf(leafBelow(*holder, q), q, beside_normal, counters, false), middle});
        }
        return sectors;
    };
    const auto mean = [](const std::vector<Sector>& sectors) {
        DVec3 sum(0.0);
        double weight = 0.0;
        for (const Sector& sector : sectors) sum += sector.weight * sector.h, weight += sector.weight;
        return sum / weight;
    };
    // Two halves first; where they disagree (a shadow wedge), kCornerSectors sectors.
    std::vector<Sector> sectors = read(2, {});
    bool agree = sectors.size() == 2;
    for (int c = 0; agree && c < 3; ++c)
        agree = std::abs(sectors[0].h[c] - sectors[1].h[c]) <=
                kCornerAgreement * std::max(sectors[0].h[c], sectors[1].h[c]);
    if (!agree) sectors = read(kCornerSectors, sectors);
    if (!sectors.empty()) return mean(sectors);
    return evaluateLeaf(leafBelow(plane_roots.front(), p_world), p_world, beside_normal, counters, false);
}

DVec3 LinkReconstruction::evaluateLeaf(uint32_t leaf, const DVec3& p_world, const DVec3& normal,
                                       ProbeCounters* counters, bool edges) const {
    const Solution& s = s_;
    const double lift = gather::kLift * s.scene_extent;
    // The lift off the polygons the point touches (gather.h), among those that can light it:
    // its own root and the roots of its links' sources.
    const Touched touched = touchedRoots(leaf, p_world);
    const DVec3 point = p_world + lift * touched.direction;
    gather::Gatherer g{.s = s,
                       .o = o_,
                       .point = point,
                       .normal = normal,
                       .origin = point + lift * normal,
                       .lift = lift,
                       .counters = counters,
                       .coarse_rule = false,
                       .link_visibility_ratio = kLinkVisibilityRatio,
                       .max_visibility_splits = kLinkVisibilitySplits};
    // Reused by the thread's reads (the edge correction's nested reads come after their last use).
    thread_local std::vector<PendingSource> pending;
    pending.clear();
    DVec3 separable(0.0);
    gatherLinks(leaf, g, pending, separable);
    // Rays only where they can matter: sources by decreasing unoccluded light get their
    // visibility from rays at the point until what is left could bring at most kRayShare of
    // the light known so far (what needed no rays and what rays found); those keep the
    // solver's visibility (over the receiver). The bound is on their sum: under a block on
    // a floor, many small partly visible links each below the share add up to a leak. And
    // it is against light found, not the fallbacks' estimate: at a point in shadow the
    // fallbacks are the error (the ceiling above the tessellated Cornell box's lamp, its
    // pairs' rays open from tile to tile, read +73 % with the estimate, +42 % with this,
    // for 1 % more rays on house.wrl's vertices and the paper scenes' texels).
    DVec3 estimate = g.sum + separable;
    double pending_light = 0.0;
    for (const PendingSource& p : pending) {
        estimate += p.fallback;
        pending_light += p.light;
    }
    const double total = maxChannel(estimate);
    // Sources by decreasing unoccluded light (ties by index) from a heap, while rays are worth
    // casting; once they are not, they never are again (what is pending only falls, what is
    // found only grows), and every source left keeps its fallback, summed in index order.
    thread_local std::vector<gather::Ranked> heap;
    heap.resize(pending.size());
    for (uint32_t k = 0; k < heap.size(); ++k) heap[k] = {pending[k].light, k};
    std::make_heap(heap.begin(), heap.end(), gather::dimmer);
    thread_local std::vector<char> read;
    read.assign(pending.size(), 0);
    for (auto end = heap.end(); end != heap.begin() && pending_light > kRayShare * maxChannel(g.sum + separable);) {
        std::pop_heap(heap.begin(), end, gather::dimmer);
        const uint32_t k = (--end)->k;
        read[k] = 1;
        const PendingSource& p = pending[k];
        g.use_rays = true;
        g.coarse_opening = o_.probe_coarse_opening && p.partial && p.light > kCoarseShare * total;
        g.known_form_factor = p.form_factor;  // -1 (computed by the visit) for a far-field estimate
        // A lamp behind a link whose rays disagreed: its penumbra is the sharpest light
        // there is. (Behind every link not proven visible, house.wrl's vertices cast 1,176
        // rays each instead of 357, for shadow.wrl's texels at 1.3 % instead of 2.0 %.)
        g.coarse_rule_on_emitters = p.partial;
        // A source whose link found it blocked (a cluster pair's one ray, an element link's
        // every ray) is first tried with one ray to its centroid: open, it is gathered with
        // rays; blocked, it stays dark. Most of them are blocked, and gathering each with
        // its own rays cost house.wrl's vertices 1.5 x (69.5 us instead of 46); the
        // tessellated Cornell box's vertices keep 2.40 % RMS (p95 3.08 -> 3.35 %, bias
        // +0.01 -> -0.18 %: a piece whose centre is hidden while some of it shows). Where the
        // centre is hidden, its corners pulled a quarter of the way in are tried too
        // (session 9: the box 1.76 -> 1.67 % RMS, p95 2.63 -> 2.17 %, bias -0.45 -> -0.26 %,
        // as without the pre-test; house.wrl's vertices about 1.15 x, a busy machine).
        if (!(maxChannel(p.fallback) > 0.0)) {
            const Element& e = s.elements[p.source];
            const auto blocked = [&](const DVec3& at) {
                if (g.counters) ++g.counters->rays;
                return s.rays->segmentBlocked(g.origin, at + g.lift * e.normal);
            };
            bool hidden = blocked(e.centroid);
            if (hidden) {
                // The corners together, as packets: most such sources are hidden from all of them.
                const PolygonView poly = polygonOf(s, e);
                thread_local std::vector<DVec3> corners;
                corners.clear();
                for (const DVec3& v : poly.vertices) corners.push_back(v + 0.25 * (e.centroid - v) + g.lift * e.normal);
                if (g.counters) g.counters->rays += corners.size();
                hidden = s.rays->countOpenFrom(g.origin, corners) == 0;
            }
            if (hidden) {
                pending_light -= p.light;
                continue;
            }
        }
        g.visit(p.source);
        g.coarse_opening = false;
        pending_light -= p.light;
    }
    for (size_t k = 0; k < pending.size(); ++k)
        if (!read[k]) g.sum += pending[k].fallback;
    const DVec3 h = g.sum + separable;
    if (!edges || touched.count < 2) return h;
    // The point's face and the faces beside it corrected together, as the vertex bake corrects
    // the faces that have vertices at a point: each face beside's own terms at this point, among
    // the faces already read (no further reads). One step from their uncorrected light read a
    // tiled room's corners in the lightmap +6.3 % (test_edges_contacts).
    std::vector<EdgeTerms> terms{edgeTerms(leaf, p_world, point, normal, h,
                                           std::span<const uint32_t>(touched.roots.data(), touched.count), {}, false,
                                           DVec3(0.0), counters)};
    if (terms[0].faces.empty()) return h;
    std::vector<SideLight> sides{{normal, h}};
    std::vector<DVec3> uncorrected{h};
    for (const EdgeTerms::Face& f : terms[0].faces) {
        sides.push_back({f.normal, f.h_read});
        uncorrected.push_back(f.h_read);
    }
    for (size_t j = 0; j < terms[0].faces.size(); ++j) {
        const EdgeTerms::Face& f = terms[0].faces[j];
        const Touched t = touchedRoots(f.leaf, p_world);
        // Each face's own touched planes and terms; only the faces in `sides` (beside_only).
        terms.push_back(t.count < 2 ? EdgeTerms{}
                                    : edgeTerms(f.leaf, p_world, p_world + lift * t.direction, f.normal, f.h_read,
                                                std::span<const uint32_t>(t.roots.data(), t.count), sides, true,
                                                DVec3(0.0), counters));
    }
    correctTogether(sides, uncorrected, terms);
    return sides[0].h;
}

void LinkReconstruction::correctTogether(std::span<SideLight> sides, std::span<const DVec3> uncorrected,
                                         std::span<const EdgeTerms> terms) {
    constexpr int kSteps = 12;  // under 1e-3 of the first step's change left at a room's corner
    std::vector<DVec3> next(sides.size());
    for (int step = 0; step < kSteps; ++step) {
        for (size_t g = 0; g < sides.size(); ++g)
            next[g] = glm::max(DVec3(0.0), uncorrected[g] + terms[g].correction(sides));
        for (size_t g = 0; g < sides.size(); ++g) sides[g].h = next[g];
    }
}

namespace {

// Whether a point read as `reading` takes the edge correction under `mode`. Texels at Shared:
// the tessellated Cornell box's lightmap (64 texels/m) looked up at its vertices read its room
// corners +9 % and edges +1.5 % without it, 2.11 % RMS in all; with it 1.64 %, for 7 % more
// lightmap time (only texels on an edge pay).
bool correctsEdges(EdgeCorrection mode, LinkReconstruction::Reading reading) {
    return mode == EdgeCorrection::On ||
           (mode == EdgeCorrection::Shared && reading == LinkReconstruction::Reading::Texel);
}

}  // namespace

DVec3 LinkReconstruction::irradiance(uint32_t mesh, uint32_t triangle, const DVec3& p_world, const DVec3& normal,
                                     Reading reading) const {
    return evaluate(mesh, triangle, p_world, normal, nullptr, correctsEdges(o_.edge_correction, reading));
}

DVec3 LinkReconstruction::irradianceCounted(uint32_t mesh, uint32_t triangle, const DVec3& p_world,
                                            const DVec3& normal, ProbeCounters& counters, Reading reading) const {
    return evaluate(mesh, triangle, p_world, normal, &counters, correctsEdges(o_.edge_correction, reading));
}

}  // namespace radbake
