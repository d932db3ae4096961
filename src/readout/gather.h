#pragma once
// The point gather over the element hierarchy (internal to readout/): probeIrradiance's
// exhaustive gather walks it from every root, the link reconstruction (reconstruct.cpp) from
// the sources of the links that reach the point's element.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "geometry/box.h"
#include "geometry/polygon.h"
#include "radiosity/elements.h"
#include "readout/evaluate_probe.h"
#include "radiosity/form_factor.h"
#include "radiosity/punctual_lights.h"
#include "radiosity/sky_light.h"
#include "radiosity/refine.h"
#include "radiosity/solution.h"
#include "visibility/ray_caster.h"

namespace radbake {
namespace gather {

// Ray ends are lifted off their surfaces by this fraction of the scene's extent, so a point
// on the edge of a wall (a room corner) does not cast along the wall's own plane. Well above
// float rounding of coordinates (1e-7) and far below any lit feature.
inline constexpr double kLift = 1e-5;

// Points on the element where visibility is sampled: an n x n grid of cell centres.
inline void elementPoints(std::span<const DVec3> loop, int n, std::vector<DVec3>& out) {
    out.clear();
    if (loop.size() == 4) {
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                const double u = (i + 0.5) / n, v = (j + 0.5) / n;
                out.push_back((1 - u) * (1 - v) * loop[0] + u * (1 - v) * loop[1] + u * v * loop[2] +
                              (1 - u) * v * loop[3]);
            }
        return;
    }
    out = stratifiedPolygonPoints(loop, n);
}

// A partially visible piece is split at most this many times below a leaf: with the size
// rule below it only binds for a piece that is very close to the probe.
inline constexpr int kMaxVisibilitySplits = 10;
// Below a leaf, pieces with agreeing rays are split for the coarse rule at most this many
// times: near a vertex in a room corner every neighbouring piece fails the rule, and splitting
// them all ten levels deep cost ~7 ms per vertex in the Cornell Box.
inline constexpr int kMaxCoarseSplits = 3;
// Pieces below a partly visible one keep splitting for this many levels even when their own
// rays agree, so an edge that slips between the rays of one level is found at the next.
inline constexpr int kSuspectLevels = 2;
// Gatherer::radiosityVaries: the relative error an inner element read whole may bring.
// Measured with tools/bench_reconstruct on the Cornell box at 64 texels/m (1 thread, texel
// RMS against the exhaustive gather, CPU per texel): none 2.2 %, 0.1: 1.9 %, 0.03: 1.8 % at
// the cost without it, 0.01: 1.8 % for 10-20 % more.
inline constexpr double kSmoothOpening = 0.03;
// The coarse rule is this much finer on a light source (an element whose light is mostly its
// own emission): its penumbrae are the sharpest and carry the most light. A piece of a 2 x 1 m
// luminaire 5 m up, trusted with 2 x 2 unanimous rays at 0.1 radius / distance, left probes in
// scenes/paper/shadow.wrl's penumbrae fully lit (+28 %) or black (-70 %); a finer rule on
// every source would cost 2-2.5 times the rays per probe.
inline constexpr double kEmitterCoarseFactor = 0.4;

// True when most of the element's light is its own (a luminaire, or a surface lit by a punctual light).
inline bool emitsMostOfItsLight(const Element& e) {
    return maxChannel(e.emission) >= 0.5 * maxChannel(e.radiosity);
}

// ReadoutOptions::probe_grazing_corner_rays: a piece gets a corner ray when that corner is
// within this sine of the point's horizon and its kernel is above this ratio of the samples'
// largest. The ceiling above the tessellated Cornell box's lamp (its walls' tops seen through
// the 1 cm gap, 6-17 degrees up) needs 1.1 and 0.3: its 8 vertices +14 % -> -4 %, for 6 % more
// rays at house.wrl's vertices and texels; on every piece (probe_corner_rays), 2 x the rays.
inline constexpr double kGrazingKernelRatio = 1.1;
inline constexpr double kGrazingElevation = 0.3;

// Most sources a point might gather from are small and far: their form factor, which ranks them
// and weights the light of those read without rays, is the point-to-centroid kernel
// A cos cos / (pi d^2) when the source's radius is below this share of its distance, wholly above
// the point's horizon and facing it (off by about the square of the ratio). Sources read with
// rays get their exact form factor.
inline constexpr double kFarFieldRatio = 0.05;

// The far-field form factor of `source` (its polygon's `vertices`) from the point, or -1 where it
// does not hold.
inline double farFormFactor(const DVec3& point, const DVec3& normal, const Element& source,
                            std::span<const DVec3> vertices) {
    const DVec3 u = source.centroid - point;
    const double d2 = glm::dot(u, u);
    if (!(source.radius * source.radius < kFarFieldRatio * kFarFieldRatio * d2)) return -1.0;
    for (const DVec3& v : vertices)
        if (!(glm::dot(normal, v - point) > 0.0)) return -1.0;
    const double cos_source = -glm::dot(source.normal, u);
    if (!(cos_source > 0.0)) return 0.0;  // the point is behind it
    return source.area * glm::dot(normal, u) * cos_source / (kPi * d2 * d2);
}

// An entry of a brightest-first heap: a light and the index of what it belongs to, side by side
// (comparing through the index cost a cache miss a step). Ties go to the lower index.
struct Ranked {
    double light;
    uint32_t k;
};
inline bool dimmer(const Ranked& a, const Ranked& b) { return a.light != b.light ? a.light < b.light : a.k > b.k; }

struct Gatherer {
    const Solution& s;
    const ReadoutOptions& o;
    DVec3 point{0.0}, normal{0.0}, origin{0.0};
    double lift = 0.0;
    std::vector<DVec3> points{};
    std::array<DVec3, kMaxClip> horizon_loop{};
    DVec3 sum{0.0};
    ProbeCounters* counters = nullptr;
    // Rays for visibility: the exhaustive gather casts them whenever the solution has a
    // caster; the link reconstruction only below links that are partly visible.
    bool use_rays = true;
    // The coarse rule (probe_visibility_coarse: unanimous rays trusted only on small enough
    // pieces) guards the exhaustive gather against a sliver of light between its rays. The
    // link reconstruction turns it off below partly visible links: the solver refined them
    // until they carry little, and a piece whose rays disagree is still split.
    bool coarse_rule = true;
    // The exhaustive gather's rules (the coarse rule, probe_visibility_ratio, its split
    // depth) on light sources, without the coarse rule elsewhere (the link reconstruction,
    // below partly visible links): a luminaire's penumbra carries the most light, and a point
    // in it read with 2 x 2 rays to a whole piece of the lamp, split once, came out twice the
    // exhaustive gather (scenes/paper/shadow.wrl's ground beside the beams).
    bool coarse_rule_on_emitters = false;
    bool coarseFor(bool emitter) const { return coarse_rule || (emitter && coarse_rule_on_emitters); }
    // Inner elements opened as the coarse rule opens them (down to its ratio of radius to
    // distance), leaves not split for it.
    bool coarse_opening = false;
    // Without it, a partly visible piece is opened down to this radius / distance only
    // (with it: probe_visibility_ratio).
    double link_visibility_ratio = 0.05;
    // Pieces below a leaf are split for visibility at most this many times.
    int max_visibility_splits = kMaxVisibilitySplits;
    // Unblocked fraction of an n x n grid of segments from the probe to the polygon, over
    // the part of it above the probe's horizon: the part its form factor integrates. (Rays
    // to the part below pass through the probe's own surface: a lamp just under a ceiling
    // read the tops of the walls as blocked and came out 4 % dark.) Returns the open count
    // in `open` and the ray count in `total`, and in `visible` the open share of the form
    // factor: each ray weighted by the point-to-point kernel cos cos / d^2 at its end, where
    // counting them alike is biased whenever what hides a piece sits where the kernel is
    // high or low (a nearby edge). On the tessellated Cornell box it moved little (vertices
    // 1.52 -> 1.50 % RMS; the ceiling above its lamp +14.3 -> +13.6 %: there the rays miss
    // the hidden part altogether, which probe_corner_rays is for).
    // Returns whether a corner ray was cast (probe_grazing_corner_rays then recasts a partly
    // hidden piece, as probe_corner_rays does every one).
    std::vector<double> weights{};
    bool castVisibility(std::span<const DVec3> loop, const DVec3& loop_normal, int& open, int& total,
                        double& visible, int samples_per_side = 0) {
        const int n = samples_per_side > 0 ? samples_per_side : std::max(2, o.probe_samples);
        bool below = false;
        for (const DVec3& v : loop) below = below || !(glm::dot(normal, v - point) > 0.0);
        if (below) {
            // Only pieces with a form factor get here: at most kMaxClip - 2 vertices.
            const size_t count = clipAboveHorizon(point, normal, loop, horizon_loop.data());
            if (count >= 3) points = stratifiedPolygonPoints(std::span<const DVec3>(horizon_loop.data(), count), n);
            else points.clear();
        } else {
            elementPoints(loop, n, points);
        }
        const auto kernel = [&](const DVec3& q) {
            const DVec3 v = q - point;
            const double d2 = glm::dot(v, v);
            return d2 > 0.0 ? std::max(0.0, glm::dot(normal, v)) * std::max(0.0, -glm::dot(loop_normal, v)) / (d2 * d2)
                            : 0.0;
        };
        weights.resize(points.size());
        double weight_sum = 0.0, weight_max = 0.0;
        for (size_t k = 0; k < points.size(); ++k) {
            weights[k] = kernel(points[k]);
            weight_sum += weights[k];
            weight_max = std::max(weight_max, weights[k]);
        }
        // ReadoutOptions::probe_corner_rays: the corner where the kernel is highest (1/16 of the
        // way in), if above every sample's, gets a ray that only tells whether the piece is
        // partly hidden (then split): the lamp hides the bottom eighth of each wall tile the
        // ceiling above the tessellated Cornell box's lamp sees through the 1 cm gap, below
        // every 2 x 2 ray and where the ceiling's cosine weights most. probe_grazing_corner_rays:
        // only on a piece near the point's horizon whose kernel is steep there (kGrazing*).
        bool cornered = false;
        if ((o.probe_corner_rays || o.probe_grazing_corner_rays) && !below && weight_max > 0.0) {
            const DVec3 centroid = polygonCentroid(loop);
            double corner_max = 0.0;
            DVec3 corner_point(0.0);
            for (const DVec3& c : loop) {
                const DVec3 q = c + 0.0625 * (centroid - c);
                const double w = kernel(q);
                if (w > corner_max) corner_max = w, corner_point = q;
            }
            const DVec3 to_corner = corner_point - point;
            const bool wanted =
                o.probe_corner_rays
                    ? corner_max > weight_max
                    : corner_max > kGrazingKernelRatio * weight_max &&
                          glm::dot(normal, to_corner) < kGrazingElevation * glm::length(to_corner);
            if (wanted) {
                cornered = true;
                points.push_back(corner_point);
                weights.push_back(0.0);  // not in the estimate
            }
        }
        for (DVec3& q : points) q += lift * loop_normal;
        double open_weight = 0.0;
        open = static_cast<int>(s.rays->countOpenFrom(origin, points, weights, open_weight));
        total = static_cast<int>(points.size());
        // No kernel at any sample (a piece edge-on, no corner ray then): count them alike.
        visible = weight_sum > 0.0 ? open_weight / weight_sum : total > 0 ? double(open) / total : 0.0;
        if (counters) counters->rays += points.size();
        return cornered;
    }

    // A piece whose rays disagree (a shadow edge crosses it) is opened until its radius is
    // below probe_visibility_ratio x its distance: a fixed 2x2 grid would give steps of 1/4
    // of its light, and a penumbra narrower than the grid would be lost altogether.
    bool fineEnough(const DVec3& centroid, double radius, bool coarse) const {
        return radius <= (coarse ? o.probe_visibility_ratio : link_visibility_ratio) *
                             glm::length(centroid - point);
    }
    // Unanimous rays are trusted only on pieces below probe_visibility_coarse x distance: a
    // sliver of light between the rays of a larger piece would read as black (a penumbra at 0).
    bool coarseEnough(const DVec3& centroid, double radius, bool emitter) const {
        return radius <= coarseRatio(emitter) * glm::length(centroid - point);
    }
    double coarseRatio(bool emitter) const {
        return o.probe_visibility_coarse * (emitter ? kEmitterCoarseFactor : 1.0);
    }

    // Light from the polygon `loop` of radiosity b, split for visibility only (a leaf's
    // radiosity is uniform over it).
    // `suspect`: levels a piece is still split below a partial ancestor though its own rays
    // agree (an edge within a quarter side of a piece's border passes between its rays).
    // `known_f`: the piece's form factor when the caller has it (>= 0).
    void gatherPiece(std::span<const DVec3> loop, const DVec3& loop_normal, const DVec3& b, int splits,
                     int suspect, bool emitter, double known_f = -1.0) {
        const double f = known_f >= 0.0 ? known_f : pointPolygonFormFactor(point, normal, loop, loop_normal);
        if (counters && known_f < 0.0) ++counters->form_factors;
        if (!(f > 0.0)) return;
        if (!use_rays) {
            sum += f * b;
            return;
        }
        int open = 0, total = 0;
        double visible = 0.0;
        const bool cornered = castVisibility(loop, loop_normal, open, total, visible);
        const bool partial = open > 0 && open < total;
        if (partial) suspect = kSuspectLevels;
        // Neither rule can split past these limits: skip the piece's geometry then.
        const bool coarse = coarseFor(emitter);
        const int coarse_splits = coarse ? kMaxCoarseSplits : 0;
        const bool suspect_splits = suspect > 0 && splits < (coarse ? kMaxVisibilitySplits : max_visibility_splits);
        if (splits < coarse_splits || suspect_splits) {
            // The centroid and radius setElementGeometry would give, without the rest of it.
            const DVec3 centroid = polygonCentroid(loop);
            double radius = 0.0;
            for (const DVec3& p : loop) radius = std::max(radius, glm::length(p - centroid));
            const bool coarse_split = splits < coarse_splits && !coarseEnough(centroid, radius, emitter);
            if (coarse_split || (suspect_splits && !fineEnough(centroid, radius, coarse))) {
                if (loop.size() == 4) {
                    QuadChildren children;
                    splitQuad(loop, children);
                    for (size_t c = 0; c < children.count; ++c)
                        gatherPiece(children.loops[c], loop_normal, b, splits + 1, suspect - 1, emitter);
                } else {
                    for (const std::vector<DVec3>& child : splitPolygon(loop))
                        gatherPiece(child, loop_normal, b, splits + 1, suspect - 1, emitter);
                }
                return;
            }
        }
        // A shadow edge crosses the piece and no rule splits it further: with probe_corner_rays
        // its visible share from twice the rays a side (2 x 2 rays read the bottom half of a
        // tile split by its corner ray as half hidden where a quarter is: the ceiling above the
        // lamp went from +14 % to -9 %, to +2 % with this).
        if (partial && (o.probe_corner_rays || cornered))
            castVisibility(loop, loop_normal, open, total, visible, 2 * std::max(2, o.probe_samples));
        if (counters) ++counters->pieces;
        sum += f * visible * b;
    }

    // An inner element read whole brings f B with B its leaves' area mean, where the light is
    // sum f_i B_i: off by about the spread of its children's B times how much f varies over
    // it (radius / distance). Opened when that product is above kSmoothOpening, without
    // rays below an element whose own rays settled its visibility. (A wall read in quarters
    // from a lamp under a ceiling came out 5 % dark: its bright top half has the smaller form
    // factor.) Only without the coarse rule, whose opening is finer anyway.
    bool radiosityVaries(const Element& e, double distance) const {
        if (coarse_rule || !(distance > 0.0)) return false;
        return childRadiositySpread(s, e) * e.radius > kSmoothOpening * maxChannel(e.radiosity) * distance;
    }

    // The form factor of the next element visited, when the caller has computed it
    // (pointPolygonFormFactor at this point and normal; -1: not known). Used once.
    double known_form_factor = -1.0;

    void visit(uint32_t index) {
        const double known_f = known_form_factor;
        known_form_factor = -1.0;
        const Element& e = s.elements[index];
        if (!(maxChannel(e.radiosity) > 0.0)) return;  // B >= 0: an inner zero means all zero
        if (!facesPoint(e)) return;
        const PolygonView poly = polygonOf(s, e);
        const DVec3& p = point;
        const double distance = glm::length(e.centroid - p);
        const bool emitter = emitsMostOfItsLight(e);
        const bool coarse = coarseFor(emitter);
        const double opening = use_rays && (coarse || coarse_opening) ? std::min(o.probe_opening, coarseRatio(emitter))
                                                  : o.probe_opening;
        if (!e.isLeaf() && e.radius > opening * distance) {
            for (uint32_t c = 0; c < e.child_count; ++c) visit(e.first_child + c);
            return;
        }
        if (e.isLeaf()) {
            gatherPiece(poly.vertices, e.normal, e.radiosity, 0, 0, emitter, known_f);
            return;
        }
        const bool varies = radiosityVaries(e, distance);
        if (!use_rays && varies) {
            for (uint32_t c = 0; c < e.child_count; ++c) visit(e.first_child + c);
            return;
        }
        const double f = known_f >= 0.0 ? known_f : pointPolygonFormFactor(p, normal, poly.vertices, e.normal);
        if (counters && known_f < 0.0) ++counters->form_factors;
        if (!(f > 0.0)) return;
        if (!use_rays) {
            sum += f * e.radiosity;
            return;
        }
        int open = 0, total = 0;
        double visible = 0.0;
        castVisibility(poly.vertices, e.normal, open, total, visible);
        if (open > 0 && open < total && !fineEnough(e.centroid, e.radius, coarse)) {
            // Partly hidden: the children carry their own radiosity, so open them.
            for (uint32_t c = 0; c < e.child_count; ++c) visit(e.first_child + c);
            return;
        }
        if (varies && visible > 0.0) {
            // Its rays settled its visibility: its children bring their own light with it.
            const DVec3 before = sum;
            sum = DVec3(0.0);
            use_rays = false;
            for (uint32_t c = 0; c < e.child_count; ++c) visit(e.first_child + c);
            use_rays = true;
            sum = before + visible * sum;
            return;
        }
        if (counters) ++counters->pieces;
        sum += f * visible * e.radiosity;
    }

    // Every root, the faintest read by a few rays among them (ReadoutOptions::probe_faint_share).
    // Roots are gathered brightest first by a bound on their unoccluded light (form factor
    // times brightest leaf); once the bounds of those left sum to at most `faint_share` of the
    // light gathered so far, the rest (the faint tail) is estimated from at most
    // kFaintTailRays of them, one ray at the centre of each, which moves the point by at most
    // that share of its light. Seen from a point among furniture most roots are far, small and
    // hidden, and in a building most of them are in other rooms: a ray each for the tail was
    // O(roots) rays a point.
    struct RootLight {
        uint32_t root = 0;
        double form_factor = 0.0;  // exact, or the far-field kernel (far_field)
        double bound = 0.0;        // form_factor x the brightest leaf's radiosity (max channel)
        bool far_field = false;
        bool visited = false;
    };
    std::vector<RootLight> root_light{};
    std::vector<Ranked> ranked{};  // bounds and indices into root_light
    void visitRoots(double faint_share) {
        if (!use_rays || !(faint_share > 0.0)) {
            for (uint32_t r = 0; r < s.root_count; ++r) visit(r);
            return;
        }
        root_light.clear();
        ranked.clear();
        double left = 0.0;
        for (uint32_t r = 0; r < s.root_count; ++r) {
            const Element& e = s.elements[r];
            if (!(maxChannel(e.radiosity) > 0.0) || !facesPoint(e)) continue;
            const PolygonView poly = polygonOf(s, e);
            double f = farFormFactor(point, normal, e, poly.vertices);
            const bool far_field = f >= 0.0;
            if (!far_field) {
                f = pointPolygonFormFactor(point, normal, poly.vertices, e.normal);
                if (counters) ++counters->form_factors;
            }
            if (!(f > 0.0)) continue;
            ranked.push_back({f * brightestLeaf(r), static_cast<uint32_t>(root_light.size())});
            root_light.push_back({r, f, ranked.back().light, far_field});
            left += ranked.back().light;
        }
        // Brightest first (ties by root: root_light is in root order) from a heap: most points
        // stop after a few hundred roots.
        std::make_heap(ranked.begin(), ranked.end(), dimmer);
        for (auto end = ranked.end(); end != ranked.begin() && left > faint_share * maxChannel(sum);) {
            std::pop_heap(ranked.begin(), end, dimmer);
            RootLight& light = root_light[(--end)->k];
            left -= light.bound;
            light.visited = true;
            known_form_factor = light.far_field ? -1.0 : light.form_factor;
            visit(light.root);
        }
        gatherFaintTail();
    }
    // The roots not visited, in root order: each one's light f V B with V from one ray at its
    // centre, or, when there are more than kFaintTailRays, that many of them chosen in
    // proportion to their bounds (systematic sampling along root order, which runs mostly
    // through the scene's meshes in turn), each standing for a step of the tail's bound.
    static constexpr size_t kFaintTailRays = 64;
    void gatherFaintTail() {
        size_t count = 0;
        double total = 0.0;
        for (const RootLight& light : root_light)
            if (!light.visited) ++count, total += light.bound;
        if (count == 0 || !(total > 0.0)) return;
        const auto centreRay = [&](const Element& e) {
            int open = 0, rays = 0;
            double visible = 0.0;
            castVisibility(polygonOf(s, e).vertices, e.normal, open, rays, visible, 1);
            if (counters) ++counters->pieces;
            return visible;
        };
        if (count <= kFaintTailRays) {
            for (const RootLight& light : root_light) {
                if (light.visited) continue;
                const Element& e = s.elements[light.root];
                sum += light.form_factor * centreRay(e) * e.radiosity;
            }
            return;
        }
        const double step = total / static_cast<double>(kFaintTailRays);
        double next = 0.5 * step, before = 0.0;
        for (const RootLight& light : root_light) {
            if (light.visited) continue;
            const double after = before + light.bound;
            size_t samples = 0;
            for (; next < after; next += step) ++samples;
            before = after;
            if (samples == 0) continue;
            const Element& e = s.elements[light.root];
            // Its light f V B over its bound, times the steps of the tail's bound that landed on it.
            sum += (static_cast<double>(samples) * step * centreRay(e) * light.form_factor / light.bound) * e.radiosity;
        }
    }
    // The element's front faces the point and some of it is above the point's horizon.
    bool facesPoint(const Element& e) const {
        const PolygonView poly = polygonOf(s, e);
        if (!(glm::dot(e.normal, point - poly.vertices[0]) > 0.0)) return false;
        for (const DVec3& v : poly.vertices)
            if (glm::dot(normal, v - point) > 0.0) return true;
        return false;
    }
    double brightestLeaf(uint32_t index) const {
        const Element& e = s.elements[index];
        if (e.isLeaf()) return maxChannel(e.radiosity);
        double most = 0.0;
        for (uint32_t c = 0; c < e.child_count; ++c) most = std::max(most, brightestLeaf(e.first_child + c));
        return most;
    }
};

// Calls f(root) for every root whose polygon may lie within `reach` of `p`, in root order: down
// the cluster tree's boxes when the solution has one (a point's lift looked at every root, which
// in a building of half a million roots cost more than the point's own gather), else every root.
template <class F>
inline void forRootsNear(const Solution& s, const DVec3& p, double reach, F&& f) {
    if (s.clusters.empty() || s.clusters[0].member_count != s.root_count) {
        for (uint32_t r = 0; r < s.root_count; ++r) f(r);
        return;
    }
    thread_local std::vector<uint32_t> found, stack;
    found.clear();
    stack.assign(1, 0);
    while (!stack.empty()) {
        const Cluster& c = s.clusters[stack.back()];
        stack.pop_back();
        if (!contains(c.box, p, reach)) continue;
        if (c.isLeaf()) {
            for (uint32_t k = 0; k < c.member_count; ++k) {
                const uint32_t r = s.cluster_members[c.first_member + k];
                const Element& e = s.elements[r];
                if (glm::length(e.centroid - p) <= e.radius + reach) found.push_back(r);
            }
        } else {
            stack.push_back(c.first_child);
            stack.push_back(c.first_child + 1);
        }
    }
    std::sort(found.begin(), found.end());
    for (const uint32_t r : found) f(r);
}

// A point on a surface (a vertex) lies in the planes of the polygons around it, where the
// point form factor is degenerate (a wall seen edge-on from the edge of the floor gives
// nothing instead of half the sky). The point is moved a lift off every root polygon it
// touches, along the sum of their normals: the limit from inside the corner, the same for
// every face that shares the point.
inline void addLiftDirection(const Solution& solution, uint32_t root, const DVec3& point, double lift,
                             DVec3& direction) {
    const Element& e = solution.elements[root];
    const PolygonView poly = polygonOf(solution, e);
    const double height = glm::dot(e.normal, point - poly.vertices[0]);
    if (height <= -lift || height >= lift) return;
    if (pointPolygonDistance(point, poly) < lift) direction += e.normal;
}

// Only polygons on the point's side lift it: one facing (all but) opposite `normal` (the back of a
// one-sided face the probe sits on, the other side of a two-sided one) would move it to where
// that face's front is seen.
inline DVec3 liftOffSurfaces(const Solution& solution, const DVec3& point, const DVec3& normal, double lift) {
    DVec3 direction(0.0);
    forRootsNear(solution, point, 2.0 * lift, [&](uint32_t r) {
        if (glm::dot(solution.elements[r].normal, normal) >= -0.99) addLiftDirection(solution, r, point, lift, direction);
    });
    return point + lift * direction;
}

// The direction into the polygon that triangle t of `mesh` belongs to, from a point of that
// triangle within `near` of its outline, in the face's plane (unit normal `normal`), scaled so
// that a step of length L along it leaves the point at least L from the line of each edge of
// the outline within `near` of it; zero inside. Towards the triangle's centroid (where
// tools/vertex_probes nudges a vertex's reference: at a window's corner the lintel's shadow
// starts there, and the light depends on the way in; a polygon's centroid can lie beyond a roof
// the polygon reaches under), or where that runs within kMinSine of an edge beside the point (a
// sliver along the outline, a reflex corner), along the bisector of those edges' inward normals.
// The outline, not the triangle's own edges: surfaces meet a face along its outline, and a step
// towards a sliver's centroid kept a point on its long edge within a fraction of the step of the
// outline it lies along. A polygon's triangles are consecutive (the importers cut polygons in
// order); an edge two of them share is inside.
inline constexpr double kMinSine = 0.05;
inline DVec3 intoPolygon(const Mesh& mesh, uint32_t t, const DVec3& normal, const DVec3& point, double near) {
    uint32_t first = t, last = t + 1;
    if (mesh.triangle_polygon.size() == mesh.triangles.size()) {
        while (first > 0 && mesh.triangle_polygon[first - 1] == mesh.triangle_polygon[t]) --first;
        while (last < mesh.triangles.size() && mesh.triangle_polygon[last] == mesh.triangle_polygon[t]) ++last;
    }
    const auto corners = [&](uint32_t u) {
        const UVec3& o = mesh.triangles[u];
        return std::array<uint32_t, 3>{o.x, o.y, o.z};
    };
    const auto inside = [&](uint32_t u, uint32_t i, uint32_t j) {
        for (uint32_t w = first; w < last; ++w) {
            if (w == u) continue;
            const std::array<uint32_t, 3> c = corners(w);
            const auto has = [&](uint32_t k) { return c[0] == k || c[1] == k || c[2] == k; };
            if (has(i) && has(j)) return true;
        }
        return false;
    };
    std::array<DVec3, 4> inward{};
    size_t count = 0;
    DVec3 sum(0.0);
    for (uint32_t u = first; u < last; ++u) {
        const std::array<uint32_t, 3> c = corners(u);
        const std::array<DVec3, 3> q{DVec3(mesh.positions[c[0]]), DVec3(mesh.positions[c[1]]), DVec3(mesh.positions[c[2]])};
        for (size_t k = 0; k < 3 && count < inward.size(); ++k) {
            const DVec3 edge = q[(k + 1) % 3] - q[k];
            const double length = glm::length(edge);
            const DVec3 across = glm::cross(normal, edge);
            if (!(length > 0.0) || !(glm::length(across) > 0.0)) continue;
            DVec3 in = glm::normalize(across);
            if (glm::dot(in, q[(k + 2) % 3] - q[k]) < 0.0) in = -in;
            const double along = glm::dot(point - q[k], edge) / length;
            if (std::abs(glm::dot(point - q[k], in)) > near || along < -near || along > length + near) continue;
            if (inside(u, c[k], c[(k + 1) % 3])) continue;
            inward[count++] = in;
            sum += in;
        }
    }
    if (count == 0) return DVec3(0.0);
    const auto least = [&](const DVec3& d) {
        double m = 1.0;
        for (size_t k = 0; k < count; ++k) m = std::min(m, glm::dot(d, inward[k]));
        return m;
    };
    const std::array<uint32_t, 3> own = corners(t);
    DVec3 to_centre =
        (DVec3(mesh.positions[own[0]]) + DVec3(mesh.positions[own[1]]) + DVec3(mesh.positions[own[2]])) / 3.0 - point;
    to_centre -= glm::dot(to_centre, normal) * normal;
    if (glm::length(to_centre) > 0.0) {
        const DVec3 d = glm::normalize(to_centre);
        if (least(d) >= kMinSine) return d / least(d);
    }
    if (!(glm::length(sum) > 0.0)) return DVec3(0.0);
    const DVec3 d = glm::normalize(sum);
    return d / std::max(least(d), kMinSine);
}

// liftOffSurfaces at a point of a known face (`face`: its triangle's corners, facing `normal`):
// off the polygons of its own plane and off those touching the point that have some of the face
// in front of them (the floor under a wall's foot, the wall beside a floor's edge). A wall's own bottom
// face and a two-sided floor's underside touch its foot too, facing away from it: lifted off them
// as well, the point went under the floor and read the light there.
inline DVec3 liftOffFacingSurfaces(const Solution& solution, const DVec3& point, const DVec3& normal, double lift,
                                   const std::array<DVec3, 3>& face) {
    DVec3 direction(0.0);
    forRootsNear(solution, point, 2.0 * lift, [&](uint32_t r) {
        const Element& e = solution.elements[r];
        const DVec3& origin = polygonOf(solution, e).vertices[0];
        // Its own plane (the face and its neighbours there), as liftOffSurfaces lifts it.
        const bool own_plane = glm::dot(e.normal, normal) > 1.0 - 1e-6;
        if (!own_plane &&
            std::none_of(face.begin(), face.end(), [&](const DVec3& v) { return glm::dot(e.normal, v - origin) > lift; }))
            return;
        addLiftDirection(solution, r, point, lift, direction);
    });
    return point + lift * direction;
}

// Punctual lights' (those whose direct light is baked: not Light::realtime) and the sky's direct light at a point on triangle `triangle` of Scene::meshes[mesh]
// (punctual_lights.h), its shadow rays cast from kPunctualLifts lifts into its polygon where the
// point lies on the polygon's outline (intoPolygon) and off the face: the limit from inside the face,
// as a vertex's value is. From the point itself a ray leaving through a surface the point lies
// on (a wall's foot on a floor, the light under the floor) crosses it within the ray caster's
// start offset (one lift), and the light under the floor reached the wall's foot, and through
// the edge correction the floor beside it.
inline constexpr double kPunctualLifts = 4.0;
// `sky`: the sky's quadrature at the point; null leaves the sky out (a link read takes it from its
// leaf's corners, skyInElement).
// Where the shadow rays of a point on that triangle start (the point itself off any triangle).
inline DVec3 punctualFrom(const Solution& solution, uint32_t mesh, uint32_t triangle, const DVec3& point,
                          const DVec3& normal) {
    const Scene* scene = solution.scene;
    if (!scene || mesh >= scene->meshes.size() || triangle >= scene->meshes[mesh].triangles.size()) return point;
    const double step = kPunctualLifts * kLift * solution.scene_extent;
    return point + step * (intoPolygon(scene->meshes[mesh], triangle, normal, point, step) + normal);
}

inline DVec3 punctualInside(const Solution& solution, uint32_t mesh, uint32_t triangle, const DVec3& point,
                            const DVec3& normal, const SkyQuadrature* sky) {
    const Scene* scene = solution.scene;
    if (!scene || (scene->lights.empty() && (!sky || !scene->sky.shines()))) return DVec3(0.0);
    const DVec3 from = punctualFrom(solution, mesh, triangle, point, normal);
    const DVec3 lights = punctualIrradiance(scene->lights, solution.rays.get(), from, normal, nullptr, mesh, LightSet::Baked);
    return sky ? lights + skyIrradiance(scene->sky, solution.rays.get(), from, normal, *sky) : lights;
}

}  // namespace gather
}  // namespace radbake
