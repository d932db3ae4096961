// Evaluation of the solved hierarchy at arbitrary points: probes and baked vertices.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "geometry/polygon.h"
#include "radiosity/elements.h"
#include "radiosity/evaluate_probe.h"
#include "radiosity/form_factor.h"
#include "radiosity/punctual_lights.h"
#include "radiosity/refine.h"
#include "radiosity/solution.h"
#include "visibility/ray_caster.h"

namespace radbake {

// The same arithmetic as splitPolygon's quad branch (elements.cpp), in the same order, so the
// same children to the bit: keep them in step; test_probe_split.cpp compares them.
void splitQuad(std::span<const DVec3> loop, QuadChildren& out) {
    const double len02 = glm::length(loop[1] - loop[0]) + glm::length(loop[3] - loop[2]);
    const double len13 = glm::length(loop[2] - loop[1]) + glm::length(loop[0] - loop[3]);
    if (len02 > 2.0 * len13 || len13 > 2.0 * len02) {
        const int a = len02 > len13 ? 0 : 1;
        const DVec3& p0 = loop[a];
        const DVec3& p1 = loop[(a + 1) % 4];
        const DVec3& p2 = loop[(a + 2) % 4];
        const DVec3& p3 = loop[(a + 3) % 4];
        const DVec3 m01 = 0.5 * (p0 + p1), m23 = 0.5 * (p2 + p3);
        out.loops[0] = {p0, m01, m23, p3};
        out.loops[1] = {m01, p1, p2, m23};
        out.count = 2;
        return;
    }
    const DVec3 centre = 0.25 * (loop[0] + loop[1] + loop[2] + loop[3]);
    for (size_t i = 0; i < 4; ++i) {
        const DVec3& v = loop[i];
        const DVec3 next_mid = 0.5 * (v + loop[(i + 1) % 4]);
        const DVec3 prev_mid = 0.5 * (v + loop[(i + 3) % 4]);
        out.loops[i] = {v, next_mid, centre, prev_mid};
    }
    out.count = 4;
}

// pointPolygonFormFactor (form_factor.cpp) for the common case of a quad wholly above the
// point's horizon, where its clipping keeps the loop as it is: the same operations in the same
// order (bit-identical answers), without the clip loop and its modulo indexing. Every other
// case goes to pointPolygonFormFactor. Keep in step with it; test_probe_split.cpp compares them.
double piecePointFormFactor(const DVec3& point, const DVec3& normal, std::span<const DVec3> source,
                            const DVec3& source_normal) {
    if (source.size() != 4) return pointPolygonFormFactor(point, normal, source, source_normal);
    if (!(glm::dot(source_normal, point - source[0]) > 0.0)) return 0.0;
    std::array<DVec3, 4> dirs;
    for (size_t i = 0; i < 4; ++i) {
        dirs[i] = source[i] - point;
        if (!(glm::dot(normal, dirs[i]) > 0.0)) return pointPolygonFormFactor(point, normal, source, source_normal);
    }
    double sum = 0.0;
    for (size_t i = 0; i < 4; ++i) {
        const DVec3& r0 = dirs[i];
        const DVec3& r1 = dirs[(i + 1) & 3];
        const DVec3 c = glm::cross(r0, r1);
        const double c_len = glm::length(c);
        if (!(c_len > 0.0)) continue;
        const double angle = std::atan2(c_len, glm::dot(r0, r1));
        sum += angle * glm::dot(normal, c) / c_len;
    }
    return std::abs(sum) / (2.0 * kPi);
}

namespace {

// Ray ends are lifted off their surfaces by this fraction of the scene's extent, so a point
// on the edge of a wall (a room corner) does not cast along the wall's own plane. Well above
// float rounding of coordinates (1e-7) and far below any lit feature.
constexpr double kLift = 1e-5;

// Points on the element where visibility is sampled: an n x n grid of cell centres.
void elementPoints(std::span<const DVec3> loop, int n, std::vector<DVec3>& out) {
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
constexpr int kMaxVisibilitySplits = 10;
// Below a leaf, pieces with agreeing rays are split for the coarse rule at most this many
// times: near a vertex in a room corner every neighbouring piece fails the rule, and splitting
// them all ten levels deep cost ~7 ms per vertex in the Cornell Box.
constexpr int kMaxCoarseSplits = 3;
// Pieces below a partly visible one keep splitting for this many levels even when their own
// rays agree, so an edge that slips between the rays of one level is found at the next.
constexpr int kSuspectLevels = 2;

struct Gatherer {
    const Solution& s;
    DVec3 point{0.0}, normal{0.0}, origin{0.0};
    double lift = 0.0;
    std::vector<DVec3> points{};
    DVec3 sum{0.0};
    ProbeCounters* counters = nullptr;

    // Unblocked fraction of an n x n grid of segments from the probe to the polygon.
    // Returns the open count in `open` and the ray count in `total`.
    void castVisibility(std::span<const DVec3> loop, const DVec3& loop_normal, int& open, int& total) {
        elementPoints(loop, std::max(2, s.options.probe_samples), points);
        for (DVec3& q : points) q += lift * loop_normal;
        open = static_cast<int>(s.rays->countOpenFrom(origin, points));
        total = static_cast<int>(points.size());
        if (counters) counters->rays += points.size();
    }

    // A piece whose rays disagree (a shadow edge crosses it) is opened until its radius is
    // below probe_visibility_ratio x its distance: a fixed 2x2 grid would give steps of 1/4
    // of its light, and a penumbra narrower than the grid would be lost altogether.
    bool fineEnough(const DVec3& centroid, double radius) const {
        return radius <= s.options.probe_visibility_ratio * glm::length(centroid - point);
    }
    // Unanimous rays are trusted only on pieces below probe_visibility_coarse x distance: a
    // sliver of light between the rays of a larger piece would read as black (a penumbra at 0).
    bool coarseEnough(const DVec3& centroid, double radius) const {
        return radius <= s.options.probe_visibility_coarse * glm::length(centroid - point);
    }

    // Light from the polygon `loop` of radiosity b, split for visibility only (a leaf's
    // radiosity is uniform over it).
    // `suspect`: levels a piece is still split below a partial ancestor though its own rays
    // agree (an edge within a quarter side of a piece's border passes between its rays).
    void gatherPiece(std::span<const DVec3> loop, const DVec3& loop_normal, const DVec3& b, int splits,
                     int suspect) {
        const double f = piecePointFormFactor(point, normal, loop, loop_normal);
        if (counters) ++counters->form_factors;
        if (!(f > 0.0)) return;
        if (!s.rays) {
            sum += f * b;
            return;
        }
        int open = 0, total = 0;
        castVisibility(loop, loop_normal, open, total);
        const bool partial = open > 0 && open < total;
        if (partial) suspect = kSuspectLevels;
        // Neither rule can split past these limits: skip the piece's geometry then.
        if (splits < kMaxVisibilitySplits && (splits < kMaxCoarseSplits || suspect > 0)) {
            // The centroid and radius setElementGeometry would give, without the rest of it.
            const DVec3 centroid = polygonCentroid(loop);
            double radius = 0.0;
            for (const DVec3& p : loop) radius = std::max(radius, glm::length(p - centroid));
            const bool coarse_split = splits < kMaxCoarseSplits && !coarseEnough(centroid, radius);
            if (coarse_split || (suspect > 0 && !fineEnough(centroid, radius))) {
                if (loop.size() == 4) {
                    QuadChildren children;
                    splitQuad(loop, children);
                    for (size_t c = 0; c < children.count; ++c)
                        gatherPiece(children.loops[c], loop_normal, b, splits + 1, suspect - 1);
                } else {
                    for (const std::vector<DVec3>& child : splitPolygon(loop))
                        gatherPiece(child, loop_normal, b, splits + 1, suspect - 1);
                }
                return;
            }
        }
        if (counters) ++counters->pieces;
        sum += f * (total > 0 ? static_cast<double>(open) / total : 0.0) * b;
    }

    void visit(uint32_t index) {
        const Element& e = s.elements[index];
        if (!(maxChannel(e.radiosity) > 0.0)) return;  // B >= 0: an inner zero means all zero
        const PolygonView poly = polygonOf(s, e);
        const DVec3& p = point;
        if (!(glm::dot(e.normal, p - poly.vertices[0]) > 0.0)) return;  // behind the element
        bool above = false;
        for (const DVec3& v : poly.vertices) above = above || glm::dot(normal, v - p) > 0.0;
        if (!above) return;  // wholly below the point's horizon
        const double distance = glm::length(e.centroid - p);
        const double opening = s.rays ? std::min(s.options.probe_opening, s.options.probe_visibility_coarse)
                                      : s.options.probe_opening;
        if (!e.isLeaf() && e.radius > opening * distance) {
            for (uint32_t c = 0; c < e.child_count; ++c) visit(e.first_child + c);
            return;
        }
        if (e.isLeaf()) {
            gatherPiece(poly.vertices, e.normal, e.radiosity, 0, 0);
            return;
        }
        const double f = piecePointFormFactor(p, normal, poly.vertices, e.normal);
        if (counters) ++counters->form_factors;
        if (!(f > 0.0)) return;
        if (!s.rays) {
            sum += f * e.radiosity;
            return;
        }
        int open = 0, total = 0;
        castVisibility(poly.vertices, e.normal, open, total);
        if (open > 0 && open < total && !fineEnough(e.centroid, e.radius)) {
            // Partly hidden: the children carry their own radiosity, so open them.
            for (uint32_t c = 0; c < e.child_count; ++c) visit(e.first_child + c);
            return;
        }
        if (counters) ++counters->pieces;
        sum += f * (total > 0 ? static_cast<double>(open) / total : 0.0) * e.radiosity;
    }
};

// A point on a surface (a vertex) lies in the planes of the polygons around it, where the
// point form factor is degenerate (a wall seen edge-on from the edge of the floor gives
// nothing instead of half the sky). The point is moved a lift off every root polygon it
// touches, along the sum of their normals: the limit from inside the corner, the same for
// every face that shares the point.
DVec3 liftOffSurfaces(const Solution& solution, const DVec3& point, double lift) {
    DVec3 direction(0.0);
    for (uint32_t r = 0; r < solution.root_count; ++r) {
        const Element& e = solution.elements[r];
        const PolygonView poly = polygonOf(solution, e);
        const double height = glm::dot(e.normal, point - poly.vertices[0]);
        if (height <= -lift || height >= lift) continue;
        if (pointPolygonDistance(point, poly) < lift) direction += e.normal;
    }
    return point + lift * direction;
}

}  // namespace

namespace {

DVec3 evaluate(const Solution& solution, const DVec3& point_on_surface, const DVec3& normal,
               ProbeCounters* counters) {
    if (solution.elements.empty()) return DVec3(0.0);
    const double lift = kLift * solution.scene_extent;
    const DVec3 point = liftOffSurfaces(solution, point_on_surface, lift);
    Gatherer g{.s = solution,
               .point = point,
               .normal = normal,
               .origin = point + lift * normal,
               .lift = lift,
               .counters = counters};
    for (uint32_t r = 0; r < solution.root_count; ++r) g.visit(r);
    DVec3 h = g.sum;
    if (solution.scene && !solution.scene->lights.empty())
        h += punctualIrradiance(solution.scene->lights, solution.rays.get(), point_on_surface, normal);
    return h;
}

}  // namespace

DVec3 probeIrradiance(const Solution& solution, const DVec3& point, const DVec3& normal) {
    return evaluate(solution, point, normal, nullptr);
}

DVec3 probeIrradianceCounted(const Solution& solution, const DVec3& point, const DVec3& normal,
                             ProbeCounters& counters) {
    return evaluate(solution, point, normal, &counters);
}

}  // namespace radbake
