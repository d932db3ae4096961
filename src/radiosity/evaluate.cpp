// Evaluation of the solved hierarchy at arbitrary points: probes and baked vertices.
#include <algorithm>
#include <array>

#include "radiosity/elements.h"
#include "radiosity/form_factor.h"
#include "radiosity/punctual_lights.h"
#include "radiosity/refine.h"
#include "radiosity/solution.h"
#include "visibility/ray_caster.h"

namespace radbake {
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

struct Gatherer {
    const Solution& s;
    DVec3 point, normal, origin;
    double lift;
    std::vector<DVec3> points;
    DVec3 sum{0.0};

    double visibility(const Element& e) {
        if (!s.rays) return 1.0;
        elementPoints(polygonOf(s, e).vertices, s.options.probe_samples, points);
        int open = 0;
        for (const DVec3& q : points) open += s.rays->segmentBlocked(origin, q + lift * e.normal) ? 0 : 1;
        return points.empty() ? 0.0 : static_cast<double>(open) / static_cast<double>(points.size());
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
        if (!e.isLeaf() && e.radius > s.options.probe_opening * distance) {
            for (uint32_t c = 0; c < e.child_count; ++c) visit(e.first_child + c);
            return;
        }
        const double f = pointPolygonFormFactor(p, normal, poly.vertices, e.normal);
        if (!(f > 0.0)) return;
        sum += f * visibility(e) * e.radiosity;
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

DVec3 probeIrradiance(const Solution& solution, const DVec3& point_on_surface, const DVec3& normal) {
    if (solution.elements.empty()) return DVec3(0.0);
    const double lift = kLift * solution.scene_extent;
    const DVec3 point = liftOffSurfaces(solution, point_on_surface, lift);
    Gatherer g{solution, point, normal, point + lift * normal, lift, {}, DVec3(0.0)};
    for (uint32_t r = 0; r < solution.root_count; ++r) g.visit(r);
    DVec3 h = g.sum;
    if (solution.scene && !solution.scene->lights.empty())
        h += punctualIrradiance(solution.scene->lights, solution.rays.get(), point_on_surface, normal);
    return h;
}

}  // namespace radbake
