// Clustering for hierarchical radiosity (issue 11).
//
// The method, and why. Linking every facing pair of roots is O(n^2) in links, shafts and
// memory. Three published ways out:
//   - Sillion 1995 (volume clusters in one hierarchy with the elements, isotropic or
//     extinction-based transfer): light is smeared over a cluster's volume, which leaks
//     through walls unless visibility is resolved inside clusters, and it needs a second
//     kind of element in every stage (the bake stage reads elements only).
//   - Smits, Arvo, Greenberg 1994 (clusters of polygons, links with a bounded error, each
//     member gathering with its own orientation): O(n log n) linking with the power-based
//     oracle we already have; the transfer stays between polygons.
//   - Gibson, Hubbold 1996: the same with orientation-aware bounds (normal cones).
// We take Smits-Arvo-Greenberg with Gibson-Hubbold's orientation kept where it costs
// nothing: clusters are a separate binary tree of boxes above the roots (the element
// quadtrees, refine.cpp, solve.cpp and evaluate.cpp stay as they are), each member emits
// and receives with its own normal, and a cluster link refines down to root-root links,
// which the existing quadtree refinement then takes over unchanged.
//
//   Hierarchy: top-down median split of root centroids along the widest axis (quantised
//     coordinates, ties by index: deterministic, and the same tree for a scaled scene),
//     leaves of at most kClusterLeafSize roots. Balanced, O(n log n). Leaves of 8 measured
//     faster than 4 or 16 on the tessellated Cornell box and CornellBox-Water.
//   Oracle: every point of the receiver node R gets from the source node S at most
//     Phi_S / (pi d_min^2), Phi_S = sum A_i B_i over S's members, d_min a lower bound on the
//     distance between the nodes (the boxes' distance, or a flat end's plane's distance from
//     the other box; a point form factor to polygon i is at most A_i / (pi r^2), r >= d_min);
//     the link may misplace at most rho_R A_R times that, compared with thresholdFor (the
//     element links' threshold, least over R's members; cluster links join light-exchange
//     groups like element links). d_min = 0 (and a node with itself) always splits. Before
//     the first solve Phi uses B + rho H_mean (one ambient bounce of the emitted power) so
//     that reflecting clusters refine in round 1 too.
//   Transfer: orientation-aware at both ends, facing-away members get nothing, never above
//     the oracle's bound. Links of at most kPairwiseLimit member pairs store a kernel per
//     pair: the exact point-to-polygon form factor from the receiver's centroid (2 x 2 points
//     when near), times that pair's own ray (from an emitting member, the open share of four).
//     Larger ones are separable, the product form of A_i cos_i cos_j / (pi d^2) about the two
//     centroids calibrated on sampled pairs, and kept only when every sampled ray between
//     their facing members is open (or every one blocked): a mixed large link is split, so
//     visibility is never averaged over a wall.
//   Visibility: shafts between the nodes' boxes (a root end: its polygon), classified with
//     the inherited candidate list (the root ends' own parts excluded, and for a flat
//     cluster the parts in its plane); the occlusion test (with `--visibility exact`) kills a link,
//     and its whole subtree, before it is refined. Lists longer than kCullOnlyListSize are
//     culled by AABBs only (the test on every part of long lists was 70 % of the time).
//   Energy: each member i sends A_i B_i (its root's area-averaged radiosity, as solve.cpp
//     pulls it up); each receiving root gets a uniform irradiance, shared among its leaves
//     by the links' geometric kernel at each leaf (exact for uniform radiosity, the analogue
//     of solve.cpp's row-sum correction, which keeps the root's power).
#include "radiosity/cluster.h"
#include "radiosity/cluster_nodes.h"
#include "radiosity/refinement_clock.h"

#include "core/memory.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "geometry/parts.h"
#include "radiosity/elements.h"
#include "radiosity/form_factor.h"
#include "visibility/occlusion.h"
#include "visibility/ray_caster.h"

namespace radbake {
namespace {

double boxDistance(const Aabb& a, const Aabb& b) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double gap = std::max({0.0, a.min[k] - b.max[k], b.min[k] - a.max[k]});
        d2 += gap * gap;
    }
    return std::sqrt(d2);
}

Aabb polygonBox(const Solution& s, const Element& e) {
    Aabb box;
    for (uint32_t v = 0; v < e.vertex_count; ++v) box.add(s.vertices[e.first_vertex + v]);
    return box;
}

std::array<DVec3, 8> corners(const Aabb& box) {
    std::array<DVec3, 8> out;
    for (int k = 0; k < 8; ++k)
        out[k] = DVec3(k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y, k & 4 ? box.max.z : box.min.z);
    return out;
}

// True when no point of the box lies in front of the root's plane (nothing there can
// exchange light with the root's front). Tolerance: 1e-9 of the pair's size, as facing().
bool boxBehind(const Solution& s, const Element& root, const Aabb& box) {
    const DVec3& origin = s.vertices[root.first_vertex];
    const double tolerance = 1e-9 * (root.radius + glm::length(box.extent()) + glm::length(box.center() - origin));
    for (const DVec3& p : corners(box))
        if (glm::dot(root.normal, p - origin) > tolerance) return false;
    return true;
}

// The point form factor from the receiver polygon j to polygon i averaged over j: 2 x 2 Gauss
// points on a quad (as solve.cpp's leaf correction), 2 x 2 stratified points otherwise. The
// centroid alone read 0.1 % high on a closed room's row sums, 10 % in its radiosity at
// rho = 0.99.
// `points`: j's 2 x 2 stratified points when the caller has them (ClusterRefiner keeps every
// root's), else they are made here.
double averagedFormFactor(const Solution& s, const Element& j, const PolygonView& source,
                          const DVec3* points = nullptr) {
    const PolygonView poly = polygonOf(s, j);
    const auto& q = poly.vertices;
    if (q.size() != 4) {
        std::vector<DVec3> made;
        if (points == nullptr) {
            made = stratifiedPolygonPoints(q, 2);
            points = made.data();
        }
        std::array<double, 4> f;
        pointPolygonFormFactors(std::span<const DVec3>(points, 4), j.normal, source.vertices, source.normal, f.data());
        double sum = 0.0;
        for (int k = 0; k < 4; ++k) sum += f[k];
        return sum / 4.0;
    }
    return gaussAveragedFormFactor(q, j.normal, source.vertices, source.normal);
}

// The kernel of a member pair: irradiance at root j per unit radiosity of root i, the exact
// point-to-polygon form factor to polygon i averaged over j (a point kernel
// A_i cos_i cos_j / (pi d^2) overestimates near pairs, and in a closed room those errors all
// have one sign). 0 when either faces away.
double pairKernel(const Solution& s, const Element& i, const Element& j, const DVec3* j_points) {
    const DVec3 u = j.centroid - i.centroid;
    if (!(glm::dot(u, u) > 0.0)) return 0.0;
    const PolygonView source = polygonOf(s, i);
    if (!facing(polygonOf(s, j), source)) return 0.0;
    return averagedFormFactor(s, j, source, j_points);
}

// pairKernel's test for a pair that can exchange light (cheap: no form factor).
bool pairFaces(const Solution& s, const Element& i, const Element& j) {
    const DVec3 u = j.centroid - i.centroid;
    return glm::dot(u, u) > 0.0 && facing(polygonOf(s, j), polygonOf(s, i));
}

OcclusionTest occlusionTestFor(LinkVisibility mode) {
    switch (mode) {
        case LinkVisibility::Obb: return OcclusionTest::Obb;
        case LinkVisibility::Exact: return OcclusionTest::Exact;
        default: return OcclusionTest::None;
    }
}

enum class Decision : uint8_t { Drop, Split, Keep };

struct ClusterEvaluation {
    Decision decision = Decision::Drop;
    bool occluded = false;
    bool shaft = false;
    bool new_list = false;              // candidates hold a new list, else `list` is inherited
    bool first_candidate_only = false;  // candidates hold only the first (a kept link's shaft)
    size_t list_parts = 0;              // parts named by the link's inherited list
    uint32_t list = kNoList;
    std::vector<uint32_t> candidates;
    std::vector<float> kernel;          // pairwise links (Solution::cluster_kernel)
    float visibility = 1.0f;
    float scale = 1.0f;
    size_t rays = 0;
};

// An evaluation as it crosses between ranks (ParallelRunner::forEachShared).
void encodeEvaluation(Writer& w, const ClusterEvaluation& ev) {
    w.value(ev.decision), w.value(ev.occluded), w.value(ev.shaft), w.value(ev.new_list);
    w.value(ev.first_candidate_only), w.value(ev.list_parts), w.value(ev.list), w.array(ev.candidates);
    w.array(ev.kernel), w.value(ev.visibility), w.value(ev.scale), w.value(ev.rays);
}
void decodeEvaluation(Reader& r, ClusterEvaluation& ev) {
    r.value(ev.decision), r.value(ev.occluded), r.value(ev.shaft), r.value(ev.new_list);
    r.value(ev.first_candidate_only), r.value(ev.list_parts), r.value(ev.list), r.array(ev.candidates);
    r.array(ev.kernel), r.value(ev.visibility), r.value(ev.scale), r.value(ev.rays);
}

// ClusterLink::visibility of a deferred link (see evaluate).
constexpr float kDeferred = -1.0f;

// A cluster link whose candidate list is longer than this skips OBB culling and the occlusion test.
constexpr size_t kCullOnlyListSize = 64;

// Pairs a separable link's kernel is calibrated on.
constexpr size_t kCalibrationPairs = 16;

// Visibility samples of a member: the 2 x 2 stratified points visibleFraction uses.
constexpr int kMemberSamples = 2;
constexpr int kPointsPerMember = kMemberSamples * kMemberSamples;
static_assert(kMemberSamples == 2, "averagedFormFactor reuses the members' 2 x 2 sample points");
constexpr int kRaysPerPair = 1;
// A pair whose source member emits (its own light or a punctual light's) casts one ray between
// each of their 2 x 2 points and keeps the open share: one ray decided whether a lamp lit a
// member that sees a third of it wholly or not at all.
constexpr int kEmitterRaysPerPair = kPointsPerMember;
constexpr int kRaysPerMember = 3;  // separable links: each member casts this many, to spread partners
// A kept link whose error bound is below kFaintFraction of its threshold is faint: its
// visibility is sampled with kFaintRays rays (spread over its member pairs) instead of rays
// from every member, and applied to every pair when they agree.
constexpr double kFaintFraction = 0.25;
// Cluster links stop refining at this fraction of the element links' threshold.
constexpr double kClusterThresholdScale = 0.25;
// 16 rays missed a dark member often enough to matter: a ceiling piece over the tessellated
// Cornell box's lamp (cut along its outline, contact_cuts.h) read +37 % through a faint link
// whose 16 rays all passed (+7 % with 32). It costs: graz.wrl's solve 1.07 x, the 200k
// building's 1.28 x, the 1M building's 1.6 x (docs/scale.md, "Session 13"): the faint links
// 32 rays find partly blocked are refined.
constexpr size_t kFaintRays = 32;
// Points this close to a plane (fraction of the scene's extent) lie in it: above float
// rounding of coordinates (1e-7), below any gap a lighting result can see.
constexpr double kCoplanarTolerance = 1e-6;

}  // namespace

void buildClusters(Solution& s) {
    s.clusters.clear();
    s.cluster_members.clear();
    s.member_position.clear();
    s.root_leaf_cluster.clear();
    s.cluster_links.clear();
    s.cluster_kernel.clear();
    const uint32_t n = s.root_count;
    if (n == 0) return;
    s.cluster_members.resize(n);
    std::iota(s.cluster_members.begin(), s.cluster_members.end(), 0u);
    s.clusters.reserve(2 * (n / kClusterLeafSize + 1));
    s.clusters.push_back({});
    s.clusters[0].member_count = n;
    // Iterative top-down build; children are allocated in pairs, so they are contiguous and
    // every child follows its parent.
    std::vector<uint32_t> todo{0};
    while (!todo.empty()) {
        const uint32_t index = todo.back();
        todo.pop_back();
        const uint32_t first = s.clusters[index].first_member, count = s.clusters[index].member_count;
        if (count <= kClusterLeafSize) continue;
        Aabb bounds;
        for (uint32_t k = first; k < first + count; ++k) bounds.add(s.elements[s.cluster_members[k]].centroid);
        // Axis and order decided on coordinates quantised relative to the bounds (ties by
        // index), so float rounding of a scaled scene does not reorder the tree.
        const DVec3 extent = bounds.extent();
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (extent[k] > (1.0 + 1e-6) * extent[axis]) axis = k;
        const double low = bounds.min[axis], span = extent[axis] > 0.0 ? extent[axis] : 1.0;
        auto key = [&](uint32_t root) {
            return static_cast<int64_t>(std::floor((s.elements[root].centroid[axis] - low) / span * 1048576.0 + 0.5));
        };
        const uint32_t half = count / 2;
        auto begin = s.cluster_members.begin() + first;
        std::nth_element(begin, begin + half, begin + count, [&](uint32_t a, uint32_t b) {
            const int64_t ka = key(a), kb = key(b);
            return ka < kb || (ka == kb && a < b);
        });
        const uint32_t child = static_cast<uint32_t>(s.clusters.size());
        s.clusters[index].first_child = child;
        Cluster lo, hi;
        lo.parent = hi.parent = index;
        lo.first_member = first;
        lo.member_count = half;
        hi.first_member = first + half;
        hi.member_count = count - half;
        s.clusters.push_back(lo);
        s.clusters.push_back(hi);
        todo.push_back(child + 1);
        todo.push_back(child);
    }
    s.member_position.assign(n, 0);
    s.root_leaf_cluster.assign(n, 0);
    // Boxes, areas and centroids bottom-up (children follow parents).
    for (size_t c = s.clusters.size(); c-- > 0;) {
        Cluster& cluster = s.clusters[c];
        Aabb box;
        DVec3 weighted(0.0);
        double area = 0.0;
        if (cluster.isLeaf()) {
            for (uint32_t k = cluster.first_member; k < cluster.first_member + cluster.member_count; ++k) {
                const uint32_t root = s.cluster_members[k];
                const Element& e = s.elements[root];
                s.member_position[root] = k;
                s.root_leaf_cluster[root] = static_cast<uint32_t>(c);
                box.add(polygonBox(s, e));
                weighted += e.area * e.centroid;
                area += e.area;
            }
        } else {
            for (uint32_t k = 0; k < 2; ++k) {
                const Cluster& child = s.clusters[cluster.first_child + k];
                box.add(child.box);
                weighted += child.area * child.centroid;
                area += child.area;
            }
        }
        cluster.box = box;
        cluster.area = area;
        cluster.centroid = area > 0.0 ? weighted / area : box.center();
    }
}

ClusterRefiner::ClusterRefiner(RefineState& state) : state_(state) {
    const Solution& s = state.solution;
    root_box_.resize(s.root_count);
    for (uint32_t r = 0; r < s.root_count; ++r) root_box_[r] = polygonBox(s, s.elements[r]);
    // Every member's visibility samples, once (they were most of the cost of a kept link).
    root_points_.resize(size_t(s.root_count) * kPointsPerMember);
    for (uint32_t r = 0; r < s.root_count; ++r) {
        const auto p = stratifiedPolygonPoints(polygonOf(s, s.elements[r]).vertices, kMemberSamples);
        for (int q = 0; q < kPointsPerMember; ++q) root_points_[size_t(r) * kPointsPerMember + q] = p[q % p.size()];
    }
    cluster_rho_.assign(s.clusters.size(), 0.0);
    cluster_radius_.assign(s.clusters.size(), 0.0);
    for (size_t c = s.clusters.size(); c-- > 0;) {
        const Cluster& cluster = s.clusters[c];
        double rho = 0.0, radius = 0.0;
        if (cluster.isLeaf()) {
            for (uint32_t k = cluster.first_member; k < cluster.first_member + cluster.member_count; ++k) {
                rho = std::max(rho, oracleReflectance(s.elements[s.cluster_members[k]].reflectance));
                radius = std::max(radius, s.elements[s.cluster_members[k]].radius);
            }
        } else {
            rho = std::max(cluster_rho_[cluster.first_child], cluster_rho_[cluster.first_child + 1]);
            radius = std::max(cluster_radius_[cluster.first_child], cluster_radius_[cluster.first_child + 1]);
        }
        cluster_rho_[c] = rho;
        cluster_radius_[c] = radius;
    }
    // Flat clusters: every member in one plane. A segment from a point of that plane to a
    // point off it leaves the plane at once, so no part lying in the plane can block it: such
    // parts (the members themselves) are dropped from the cluster's shafts, or every shaft of
    // a wall's cluster would be partial and need rays.
    const double tolerance = kCoplanarTolerance * s.scene_extent;
    auto same_plane = [&](const Plane& a, const Plane& b) {
        return std::abs(glm::dot(a.normal, b.normal)) > 1.0 - 1e-9 &&
               std::abs(std::abs(a.offset) - std::abs(b.offset)) <= tolerance &&
               (glm::dot(a.normal, b.normal) > 0.0 ? std::abs(a.offset - b.offset) : std::abs(a.offset + b.offset)) <=
                   tolerance;
    };
    cluster_flat_.assign(s.clusters.size(), 0);
    cluster_plane_.assign(s.clusters.size(), Plane{});
    for (size_t c = s.clusters.size(); c-- > 0;) {
        const Cluster& cluster = s.clusters[c];
        if (cluster.isLeaf()) {
            const Element& first = s.elements[s.cluster_members[cluster.first_member]];
            const Plane plane{first.normal, -glm::dot(first.normal, s.vertices[first.first_vertex])};
            bool flat = true;
            for (uint32_t k = cluster.first_member; k < cluster.first_member + cluster.member_count && flat; ++k) {
                const Element& e = s.elements[s.cluster_members[k]];
                for (uint32_t v = 0; v < e.vertex_count && flat; ++v)
                    flat = std::abs(plane.eval(s.vertices[e.first_vertex + v])) <= tolerance;
            }
            cluster_flat_[c] = flat;
            cluster_plane_[c] = plane;
        } else {
            const uint32_t a = cluster.first_child, b = a + 1;
            cluster_flat_[c] = cluster_flat_[a] && cluster_flat_[b] && same_plane(cluster_plane_[a], cluster_plane_[b]);
            cluster_plane_[c] = cluster_plane_[a];
        }
    }
}

void ClusterRefiner::prepareRound() {
    const Solution& s = state_.solution;
    const uint32_t n = s.root_count;
    node_power_.assign(n + s.clusters.size(), 0.0);
    node_threshold_.assign(n + s.clusters.size(), 0.0);
    for (uint32_t r = 0; r < n; ++r) {
        const Element& e = s.elements[r];
        node_power_[r] = e.area * maxChannel(e.radiosity);
        node_threshold_[r] = kClusterThresholdScale * state_.thresholdFor(r);
    }
    for (size_t c = s.clusters.size(); c-- > 0;) {
        const Cluster& cluster = s.clusters[c];
        double power = 0.0, threshold = std::numeric_limits<double>::max();
        if (cluster.isLeaf()) {
            for (uint32_t k = cluster.first_member; k < cluster.first_member + cluster.member_count; ++k) {
                power += node_power_[s.cluster_members[k]];
                threshold = std::min(threshold, node_threshold_[s.cluster_members[k]]);
            }
        } else {
            for (uint32_t k = 0; k < 2; ++k) {
                power += node_power_[n + cluster.first_child + k];
                threshold = std::min(threshold, node_threshold_[n + cluster.first_child + k]);
            }
        }
        node_power_[n + c] = power;
        node_threshold_[n + c] = threshold;
    }
}

double ClusterRefiner::minDistance(uint32_t a, uint32_t b) const {
    const Solution& s = state_.solution;
    const Aabb& ab = isCluster(a) ? s.clusters[clusterOf(a)].box : root_box_[a];
    const Aabb& bb = isCluster(b) ? s.clusters[clusterOf(b)].box : root_box_[b];
    double d = boxDistance(ab, bb);
    // The gap between a flat node's plane and the other box, when the box is wholly on one side.
    auto plane_gap = [&](uint32_t node, const Aabb& box) {
        Plane plane;
        if (isCluster(node)) {
            if (!cluster_flat_[clusterOf(node)]) return 0.0;
            plane = cluster_plane_[clusterOf(node)];
        } else {
            const Element& e = s.elements[node];
            plane = Plane{e.normal, -glm::dot(e.normal, s.vertices[e.first_vertex])};
        }
        double lo = std::numeric_limits<double>::max(), hi = -lo;
        for (const DVec3& p : corners(box)) {
            lo = std::min(lo, plane.eval(p));
            hi = std::max(hi, plane.eval(p));
        }
        // Rounding of the plane and the corners: far below any gap that matters.
        const double tolerance = kCoplanarTolerance * s.scene_extent;
        return lo > tolerance ? lo - tolerance : hi < -tolerance ? -hi - tolerance : 0.0;
    };
    d = std::max({d, plane_gap(a, bb), plane_gap(b, ab)});
    return d;
}

double ClusterRefiner::irradianceBound(uint32_t receiver, uint32_t source) const {
    const Solution& s = state_.solution;
    const double power = node_power_[keyOf(s, source)];
    if (!(power > 0.0)) return 0.0;
    const double d = minDistance(receiver, source);
    if (!(d > 0.0)) return std::numeric_limits<double>::infinity();
    return power / (kPi * d * d);
}

double ClusterRefiner::bound(uint32_t receiver, uint32_t source) const {
    const Solution& s = state_.solution;
    const double rho = isCluster(receiver) ? cluster_rho_[clusterOf(receiver)]
                                           : oracleReflectance(s.elements[receiver].reflectance);
    const double area = isCluster(receiver) ? s.clusters[clusterOf(receiver)].area : s.elements[receiver].area;
    const double e = irradianceBound(receiver, source);
    if (!(rho > 0.0) || !(area > 0.0)) return 0.0;  // no area: misplaces nothing
    return rho * area * e;
}

std::vector<PendingLink> ClusterRefiner::initial(Progress& progress) {
    prepareRound();
    if (state_.solution.clusters.empty()) return {};
    return refine({{clusterNode(0), clusterNode(0), 0}}, progress);
}

bool ClusterRefiner::hasDeferred() const {
    for (const ClusterLink& link : state_.solution.cluster_links)
        if (link.visibility < 0.0f) return true;
    return false;
}

std::vector<PendingLink> ClusterRefiner::reopen(Progress& progress, bool& changed, bool deferred_only) {
    Solution& s = state_.solution;
    prepareRound();
    std::vector<PendingClusterLink> pending;
    // The kept links and their kernels are compacted in place: copies of both were the peak
    // of a large solve.
    size_t kept = 0;
    std::vector<std::pair<uint32_t, uint32_t>> kernels;  // (old offset, kept link) per pairwise link
    for (size_t l = 0; l < s.cluster_links.size(); ++l) {
        const ClusterLink link = s.cluster_links[l];
        const double error = link.visibility == 0.0f ? 0.0 : bound(link.receiver, link.source);
        // Deferred links whose source now has light are evaluated; others reopen when their
        // bound exceeds the threshold (never those whose rays were all blocked).
        const bool reopen_it = link.visibility < 0.0f ? error > 0.0
                               : !deferred_only && link.visibility > 0.0f &&
                                     error > node_threshold_[keyOf(s, link.receiver)];
        if (reopen_it) {
            pending.push_back({link.receiver, link.source, link.candidates});
            ++s.stats.reopened_links;
            continue;
        }
        if (link.kernel != kNoKernel) kernels.push_back({link.kernel, static_cast<uint32_t>(kept)});
        s.cluster_links[kept++] = link;
    }
    s.cluster_links.resize(kept);
    // Kernels move down in the order they are stored, so no block overwrites one still to move.
    std::sort(kernels.begin(), kernels.end());
    size_t end = 0;
    for (const auto& [offset, l] : kernels) {
        ClusterLink& link = s.cluster_links[l];
        const size_t size = kernelFloats(kernelMask(s, link));
        std::copy(s.cluster_kernel.begin() + offset, s.cluster_kernel.begin() + offset + size,
                  s.cluster_kernel.begin() + end);
        link.kernel = static_cast<uint32_t>(end);
        end += size;
    }
    s.cluster_kernel.resize(end);
    changed = !pending.empty();
    if (pending.empty()) return {};
    return refine(std::move(pending), progress);
}

std::vector<PendingLink> ClusterRefiner::refine(std::vector<PendingClusterLink> pending, Progress& progress) {
    Solution& s = state_.solution;
    const bool rays_mode = state_.options.visibility == LinkVisibility::Rays;
    const OcclusionTest test = occlusionTestFor(state_.options.visibility);
    std::vector<PendingLink> out;

    // Evaluation: pure, in parallel (bound, shaft, kernel and its rays).
    auto evaluate = [&](const PendingClusterLink& link) {
        ClusterEvaluation ev;
        ev.list = link.candidates;
        if (!(node_power_[keyOf(s, link.source)] > 0.0)) {
            // A dark source (no light yet: the first round knows emission only) is deferred,
            // carrying nothing, until a solve lights it, even where the ends touch: a room no
            // light reaches then costs no link, shaft or ray, and a scene without light none.
            ev.decision = Decision::Keep;
            ev.visibility = kDeferred;
            return ev;
        }
        if (link.receiver == link.source) {
            ev.decision = Decision::Split;
            return ev;
        }
        const uint32_t r_node = link.receiver, s_node = link.source;
        const Aabb& rb = isCluster(r_node) ? s.clusters[clusterOf(r_node)].box : root_box_[r_node];
        const Aabb& sb = isCluster(s_node) ? s.clusters[clusterOf(s_node)].box : root_box_[s_node];
        if (!isCluster(r_node) && boxBehind(s, s.elements[r_node], sb)) return ev;  // Drop
        if (!isCluster(s_node) && boxBehind(s, s.elements[s_node], rb)) return ev;
        const double distance = minDistance(r_node, s_node);
        if (!(distance > 0.0)) {
            ev.decision = Decision::Split;
            return ev;
        }
        const double error = bound(r_node, s_node);
        const bool split = error > node_threshold_[keyOf(s, r_node)];
        if (!split && !(error > 0.0)) {
            ev.decision = Decision::Keep;  // a receiver without area or reflectance
            ev.visibility = 0.0f;
            return ev;
        }
        bool visible = link.candidates == kNoList;
        // A link that splits, with a list too long for the occlusion test, would only cull
        // its list for its children: they cull their parent's list as well through the part
        // tree (part_tree.h), at about the same cost, so no shaft is built for it.
        ev.list_parts = visible ? 0 : candidatePartCount(state_.parts, state_.candidate_pool[link.candidates]);
        const bool long_list = ev.list_parts > kCullOnlyListSize;
        if (!rays_mode && !visible && !(split && long_list && !state_.parts.tree.empty())) {
            // Shaft between the ends: a cluster by its box corners, a root by its polygon.
            const std::array<DVec3, 8> rc = corners(rb), sc = corners(sb);
            const std::span<const DVec3> rp = isCluster(r_node)
                                                  ? std::span<const DVec3>(rc)
                                                  : polygonOf(s, s.elements[r_node]).vertices;
            const std::span<const DVec3> sp = isCluster(s_node)
                                                  ? std::span<const DVec3>(sc)
                                                  : polygonOf(s, s.elements[s_node]).vertices;
            std::vector<uint32_t> excluded;
            if (!isCluster(r_node)) excluded = state_.root_excluded[r_node];
            if (!isCluster(s_node)) {
                const auto& more = state_.root_excluded[s_node];
                excluded.insert(excluded.end(), more.begin(), more.end());
            }
            ShaftQuery query;
            query.source = sp;
            query.receiver = rp;
            // A long list is only culled by boxes (AABBs): OBB culling and the occlusion test on
            // every crossing part of long lists cost 70 % of house.wrl's refinement and killed
            // nothing there; the sub-links test their shorter lists, and a link kept with a
            // long list gets rays.
            query.test = long_list ? OcclusionTest::None : test;
            query.polygon_shaft = false;
            query.excluded = excluded;
            // A flat cluster's own plane holds nothing that can block it (ShaftQuery).
            std::array<Plane, 2> planes;
            size_t plane_count = 0;
            for (const uint32_t node : {r_node, s_node})
                if (isCluster(node) && cluster_flat_[clusterOf(node)]) planes[plane_count++] = cluster_plane_[clusterOf(node)];
            query.ignored_planes = std::span<const Plane>(planes.data(), plane_count);
            query.plane_tolerance = kCoplanarTolerance * s.scene_extent;
            // A kept link stores its parent's list, not its own (memory): it needs only
            // whether anything is left in its shaft.
            query.first_candidate_only = !split;
            ev.first_candidate_only = !split;
            ShaftResult result;
            classifyLink(state_.parts, state_.candidate_pool[link.candidates], query, result);
            ev.shaft = true;
            if (result.occluded) {
                ev.occluded = true;
                return ev;  // Drop: every segment between the ends is blocked
            }
            if (result.candidates.empty()) {
                visible = true;
                ev.list = kNoList;
            } else {
                ev.new_list = true;
                ev.candidates = std::move(result.candidates);
            }
        }
        if (split) {
            ev.decision = Decision::Split;
            return ev;
        }
        ev.decision = Decision::Keep;
        const bool faint = error <= kFaintFraction * node_threshold_[keyOf(s, r_node)];
        const NodeMembers rm = membersOf(s, r_node), sm = membersOf(s, s_node);
        auto src_point = [&](uint32_t i, int q) {
            return root_points_[size_t(s.cluster_members[sm.first + i]) * kPointsPerMember + q % kPointsPerMember];
        };
        auto rcv_point = [&](uint32_t j, int q) -> const DVec3& {
            return root_points_[size_t(s.cluster_members[rm.first + j]) * kPointsPerMember + q % kPointsPerMember];
        };
        if (size_t(rm.count) * sm.count <= kPairwiseLimit) {
            // Pairs that face: rays first, then the kernel of the pairs found open only (the
            // kernels of blocked pairs were a third of a building's solve).
            ev.kernel.assign(size_t(sm.count) * rm.count, 0.0f);
            std::array<uint32_t, kPairwiseLimit> lit;  // pairs that face: i * rm.count + j
            size_t lit_count = 0;
            for (uint32_t i = 0; i < sm.count; ++i) {
                const Element& ei = s.elements[s.cluster_members[sm.first + i]];
                for (uint32_t j = 0; j < rm.count; ++j)
                    if (pairFaces(s, ei, s.elements[s.cluster_members[rm.first + j]])) lit[lit_count++] = i * rm.count + j;
            }
            std::array<float, kPairwiseLimit> open_pair;  // per lit pair: the share of its rays open
            open_pair.fill(1.0f);
            // Each pair's own rays (kRaysPerPair, kEmitterRaysPerPair from an emitter), or for a
            // faint link first kFaintRays of them, spread: when they agree, every pair takes their answer.
            const auto rays_of = [&](uint32_t pair) {
                const Element& source = s.elements[s.cluster_members[sm.first + pair / rm.count]];
                return maxChannel(source.emission) > 0.0 ? kEmitterRaysPerPair : kRaysPerPair;
            };
            const auto pair_open = [&](uint32_t pair, int rays) {
                const uint32_t i = pair / rm.count, j = pair % rm.count;
                double open = 0.0;
                for (int q = 0; q < rays; ++q) {
                    // Other points at both ends for every q (3 q: a bijection of the 2 x 2).
                    const int a = int(i + j) + q, b = int(i + 2 * j + 1) + 3 * q;
                    open += s.rays->transmittance(src_point(i, a), rcv_point(j, b));
                }
                ev.rays += rays;
                return open / rays;
            };
            bool resolved = visible;
            if (!resolved && faint && lit_count > kFaintRays) {
                size_t open = 0;
                for (size_t t = 0; t < kFaintRays; ++t) {
                    const uint32_t pair = lit[t * lit_count / kFaintRays];
                    open += pair_open(pair, rays_of(pair)) == 1.0 ? 1 : 0;
                }
                if (open == 0) {
                    ev.kernel.clear();
                    ev.visibility = 0.0f;
                    return ev;
                }
                resolved = open == kFaintRays;
            }
            if (!resolved)
                for (size_t t = 0; t < lit_count; ++t) {
                    // One ray: open or not (through glass too); more: the share they find open.
                    const int rays = rays_of(lit[t]);
                    const double open = pair_open(lit[t], rays);
                    open_pair[t] = rays == kRaysPerPair ? (open > 0.0 ? 1.0f : 0.0f) : static_cast<float>(open);
                }
            bool any = false;
            for (size_t t = 0; t < lit_count; ++t) {
                if (!(open_pair[t] > 0.0f)) continue;
                const uint32_t i = lit[t] / rm.count, j = lit[t] % rm.count;
                const float k = open_pair[t] * static_cast<float>(
                    pairKernel(s, s.elements[s.cluster_members[sm.first + i]], s.elements[s.cluster_members[rm.first + j]],
                               &rcv_point(j, 0)));
                ev.kernel[lit[t]] = k;
                any = any || k > 0.0f;
            }
            if (!any) {
                // Every pair's ray blocked: it carries nothing, but a link above its faint bound
                // keeps its pairs (a zero kernel), so the read-out still casts rays from the points
                // that see a source past what blocked the pairs' rays (a folder's side past its
                // neighbour, a shelf's side face out of its compartment).
                if (faint) ev.kernel.clear();
                ev.visibility = 0.0f;
            }
            return ev;
        }
        // Separable: calibrated on sampled member pairs against the exact point-to-polygon
        // form factor (the product form alone read 0.5 % high in a closed room), and kept
        // only when every sampled ray between facing members agrees.
        const DVec3 c_r = centroidOf(s, r_node), c_s = centroidOf(s, s_node);
        std::vector<uint32_t> sf, rf;
        for (uint32_t i = 0; i < sm.count; ++i)
            if (sourceWeight(s.elements[s.cluster_members[sm.first + i]], c_r) > 0.0) sf.push_back(i);
        for (uint32_t j = 0; j < rm.count; ++j)
            if (receiverCosine(s.elements[s.cluster_members[rm.first + j]], c_s, c_r) > 0.0) rf.push_back(j);
        if (sf.empty() || rf.empty()) {
            ev.visibility = 0.0f;
            return ev;
        }
        // The calibration, once the link is known to carry light (after its rays).
        auto calibrate = [&] {
            double exact = 0.0, product = 0.0;
            const size_t pairs = std::min(kCalibrationPairs, sf.size() * rf.size());
            for (size_t t = 0; t < pairs; ++t) {
                const Element& ei = s.elements[s.cluster_members[sm.first + sf[(t * 7) % sf.size()]]];
                const uint32_t j = rf[(t * 5 + t / sf.size()) % rf.size()];
                const Element& ej = s.elements[s.cluster_members[rm.first + j]];
                product += sourceWeight(ei, c_r) * receiverCosine(ej, c_s, c_r);
                exact += averagedFormFactor(s, ej, polygonOf(s, ei), &rcv_point(j, 0));
            }
            if (product > 0.0) ev.scale = static_cast<float>(exact / product);
        };
        if (visible) {
            calibrate();
            return ev;
        }
        // Rays between facing members; the first disagreement settles it (mixed: split), as does
        // a ray through a transmitting surface (a separable link is wholly visible or dark).
        size_t open = 0, total = 0;
        auto cast = [&](const DVec3& from, const DVec3& to) {
            const double through = s.rays->transmittance(from, to);
            open += through > 0.0 ? 1 : 0;
            ++total;
            return (open > 0 && open < total) || (through > 0.0 && through < 1.0);
        };
        bool mixed = false;
        if (faint) {
            // A faint link (far below its threshold) is sampled on kFaintRays spread pairs, not
            // every member: what a partial occluder its rays miss can misplace is a fraction of
            // a power the oracle already lets this link misplace.
            for (size_t t = 0; t < kFaintRays && !mixed; ++t)
                mixed = cast(src_point(sf[(t * 7) % sf.size()], int(t)),
                             rcv_point(rf[(t * 5 + t / sf.size()) % rf.size()], int(t) + 1));
        } else {
            const size_t stride_r = std::max<size_t>(1, rf.size() / kRaysPerMember);
            const size_t stride_s = std::max<size_t>(1, sf.size() / kRaysPerMember);
            for (size_t t = 0; t < sf.size() && !mixed; ++t)
                for (int q = 0; q < kRaysPerMember && !mixed; ++q)
                    mixed = cast(src_point(sf[t], q), rcv_point(rf[(t + q * stride_r) % rf.size()], int(t) + q));
            for (size_t t = 0; t < rf.size() && !mixed; ++t)
                for (int q = 0; q < kRaysPerMember && !mixed; ++q)
                    mixed = cast(src_point(sf[(t + q * stride_s) % sf.size()], int(t) + q), rcv_point(rf[t], q));
        }
        ev.rays += total;
        if (mixed) {
            ev.decision = Decision::Split;  // refine until the pairs resolve it
            return ev;
        }
        if (open == 0) ev.visibility = 0.0f;  // else wholly visible
        else calibrate();
        return ev;
    };

    // Children of a node for a split: a cluster's two children, a leaf's member roots.
    auto children = [&](uint32_t node, std::vector<uint32_t>& out) {
        out.clear();
        const Cluster& c = s.clusters[clusterOf(node)];
        if (c.isLeaf()) {
            for (uint32_t k = 0; k < c.member_count; ++k) out.push_back(s.cluster_members[c.first_member + k]);
        } else {
            out.push_back(clusterNode(c.first_child));
            out.push_back(clusterNode(c.first_child + 1));
        }
    };
    auto diagonal = [&](uint32_t node) {
        return isCluster(node) ? glm::length(s.clusters[clusterOf(node)].box.extent()) : 2.0 * s.elements[node].radius;
    };

    // A split link's children, given to push(receiver, source, list).
    std::vector<uint32_t> a_children;
    auto splitLink = [&](const PendingClusterLink& link, ClusterEvaluation& ev, auto&& push) {
        // The children classify against this link's list, or its parent's when this one
        // culled little (lists of thousands of parts per link were most of the memory).
        uint32_t list = ev.list;
        if (ev.new_list && ev.first_candidate_only) {
            list = link.candidates;  // kept, then split by its rays: its list is incomplete
        } else if (ev.new_list && 4 * candidatePartCount(state_.parts, ev.candidates) > 3 * ev.list_parts) {
            list = link.candidates;
        } else if (ev.new_list) {
            list = static_cast<uint32_t>(state_.candidate_pool.size());
            state_.candidate_pool.push_back(std::move(ev.candidates));
        }
        if (link.receiver == link.source) {
            children(link.receiver, a_children);
            for (uint32_t a : a_children)
                for (uint32_t b : a_children) push(a, b, list);
            return;
        }
        // Near ties split the receiver: a relative margin keeps the choice (and so element
        // numbering) the same for a scene scaled by any factor.
        const bool split_source =
            !isCluster(link.receiver) ||
            (isCluster(link.source) && diagonal(link.source) > (1.0 + 1e-6) * diagonal(link.receiver));
        children(split_source ? link.source : link.receiver, a_children);
        for (uint32_t c : a_children) {
            if (split_source) push(link.receiver, c, list);
            else push(c, link.source, list);
        }
    };
    // Evaluates a level's links in batches (shared between ranks, or by this rank alone),
    // handing each to decide(index, evaluation) in order and then the batch's end to batchDone.
    std::vector<ClusterEvaluation> evals;
    auto evaluateLevel = [&](const std::vector<PendingClusterLink>& level, bool shared, auto&& decide,
                             auto&& batchDone) {
        for (size_t batch = 0; batch < level.size(); batch += kEvaluationBatch) {
            const size_t batch_end = std::min(level.size(), batch + kEvaluationBatch);
            evals.clear();
            evals.resize(batch_end - batch);
            auto compute = [&](size_t i) { evals[i] = evaluate(level[batch + i]); };
            if (shared) {
                state_.runner.forEachShared(
                    evals.size(), 4, compute, [&](Writer& w, size_t i) { encodeEvaluation(w, evals[i]); },
                    [&](Reader& r, size_t i) { decodeEvaluation(r, evals[i]); });
            } else {
                state_.runner.forEach(evals.size(), 4, compute);
            }
            for (size_t i = batch; i < batch_end; ++i) decide(i, evals[i - batch]);
            batchDone(batch_end);
        }
    };
    // Refines every stride-th link of `level` to the end, discarding the results (the pool's
    // new lists are dropped again): the seconds each level to come took on the sample, times
    // the stride, and the root links it made, for the progress estimate. Only a rank whose
    // progress is seen does it, alone (the ranks share the real levels: its time over their count).
    auto refineSample = [&](const std::vector<PendingClusterLink>& level, size_t stride) {
        RefinementClock::Sample sample;
        const size_t pool_size = state_.candidate_pool.size();
        std::vector<PendingClusterLink> links, next;
        for (size_t i = stride / 2; i < level.size(); i += stride) links.push_back(level[i]);
        sampled_links_ = links.size();
        auto push = [&](uint32_t r, uint32_t src, uint32_t list) {
            if (r == src && !isCluster(r)) return;
            if (!isCluster(r) && !isCluster(src)) sample.root_links += double(stride);
            else next.push_back({r, src, list});
        };
        while (!links.empty() && !state_.runner.cancelled()) {
            const auto start = std::chrono::steady_clock::now();
            next.clear();
            evaluateLevel(
                links, false,
                [&](size_t i, ClusterEvaluation& ev) {
                    if (ev.decision == Decision::Split) splitLink(links[i], ev, push);
                },
                [](size_t) {});
            sample.level_seconds.push_back(double(stride) * secondsSince(start) / state_.runner.ranks().size());
            sample.evaluations += double(stride) * double(links.size());
            std::swap(links, next);
        }
        state_.candidate_pool.resize(pool_size);
        return sample;
    };

    RefinementClock clock;
    sampled_links_ = 0;
    while (!pending.empty()) {
        checkMemoryBudget(state_.memory_budget_mb, "linking clusters");
        if (progress.watched() && !clock.sampled() && pending.size() >= kSampleFrom)
            clock.setSample(refineSample(pending, std::max(kSampleStride, pending.size() / kSampleLinks)), out.size());
        clock.beginLevel();
        s.stats.candidate_links += pending.size();
        std::vector<PendingClusterLink> next;
        auto push = [&](uint32_t r, uint32_t src, uint32_t list) {
            if (r == src && !isCluster(r)) return;  // a root does not light itself
            if (!isCluster(r) && !isCluster(src)) out.push_back({r, src, list});
            else next.push_back({r, src, list});
        };
        // In batches: every evaluation holds its candidate list until its decision, and a
        // level of a large scene holds hundreds of thousands of links.
        evaluateLevel(
            pending, true,
            [&](size_t i, ClusterEvaluation& ev) {
                const PendingClusterLink& link = pending[i];
                s.stats.rays += ev.rays;
                s.stats.cluster_rays += ev.rays;
                s.stats.shafts += ev.shaft ? 1 : 0;
                if (ev.decision == Decision::Drop) {
                    ++(ev.occluded ? s.stats.occluded_links : s.stats.dropped_links);
                    return;
                }
                if (ev.decision != Decision::Keep) ++s.stats.split_links;
                if (ev.decision == Decision::Keep && ev.visibility == 0.0f && !state_.options.keep_blocked_links &&
                    ev.kernel.empty()) {
                    // Carries nothing, is never reopened and lists no pairs: not stored (they were
                    // half of a building's cluster links, blocked by walls).
                    ++(ev.rays > 0 ? s.stats.occluded_links : s.stats.dropped_links);
                    return;
                }
                if (ev.decision == Decision::Keep) {
                    // Reopened, a link is classified again from its parent's list (a superset):
                    // a kept link's own list is not stored (it was most of the memory).
                    ClusterLink final_link{.receiver = link.receiver,
                                           .source = link.source,
                                           .candidates = ev.new_list ? link.candidates : ev.list,
                                           .kernel = kNoKernel,
                                           .visibility = ev.visibility,
                                           .scale = ev.scale};
                    if (!ev.kernel.empty()) final_link.kernel = appendKernel(s, ev.kernel.data(), ev.kernel.size());
                    s.cluster_links.push_back(final_link);
                    return;
                }
                splitLink(link, ev, push);
            },
            // The cluster links' share of the links phase (refine.cpp's element links the rest).
            [&](size_t batch_end) {
                progress.update(clock.fraction(double(batch_end) / double(pending.size()), out.size()));
            });
        clock.endLevel();
        pending = std::move(next);
    }
    state_.progress_base = clock.finished(out.size());
    return out;
}

void forEachClusterExchange(const Solution& s, const std::function<void(uint32_t, uint32_t)>& join) {
    for (const ClusterLink& link : s.cluster_links) {
        if (link.visibility == 0.0f) continue;
        const NodeMembers rm = membersOf(s, link.receiver), sm = membersOf(s, link.source);
        if (link.visibility < 0.0f) {
            // Deferred: it will carry light once its source has some; join both ends whole (a
            // group too large only brings its threshold nearer the scene's).
            for (uint32_t k = 1; k < rm.count; ++k) join(s.cluster_members[rm.first], s.cluster_members[rm.first + k]);
            for (uint32_t k = 0; k < sm.count; ++k) join(s.cluster_members[rm.first], s.cluster_members[sm.first + k]);
            continue;
        }
        const DVec3 c_r = centroidOf(s, link.receiver), c_s = centroidOf(s, link.source);
        uint32_t anchor = kNoElement;
        auto add = [&](uint32_t root) {
            if (anchor == kNoElement) anchor = root;
            else join(anchor, root);
        };
        if (link.kernel != kNoKernel) {
            for (uint64_t mask = kernelMask(s, link); mask != 0; mask &= mask - 1) {
                const auto pair = static_cast<uint32_t>(std::countr_zero(mask));  // pairs in order
                add(s.cluster_members[sm.first + pair / rm.count]);
                add(s.cluster_members[rm.first + pair % rm.count]);
            }
            continue;
        }
        for (uint32_t k = sm.first; k < sm.first + sm.count; ++k)
            if (sourceWeight(s.elements[s.cluster_members[k]], c_r) > 0.0) add(s.cluster_members[k]);
        for (uint32_t k = rm.first; k < rm.first + rm.count; ++k)
            if (receiverCosine(s.elements[s.cluster_members[k]], c_s, c_r) > 0.0) add(s.cluster_members[k]);
    }
}

void dropDeferredClusterLinks(Solution& s) {
    // A deferred link holds no kernel: removing it moves no kernel block.
    s.stats.dropped_links += std::erase_if(s.cluster_links, [](const ClusterLink& link) { return link.visibility < 0.0f; });
}

void groupClusterLinksByReceiver(Solution& s) {
    std::stable_sort(s.cluster_links.begin(), s.cluster_links.end(), [&](const ClusterLink& a, const ClusterLink& b) {
        return keyOf(s, a.receiver) < keyOf(s, b.receiver);
    });
    // The kernels in the links' order too: the gather reads a node's links one after another
    // for each of its members, and each link's kernel; left in the order the links were made,
    // those loads missed the cache (a third of the gather's time on graz.wrl).
    std::vector<float> ordered;
    ordered.reserve(s.cluster_kernel.size());
    for (ClusterLink& link : s.cluster_links) {
        if (link.kernel == kNoKernel) continue;
        const auto from = s.cluster_kernel.begin() + link.kernel;
        const auto offset = static_cast<uint32_t>(ordered.size());
        ordered.insert(ordered.end(), from, from + ptrdiff_t(kernelFloats(kernelMask(s, link))));
        link.kernel = offset;
    }
    s.cluster_kernel = std::move(ordered);
}

ClusterTransfer::ClusterTransfer(const Solution& s) {
    empty_ = s.cluster_links.empty();
    if (empty_) return;
    const size_t keys = s.root_count + s.clusters.size();
    link_begin_.assign(keys + 1, 0);
    for (const ClusterLink& link : s.cluster_links) ++link_begin_[keyOf(s, link.receiver) + 1];
    for (size_t k = 0; k < keys; ++k) link_begin_[k + 1] += link_begin_[k];
    flux_.assign(s.cluster_links.size(), DVec3(0.0));
}

void ClusterTransfer::gather(const Solution& s, ParallelRunner& runner, std::vector<DVec3>& per_root) {
    per_root.assign(s.root_count, DVec3(0.0));
    if (empty_) return;
    // Separable links: the source's weighted radiosity towards the receiver's centroid.
    runner.forEach(s.cluster_links.size(), 64, [&](size_t l) { flux_[l] = separableFlux(s, s.cluster_links[l]); });
    // The members' radiosity in cluster order, where a node's members are contiguous: pairwise
    // links read their sources' from here, not from elements scattered over the solution (those
    // loads were most of the gather, itself a sixth of graz.wrl's solve).
    member_radiosity_.resize(s.cluster_members.size());
    runner.forEach(s.cluster_members.size(), 1024,
                   [&](size_t k) { member_radiosity_[k] = s.elements[s.cluster_members[k]].radiosity; });
    // Every root gathers from the links of its own node and of its clusters, in a fixed order.
    runner.forEachSharedSlot(per_root, 64, [&](size_t r) {
        const uint32_t root = static_cast<uint32_t>(r);
        const Element& receiver = s.elements[root];
        DVec3 h(0.0);
        forLinksOf(s, root, [&](size_t l) {
            const ClusterLink& link = s.cluster_links[l];
            if (link.kernel == kNoKernel) {
                h += receiverCosine(receiver, centroidOf(s, link.source), centroidOf(s, link.receiver)) * flux_[l];
                return;
            }
            // pairKernelOf over the source members, the link's mask read once.
            const NodeMembers rm = membersOf(s, link.receiver), sm = membersOf(s, link.source);
            const uint32_t j = s.member_position[root] - rm.first;
            const uint64_t mask = kernelMask(s, link);
            const float* values = kernelValues(s, link);
            const DVec3* radiosity = member_radiosity_.data() + sm.first;
            for (uint32_t i = 0, pair = j; i < sm.count; ++i, pair += rm.count)
                if ((mask >> pair) & 1u) h += kernelValue(mask, values, pair) * radiosity[i];  // skip 0 x B
        });
        per_root[r] = h;
    });
}

template <class F>
void ClusterTransfer::forLinksOf(const Solution& s, uint32_t root, F&& f) const {
    auto visit = [&](uint32_t node) {
        const size_t key = keyOf(s, node);
        for (size_t l = link_begin_[key]; l < link_begin_[key + 1]; ++l)
            if (s.cluster_links[l].visibility > 0.0f) f(l);
    };
    visit(root);
    for (uint32_t c = s.root_leaf_cluster[root]; c != kNoElement; c = s.clusters[c].parent) visit(clusterNode(c));
}

std::vector<double> ClusterTransfer::leafFactors(const Solution& s, ParallelRunner& runner,
                                                 const std::vector<uint32_t>& leaves, ElementMemo* kept) const {
    std::vector<double> factor(leaves.size(), 1.0);
    if (empty_) return factor;
    std::vector<double> kernel_at(leaves.size(), 0.0);
    if (kept) kept->cover(s.elements.size());
    runner.forEachSharedSlot(kernel_at, 16, [&](size_t k) {
        const Element& leaf = s.elements[leaves[k]];
        if (leaves[k] == leaf.root) return;  // the root itself: its kernel is the links' own
        uint64_t signature = ElementMemo::kSignatureSeed;
        if (kept) {
            // What the sum reads: each link's source node, and a small link's lit pairs.
            forLinksOf(s, leaf.root, [&](size_t l) {
                const ClusterLink& link = s.cluster_links[l];
                signature = mixHash(signature, (uint64_t(link.source) << 1) | (link.kernel == kNoKernel));
                if (link.kernel == kNoKernel) return;
                const NodeMembers sm = membersOf(s, link.source), rm = membersOf(s, link.receiver);
                const uint32_t j = s.member_position[leaf.root] - rm.first;
                for (uint32_t i = 0; i < sm.count; ++i)
                    if (pairKernelOf(s, link, i * rm.count + j) > 0.0) signature = mixHash(signature, i);
            });
            if (kept->find(leaves[k], signature, kernel_at[k])) return;
        }
        double sum = 0.0;
        forLinksOf(s, leaf.root, [&](size_t l) {
            const ClusterLink& link = s.cluster_links[l];
            const NodeMembers sm = membersOf(s, link.source);
            if (link.kernel == kNoKernel) {
                // Separable (far) links: point kernels between centroids.
                for (uint32_t i = sm.first; i < sm.first + sm.count; ++i) {
                    const Element& src = s.elements[s.cluster_members[i]];
                    const DVec3 u = leaf.centroid - src.centroid;
                    const double d2 = glm::dot(u, u), cos_i = glm::dot(src.normal, u), cos_j = -glm::dot(leaf.normal, u);
                    if (cos_i > 0.0 && cos_j > 0.0 && d2 > 0.0) sum += src.area * cos_i * cos_j / (kPi * d2 * d2);
                }
                return;
            }
            // Small (near) links: the exact point-to-polygon form factor of each pair that carries
            // light (two sources at a time, summed in member order).
            const NodeMembers rm = membersOf(s, link.receiver);
            const uint32_t j = s.member_position[leaf.root] - rm.first;
            std::array<PolygonView, kPairwiseLimit> lit;  // a kernel's pairs fit one 64-bit mask
            std::array<double, kPairwiseLimit> f;
            size_t count = 0;
            for (uint32_t i = 0; i < sm.count; ++i) {
                if (!(pairKernelOf(s, link, i * rm.count + j) > 0.0)) continue;
                lit[count++] = polygonOf(s, s.elements[s.cluster_members[sm.first + i]]);
            }
            pointPolygonFormFactorsTo(leaf.centroid, leaf.normal, std::span<const PolygonView>(lit.data(), count),
                                      f.data());
            for (size_t i = 0; i < count; ++i) sum += f[i];
        });
        kernel_at[k] = sum;
        if (kept) kept->keep(leaves[k], signature, sum);
    });
    // Area averages per root (sequential: a fixed order), then each leaf's share.
    std::vector<double> weighted(s.root_count, 0.0), area(s.root_count, 0.0);
    for (size_t k = 0; k < leaves.size(); ++k) {
        const Element& leaf = s.elements[leaves[k]];
        weighted[leaf.root] += leaf.area * kernel_at[k];
        area[leaf.root] += leaf.area;
    }
    for (size_t k = 0; k < leaves.size(); ++k) {
        const Element& leaf = s.elements[leaves[k]];
        if (leaves[k] == leaf.root || !(weighted[leaf.root] > 0.0)) continue;
        factor[k] = kernel_at[k] * area[leaf.root] / weighted[leaf.root];
    }
    return factor;
}

}  // namespace radbake
