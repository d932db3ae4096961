#include "radiosity/refine.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include "core/memory.h"
#include "geometry/parts.h"
#include "radiosity/cluster.h"
#include "radiosity/elements.h"
#include "radiosity/sky_light.h"
#include "radiosity/form_factor.h"
#include "radiosity/punctual_lights.h"
#include "visibility/occlusion.h"
#include "visibility/ray_caster.h"

namespace radbake {
namespace {

// Elements deeper than this are never split (a guard; min_area stops long before).
constexpr uint32_t kMaxDepth = 30;

enum class LinkState : uint8_t { None, Visible, Partial, Occluded };

struct Evaluation {
    FormFactorEstimate ff;
    LinkState state = LinkState::None;
    double visibility = 1.0;        // Rays mode: from rays at evaluation
    std::vector<uint32_t> candidates;
    size_t rays = 0;
    bool shaft = false;
    bool classify_fell_back = false;  // ShaftResult::fell_back
};

// An evaluation as it crosses between ranks (ParallelRunner::forEachShared).
void encodeEvaluation(Writer& w, const Evaluation& ev) {
    w.value(ev.ff), w.value(ev.state), w.value(ev.visibility), w.array(ev.candidates);
    w.value(ev.rays), w.value(ev.shaft), w.value(ev.classify_fell_back);
}
void decodeEvaluation(Reader& r, Evaluation& ev) {
    r.value(ev.ff), r.value(ev.state), r.value(ev.visibility), r.array(ev.candidates);
    r.value(ev.rays), r.value(ev.shaft), r.value(ev.classify_fell_back);
}

// The visible fraction of a link from rays between the parts of its two elements that can
// exchange light: each clipped to the half-space in front of the other's plane. Rays to the
// whole polygons would also sample paths that carry no light and cross the elements' own
// objects: a beam's end cap and the ground behind its plane read fully blocked, though the
// strip of ground in front of the cap sees it.
double linkVisibleFraction(const Solution& s, const Element& source, const Element& receiver, int samples,
                           size_t* rays) {
    const PolygonView from = polygonOf(s, source), to = polygonOf(s, receiver);
    std::array<DVec3, kMaxClip> from_part, to_part;
    const size_t from_count = from.vertices.size() <= kMaxClip - 2
                                  ? clipAboveHorizon(to.centroid, to.normal, from.vertices, from_part.data())
                                  : 0;
    const size_t to_count = to.vertices.size() <= kMaxClip - 2
                                ? clipAboveHorizon(from.centroid, from.normal, to.vertices, to_part.data())
                                : 0;
    if (from_count < 3 || to_count < 3) return s.rays->visibleFraction(from.vertices, to.vertices, samples, rays);
    return s.rays->visibleFraction(std::span<const DVec3>(from_part.data(), from_count),
                                   std::span<const DVec3>(to_part.data(), to_count), samples, rays);
}

QuadratureOptions quadratureOptions(const SolverOptions& options) {
    QuadratureOptions q;
    q.order = options.quadrature_order;
    q.near_ratio = options.quadrature_near_ratio;
    q.max_depth = options.quadrature_max_depth;
    return q;
}

OcclusionTest occlusionTest(LinkVisibility mode) {
    switch (mode) {
        case LinkVisibility::Obb: return OcclusionTest::Obb;
        case LinkVisibility::Exact: return OcclusionTest::Exact;
        default: return OcclusionTest::None;
    }
}

Evaluation evaluate(const RefineState& state, const PendingLink& link) {
    const Solution& s = state.solution;
    const Element& r = s.elements[link.receiver];
    const Element& e = s.elements[link.source];
    const PolygonView receiver = polygonOf(s, r);
    const PolygonView source = polygonOf(s, e);
    Evaluation out;
    out.ff = polygonFormFactor(receiver, source, quadratureOptions(state.options));
    if (!(out.ff.form_factor > 0.0)) return out;
    if (state.options.visibility == LinkVisibility::Rays) {
        // The baseline without shafts: rays against the whole scene on every candidate link.
        out.visibility = linkVisibleFraction(s, e, r, state.options.visibility_samples, &out.rays);
        out.state = out.visibility <= 0.0   ? LinkState::Occluded
                    : out.visibility >= 1.0 ? LinkState::Visible
                                            : LinkState::Partial;
        return out;
    }
    if (link.candidates == kNoList) {
        out.state = LinkState::Visible;  // the parent's shaft held no potential occluder
        return out;
    }
    std::vector<uint32_t> excluded = state.root_excluded[r.root];
    const auto& more = state.root_excluded[e.root];
    excluded.insert(excluded.end(), more.begin(), more.end());
    ShaftQuery query;
    query.source = source.vertices;
    query.receiver = receiver.vertices;
    query.test = occlusionTest(state.options.visibility);
    query.excluded = excluded;
    ShaftResult result;
    classifyLink(state.parts, state.candidate_pool[link.candidates], query, result);
    out.shaft = true;
    out.classify_fell_back = result.fell_back;
    if (result.occluded) {
        out.state = LinkState::Occluded;
    } else if (result.candidates.empty()) {
        out.state = LinkState::Visible;
    } else {
        out.state = LinkState::Partial;
        out.candidates = std::move(result.candidates);
    }
    return out;
}

bool splittable(const RefineState& state, const Element& e) {
    return e.area > state.min_area && e.depth < kMaxDepth;
}

// The power the link may misplace, rho_R (F_max - F_min) B_S A_R, with the receiver's area
// taken to the power area_exponent relative to the scene's (1: the paper's oracle; below 1
// favours local accuracy on small elements; see SolverOptions).
double linkError(const RefineState& state, const Element& receiver, const Element& source, double spread) {
    const double total = state.solution.total_area;
    const double area = state.options.area_exponent == 1.0
                            ? receiver.area
                            : total * std::pow(receiver.area / total, state.options.area_exponent);
    return oracleReflectance(receiver.reflectance) * spread * maxChannel(source.radiosity) * area;
}

// The receiver's irradiance from the last solve; an element made since reads its nearest
// ancestor's (the mean over a region holding it: an estimate, like the power rule's P).
double receiverIrradiance(const RefineState& state, uint32_t element) {
    const auto& elements = state.solution.elements;
    while (element >= state.irradiance.size() && elements[element].parent != kNoElement)
        element = elements[element].parent;
    return element < state.irradiance.size() ? state.irradiance[element] : 0.0;
}

// The local rule, for a receiver the power rule cannot help: one at the min-area floor (a
// sliver, a leaf), whose power is too small for the power rule ever to split its source.
// (F_max - F_min) B_S bounds how far the irradiance this link brings varies over the
// receiver, i.e. what gathering it as a constant may misplace there; the source is split
// while that exceeds local_error_threshold x the receiver's whole irradiance H_R. Splittable
// receivers are left to the power rule: applied to them too, the rule at 0.2 doubled the
// Cornell Box's links (x5 on Shadow) for 0.1 % of L2 error.
// A source split already (for other links) whose children's light differs brings, read as
// its mean, up to F (B_max - B_min) too much or too little: the rule counts that as well. A
// sliver standing on a floor cut along it (contact_cuts.h) sees the floor's half at F = 0.5
// from every point (no spread), and read its mean 40 % below the bright patch it stands in.
bool locallyInaccurate(const RefineState& state, uint32_t receiver, const Element& source, double spread,
                       double form_factor) {
    if (!state.local_active) return false;
    const Element& r = state.solution.elements[receiver];
    if (splittable(state, r) || !splittable(state, source)) return false;
    const double allowed = state.options.local_error_threshold * receiverIrradiance(state, receiver);
    return spread * maxChannel(source.radiosity) + form_factor * childRadiositySpread(state.solution, source) >
           allowed;
}

// Either rule asks for a split (the min-area floor and the depth guard still stop it).
// `form_factor`: the link's mean form factor without visibility.
bool needsRefinement(const RefineState& state, uint32_t receiver, uint32_t source, double spread,
                     double form_factor) {
    const Element& r = state.solution.elements[receiver];
    const Element& e = state.solution.elements[source];
    return linkError(state, r, e, spread) > state.thresholdFor(r.root) ||
           locallyInaccurate(state, receiver, e, spread, form_factor);
}

uint32_t findGroup(std::vector<uint32_t>& group, uint32_t i) {
    while (group[i] != i) i = group[i] = group[group[i]];
    return i;
}

// Roots joined by a link that carries light (form factor, visibility included, > 0) exchange
// light; the closure of that relation splits the scene into groups that cannot light each
// other (two closed rooms). Each group is its own scene for the power rule: its threshold is
// error_threshold x the power leaving its own surfaces, so a dim room beside one 1e8
// brighter is refined as if it were alone. One group (any connected room) changes nothing.
void groupThresholds(RefineState& state) {
    const Solution& s = state.solution;
    std::vector<uint32_t> group(s.root_count);
    for (uint32_t i = 0; i < s.root_count; ++i) group[i] = i;
    for (const Link& link : s.links) {
        if (!(link.form_factor > 0.0)) continue;
        const uint32_t a = findGroup(group, s.elements[link.receiver].root);
        const uint32_t b = findGroup(group, s.elements[link.source].root);
        if (a != b) group[std::max(a, b)] = std::min(a, b);  // smallest index: deterministic
    }
    forEachClusterExchange(s, [&](uint32_t ra, uint32_t rb) {  // cluster links carry light too
        const uint32_t a = findGroup(group, ra), b = findGroup(group, rb);
        if (a != b) group[std::max(a, b)] = std::min(a, b);
    });
    std::vector<double> power(s.root_count, 0.0);
    for (uint32_t i = 0; i < s.root_count; ++i)
        power[findGroup(group, i)] += s.elements[i].area * maxChannel(s.elements[i].radiosity);
    state.root_threshold.assign(s.root_count, state.threshold);
    for (uint32_t i = 0; i < s.root_count; ++i) {
        const double p = power[findGroup(group, i)];
        if (p > 0.0) state.root_threshold[i] = std::min(state.threshold, state.options.error_threshold * p);
    }
}

}  // namespace

void RefineState::updateThresholds() {
    // Later rounds compare against the power leaving the surfaces (emitted and reflected):
    // at rho = 0.99 that is 100 times the emitted power, and so is every link's error.
    double power = 0.0;
    for (uint32_t i = 0; i < solution.root_count; ++i)
        power += solution.elements[i].area * maxChannel(solution.elements[i].radiosity);
    if (power > 0.0) threshold = options.error_threshold * power;
    groupThresholds(*this);

    local_active = options.local_error_threshold > 0.0;
    if (!local_active) return;
    // Mean irradiance over each element: what its ancestors' links push down, what its own
    // links gather, and the area average of what its descendants' links gather, plus the
    // punctual lights' direct light. Parents precede their (contiguous) children.
    const auto& elements = solution.elements;
    const size_t n = elements.size();
    std::vector<DVec3> above(n, DVec3(0.0)), below(n, DVec3(0.0));
    for (size_t i = 0; i < n; ++i) {
        const Element& e = elements[i];
        above[i] = e.gathered + (e.parent == kNoElement ? DVec3(0.0) : above[e.parent]);
    }
    for (size_t i = n; i-- > 0;) {
        const Element& e = elements[i];
        below[i] = e.gathered;
        double area = 0.0;
        DVec3 sum(0.0);
        for (uint32_t c = 0; c < e.child_count; ++c) {
            area += elements[e.first_child + c].area;
            sum += elements[e.first_child + c].area * below[e.first_child + c];
        }
        if (area > 0.0) below[i] += sum / area;
    }
    irradiance.assign(n, 0.0);
    for (size_t i = 0; i < n; ++i) {
        const Element& e = elements[i];
        DVec3 h = below[i] + (e.parent == kNoElement ? DVec3(0.0) : above[e.parent]);
        if (i < direct.size()) h += direct[i];
        irradiance[i] = maxChannel(h);
    }
}

RefineState makeRefineState(const Scene& scene, const PartSet& parts, const SolverOptions& options,
                            ParallelRunner& runner, Solution& solution) {
    RefineState state{.scene = scene, .parts = parts, .options = options, .runner = runner, .solution = solution};
    state.memory_budget_mb = memoryBudgetMegabytes(options.max_memory_mb);
    state.candidate_pool.push_back(allParts(parts));
    // partsOfPolygon's answer for every root from one pass over the parts (asking it per root
    // scanned every part: O(roots x parts), minutes on the 1M-triangle building).
    std::vector<std::vector<std::vector<uint32_t>>> by_polygon(scene.meshes.size());
    for (uint32_t p = 0; p < parts.parts.size(); ++p) {
        const ConvexPart& part = parts.parts[p];
        if (part.mesh >= by_polygon.size()) continue;
        auto& mesh = by_polygon[part.mesh];
        for (const uint32_t polygon : part.polygons) {
            if (polygon >= mesh.size()) mesh.resize(polygon + 1);
            if (mesh[polygon].empty() || mesh[polygon].back() != p) mesh[polygon].push_back(p);
        }
    }
    state.root_excluded.resize(solution.root_count);
    for (uint32_t i = 0; i < solution.root_count; ++i) {
        const Element& e = solution.elements[i];
        if (e.mesh < by_polygon.size() && e.polygon < by_polygon[e.mesh].size())
            state.root_excluded[i] = by_polygon[e.mesh][e.polygon];
    }
    state.min_area = options.min_element_area * solution.total_area;
    return state;
}

size_t SkyCornerHash::operator()(const SkyCornerKey& k) const {
    uint64_t h = 0;
    for (const DVec3* v : {&k.point, &k.normal})
        for (int c = 0; c < 3; ++c) h = mixHash(h, std::bit_cast<uint64_t>((*v)[c]));
    return static_cast<size_t>(h);
}

namespace {

// The sky at every corner of the elements `todo` (Solution::vertex_sky), each distinct (point,
// normal) once: elements sharing a corner on one plane share its value, so the light read across
// their edge is continuous. A corner is read from just inside its element (the first to name it)
// and off its plane: on a contact line the sky is the limit from inside the face.
// Returns the rays cast.
size_t skyAtCorners(RefineState& state, const std::vector<uint32_t>& todo) {
    Solution& s = state.solution;
    s.vertex_sky.resize(s.vertices.size(), DVec3(0.0));
    struct Corner {
        DVec3 from, normal;
        std::vector<uint32_t> slots;  // into Solution::vertices
    };
    std::vector<Corner> corners;
    const size_t base = state.sky_values.size();
    for (const uint32_t i : todo) {
        const Element& e = s.elements[i];
        for (uint32_t k = 0; k < e.vertex_count; ++k) {
            const uint32_t slot = e.first_vertex + k;
            const DVec3& p = s.vertices[slot];
            const auto [it, added] =
                state.sky_corners.try_emplace(SkyCornerKey{p, e.normal}, static_cast<uint32_t>(base + corners.size()));
            if (added) {
                const double step = kSkyCornerLifts * s.rays->epsilon();
                const DVec3 inward = e.centroid - p;
                const double length = glm::length(inward);
                corners.push_back({p + step * (e.normal + (length > 0.0 ? inward / length : DVec3(0.0))), e.normal, {}});
            }
            if (it->second >= base) corners[it->second - base].slots.push_back(slot);
            else s.vertex_sky[slot] = state.sky_values[it->second];  // read in an earlier pass
        }
    }
    std::vector<DVec3> value(corners.size());
    std::vector<size_t> rays(corners.size(), 0);
    state.runner.forEachShared(
        corners.size(), 8,
        [&](size_t c) {
            value[c] = skyIrradiance(state.scene.sky, s.rays.get(), corners[c].from, corners[c].normal,
                                     state.options.sky, &rays[c]);
        },
        [&](Writer& w, size_t c) { w.value(value[c]), w.value(rays[c]); },
        [&](Reader& r, size_t c) { r.value(value[c]), r.value(rays[c]); });
    size_t total = 0;
    for (size_t c = 0; c < corners.size(); ++c) {
        for (const uint32_t slot : corners[c].slots) s.vertex_sky[slot] = value[c];
        state.sky_values.push_back(value[c]);
        total += rays[c];
    }
    return total;
}

}  // namespace

// A corner reading more than this times the mean of the element's other corners is singular.
constexpr double kSingularCorner = 4.0;

// Whether leaf i's direct light varies more over it than its group's power rule allows.
bool directTooCoarse(const RefineState& state, uint32_t i) {
    const Element& e = state.solution.elements[i];
    if (!(state.threshold > 0.0) || !e.isLeaf() || !splittable(state, e)) return false;
    const DVec3& spread = state.direct_spread[i];
    const double varies = maxChannel(e.reflectance) > 0.0 ? maxChannel(e.reflectance * spread) : maxChannel(spread);
    return varies * e.area > state.thresholdFor(e.root);
}

void computeDirectLight(RefineState& state) {
    Solution& s = state.solution;
    const Scene& scene = state.scene;
    // Leaves read before a solve set their group's power rule (updateThresholds: a room lit
    // only through a slit is refined by the light it gets, not by the sunlit outside) are
    // examined again; their children read their own direct light below.
    for (uint32_t i = 0; i < state.direct_spread.size(); ++i)
        if (state.direct_done[i] && directTooCoarse(state, i)) ensureChildren(s, i);
    // Own emission first (every element, cheap).
    auto own = [&](const Element& e) { return kPi * DVec3(polygonEmission(scene, scene.meshes[e.mesh], e.polygon)); };
    const bool lights = !scene.lights.empty();
    const bool direct = lights || scene.sky.shines();
    for (int pass = 0; pass < 64; ++pass) {
        state.direct_done.resize(s.elements.size(), 0);
        state.direct.resize(s.elements.size(), DVec3(0.0));
        std::vector<uint32_t> todo;
        for (uint32_t i = 0; i < s.elements.size(); ++i)
            if (!state.direct_done[i]) todo.push_back(i);
        if (todo.empty()) break;
        std::vector<DVec3> mean(todo.size(), DVec3(0.0)), spread(todo.size(), DVec3(0.0));
        std::vector<size_t> rays(todo.size(), 0);
        if (lights) {
            const auto compute = [&](size_t k) {
                const Element& e = s.elements[todo[k]];
                const PolygonView poly = polygonOf(s, e);
                // 3 x 3 (odd): a symmetric 2 x 2 pattern can hide a light straight above.
                const auto points = stratifiedPolygonPoints(poly.vertices, 3);
                DVec3 lo(std::numeric_limits<double>::max()), hi(0.0), sum(0.0);
                for (const DVec3& p : points) {
                    const DVec3 h = punctualIrradiance(scene.lights, s.rays.get(), p, e.normal, &rays[k], e.mesh);
                    sum += h;
                    lo = glm::min(lo, h);
                    hi = glm::max(hi, h);
                }
                mean[k] = points.empty() ? DVec3(0.0) : sum / static_cast<double>(points.size());
                spread[k] = points.empty() ? DVec3(0.0) : hi - lo;
            };
            state.runner.forEachShared(
                todo.size(), 16, compute,
                [&](Writer& w, size_t k) { w.value(mean[k]), w.value(spread[k]), w.value(rays[k]); },
                [&](Reader& r, size_t k) { r.value(mean[k]), r.value(spread[k]), r.value(rays[k]); });
        }
        if (state.scene.sky.shines()) {
            s.stats.rays += skyAtCorners(state, todo);
            std::vector<size_t> singular;
            std::vector<DVec3> corner_mean;
            for (size_t k = 0; k < todo.size(); ++k) {
                const Element& e = s.elements[todo[k]];
                DVec3 lo(std::numeric_limits<double>::max()), hi(0.0), sum(0.0);
                for (uint32_t c = 0; c < e.vertex_count; ++c) {
                    const DVec3& h = s.vertex_sky[e.first_vertex + c];
                    sum += h, lo = glm::min(lo, h), hi = glm::max(hi, h);
                }
                mean[k] += sum / static_cast<double>(e.vertex_count);
                spread[k] += hi - lo;
                const double top = maxChannel(hi), rest = maxChannel(sum) - top;
                if (top > kSingularCorner * rest / (e.vertex_count - 1)) {
                    singular.push_back(k);
                    corner_mean.push_back(sum / static_cast<double>(e.vertex_count));
                }
            }
            // A corner that sees far more sky than the others (one standing in a slit, at a
            // window's edge) stands for a quarter of the element in the corners' mean: such an
            // element's light is read inside it, as punctual light is.
            std::vector<DVec3> inside(singular.size(), DVec3(0.0));
            const auto inside_of = [&](size_t u) {
                const Element& e = s.elements[todo[singular[u]]];
                const auto points = stratifiedPolygonPoints(polygonOf(s, e).vertices, 3);
                const DVec3 lift = e.normal * (kSkyCornerLifts * s.rays->epsilon());
                for (const DVec3& p : points)
                    inside[u] += skyIrradiance(scene.sky, s.rays.get(), p + lift, e.normal, state.options.sky,
                                               &rays[singular[u]]);
                if (!points.empty()) inside[u] /= static_cast<double>(points.size());
            };
            state.runner.forEachShared(
                singular.size(), 2, inside_of,
                [&](Writer& w, size_t u) { w.value(inside[u]), w.value(rays[singular[u]]); },
                [&](Reader& r, size_t u) { r.value(inside[u]), r.value(rays[singular[u]]); });
            for (size_t u = 0; u < singular.size(); ++u) mean[singular[u]] += inside[u] - corner_mean[u];
        }
        bool split_any = false;
        state.direct_spread.resize(s.elements.size(), DVec3(0.0));
        for (size_t k = 0; k < todo.size(); ++k) {
            const uint32_t i = todo[k];
            s.stats.rays += rays[k];
            Element& e = s.elements[i];
            e.emission = own(e) + e.reflectance * mean[k];
            state.direct[i] = mean[k];
            state.direct_spread[i] = spread[k];
            state.direct_done[i] = 1;
            // Refine where the direct light varies (threshold known after the first pass).
            if (directTooCoarse(state, i)) {
                ensureChildren(s, i);
                split_any = true;
            }
        }
        if (pass == 0 && state.threshold == 0.0) {
            double power = 0.0;
            for (uint32_t i = 0; i < s.root_count; ++i) power += s.elements[i].area * maxChannel(s.elements[i].emission);
            state.threshold = state.options.error_threshold * power;
            // Re-examine the roots' direct light with the threshold now known.
            if (direct && state.threshold > 0.0) {
                for (uint32_t i = 0; i < s.root_count; ++i) state.direct_done[i] = 0;
                continue;
            }
        }
        if (!split_any && pass > 0) break;
    }
}

std::vector<PendingLink> initialLinks(const RefineState& state) {
    const Solution& s = state.solution;
    std::vector<PendingLink> links;
    for (uint32_t r = 0; r < s.root_count; ++r) {
        const PolygonView receiver = polygonOf(s, s.elements[r]);
        for (uint32_t e = 0; e < s.root_count; ++e) {
            if (e == r) continue;
            if (facing(receiver, polygonOf(s, s.elements[e]))) links.push_back({r, e, 0});
        }
    }
    return links;
}

void refineLinks(RefineState& state, std::vector<PendingLink> pending, Progress& progress) {
    Solution& s = state.solution;
    std::vector<size_t> needs_rays;  // final partial links (not in Rays mode)
    const bool rays_mode = state.options.visibility == LinkVisibility::Rays;
    int level = 0;
    while (!pending.empty()) {
        if (state.runner.cancelled()) return;  // the solver stops after this phase
        checkMemoryBudget(state.memory_budget_mb, "linking");
        s.stats.candidate_links += pending.size();
        std::vector<PendingLink> next;
        // In batches, so that progress moves within a level and the evaluations' candidate
        // lists are held for one batch only. Decisions stay in link order: evaluation reads
        // nothing a decision of an earlier batch changes (new children, new lists).
        std::vector<Evaluation> evals;
        for (size_t batch = 0; batch < pending.size(); batch += kEvaluationBatch) {
            const size_t batch_end = std::min(pending.size(), batch + kEvaluationBatch);
            evals.clear();
            evals.resize(batch_end - batch);
            state.runner.forEachShared(
                evals.size(), 8, [&](size_t i) { evals[i] = evaluate(state, pending[batch + i]); },
                [&](Writer& w, size_t i) { encodeEvaluation(w, evals[i]); },
                [&](Reader& r, size_t i) { decodeEvaluation(r, evals[i]); });
            for (size_t i = batch; i < batch_end; ++i) {
                Evaluation& ev = evals[i - batch];
                const PendingLink& link = pending[i];
                s.stats.rays += ev.rays;
                s.stats.shafts += ev.shaft ? 1 : 0;
                s.stats.classify_fallbacks += ev.classify_fell_back ? 1 : 0;
                if (ev.state == LinkState::Occluded) {
                    ++s.stats.occluded_links;
                    continue;
                }
                if (ev.state == LinkState::None) {
                    ++s.stats.dropped_links;
                    continue;
                }
                const bool partial = ev.state == LinkState::Partial;
                const double spread = ev.ff.f_max - (partial ? 0.0 : ev.ff.f_min);
                const Element& r = s.elements[link.receiver];
                const Element& e = s.elements[link.source];
                uint32_t list = kNoList;
                if (partial) {
                    if (rays_mode) {
                        list = 0;
                    } else {
                        list = static_cast<uint32_t>(state.candidate_pool.size());
                        state.candidate_pool.push_back(std::move(ev.candidates));
                    }
                }
                if (needsRefinement(state, link.receiver, link.source, spread, ev.ff.form_factor)) {
                    const bool split_r = splittable(state, r), split_e = splittable(state, e);
                    if (split_e && (e.area > r.area || !split_r)) {
                        const uint32_t count = ensureChildren(s, link.source);
                        const uint32_t first = s.elements[link.source].first_child;
                        for (uint32_t c = 0; c < count; ++c) next.push_back({link.receiver, first + c, list});
                        ++s.stats.split_links;
                        continue;
                    }
                    if (split_r) {
                        const uint32_t count = ensureChildren(s, link.receiver);
                        const uint32_t first = s.elements[link.receiver].first_child;
                        for (uint32_t c = 0; c < count; ++c) next.push_back({first + c, link.source, list});
                        ++s.stats.split_links;
                        continue;
                    }
                }
                Link final_link{link.receiver, link.source, ev.ff.form_factor, 1.0f};
                if (rays_mode) {
                    final_link.visibility = static_cast<float>(ev.visibility);
                    final_link.form_factor *= ev.visibility;
                    final_link.by_rays = true;
                } else if (partial) {
                    needs_rays.push_back(s.links.size());
                }
                s.links.push_back(final_link);
                state.records.push_back({spread, list});
            }
            // After the cluster links (cluster.cpp: their share), or the whole phase.
            const double base = state.progress_base;
            progress.update(base + (0.98 - base) * refinementFraction(level + double(batch_end) / pending.size()));
        }
        pending = std::move(next);
        ++level;
    }
    state.progress_base = 0.0;
    // A partial link that stopped refining gets its real visibility from rays.
    std::vector<double> visibility(needs_rays.size(), 1.0);
    std::vector<size_t> rays(needs_rays.size(), 0);
    state.runner.forEachShared(
        needs_rays.size(), 16,
        [&](size_t k) {
            const Link& link = s.links[needs_rays[k]];
            visibility[k] = linkVisibleFraction(s, s.elements[link.source], s.elements[link.receiver],
                                                state.options.visibility_samples, &rays[k]);
        },
        [&](Writer& w, size_t k) { w.value(visibility[k]), w.value(rays[k]); },
        [&](Reader& r, size_t k) { r.value(visibility[k]), r.value(rays[k]); });
    for (size_t k = 0; k < needs_rays.size(); ++k) {
        Link& link = s.links[needs_rays[k]];
        link.visibility = static_cast<float>(visibility[k]);
        link.form_factor *= visibility[k];
        link.by_rays = true;
        s.stats.rays += rays[k];
    }
    // A link every ray found blocked carries nothing and is never reopened: its candidate
    // list (its own) is freed. The link stays: the reconstruction finds the polygons touching
    // a point through its links (reconstruct.cpp), blocked ones included.
    for (size_t k = 0; k < needs_rays.size(); ++k) {
        LinkRecord& record = state.records[needs_rays[k]];
        if (visibility[k] > 0.0 || record.candidates == kNoList || record.candidates == 0) continue;
        std::vector<uint32_t>().swap(state.candidate_pool[record.candidates]);
        record.candidates = kNoList;
    }
}

std::vector<PendingLink> reopenLinks(RefineState& state) {
    Solution& s = state.solution;
    std::vector<PendingLink> reopened;
    size_t kept = 0;
    for (size_t i = 0; i < s.links.size(); ++i) {
        const Link& link = s.links[i];
        const Element& r = s.elements[link.receiver];
        const Element& e = s.elements[link.source];
        const LinkRecord& record = state.records[i];
        const bool can_split = splittable(state, r) || splittable(state, e);
        if (can_split && link.visibility > 0.0f &&
            needsRefinement(state, link.receiver, link.source, record.spread, link.form_factor / link.visibility)) {
            // Re-evaluated from its own pair: its own candidate list is a superset of what
            // its sub-links need.
            reopened.push_back({link.receiver, link.source, record.candidates});
            ++s.stats.reopened_links;
            continue;
        }
        s.links[kept] = link;
        state.records[kept] = record;
        ++kept;
    }
    s.links.resize(kept);
    state.records.resize(kept);
    return reopened;
}

}  // namespace radbake
