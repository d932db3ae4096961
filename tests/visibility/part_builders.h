#pragma once
// Literal convex parts and polygons for the visibility tests and benchmarks (independent of
// the geometry stage's part builder, so these tests check the visibility code alone).
#include <array>
#include <cmath>
#include <vector>

#include "geometry/types.h"

namespace radbake::testing {

inline ConvexPart orientedBoxPart(const DVec3& center, const std::array<DVec3, 3>& axes,
                                  const DVec3& half) {
    ConvexPart part;
    part.closed = true;
    for (int c = 0; c < 8; ++c) {
        DVec3 p = center;
        for (int i = 0; i < 3; ++i) p += axes[i] * (((c >> i) & 1) ? half[i] : -half[i]);
        part.vertices.push_back(p);
        part.aabb.add(p);
    }
    for (int i = 0; i < 3; ++i) {
        for (double s : {-1.0, 1.0}) {
            const DVec3 n = s * axes[i];
            part.planes.push_back(Plane{n, -(glm::dot(n, center) + half[i])});
        }
    }
    part.obb.center = center;
    part.obb.axes = axes;
    part.obb.half_extents = half;
    return part;
}

inline ConvexPart boxPart(const DVec3& min, const DVec3& max) {
    return orientedBoxPart(0.5 * (min + max), {DVec3(1, 0, 0), DVec3(0, 1, 0), DVec3(0, 0, 1)},
                           0.5 * (max - min));
}

// Flat part from a convex planar loop (any winding).
inline ConvexPart flatPart(const std::vector<DVec3>& loop) {
    ConvexPart part;
    part.closed = false;
    part.vertices = loop;
    DVec3 newell(0.0), centroid(0.0);
    for (size_t i = 0; i < loop.size(); ++i) {
        const DVec3& a = loop[i];
        const DVec3& b = loop[(i + 1) % loop.size()];
        newell += glm::cross(a, b);
        centroid += a;
        part.aabb.add(a);
    }
    centroid /= static_cast<double>(loop.size());
    const DVec3 n = glm::normalize(newell);
    part.planes.push_back(Plane{n, -glm::dot(n, centroid)});
    // A flat OBB: u along the first edge, v = n x u, extents from the projections.
    const DVec3 u = glm::normalize(loop[1] - loop[0]);
    const DVec3 v = glm::cross(n, u);
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    for (const DVec3& p : loop) {
        const DVec3 d = p - centroid;
        u0 = std::min(u0, glm::dot(d, u));
        u1 = std::max(u1, glm::dot(d, u));
        v0 = std::min(v0, glm::dot(d, v));
        v1 = std::max(v1, glm::dot(d, v));
    }
    part.obb.center = centroid + u * (0.5 * (u0 + u1)) + v * (0.5 * (v0 + v1));
    part.obb.axes = {u, v, n};
    part.obb.half_extents = DVec3(0.5 * (u1 - u0), 0.5 * (v1 - v0), 0.0);
    return part;
}

// Axis-aligned rectangle in the plane coordinate[axis] = level.
inline std::vector<DVec3> rectangle(int axis, double level, double a0, double a1, double b0,
                                    double b1) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    std::vector<DVec3> loop(4, DVec3(0.0));
    const double us[4] = {a0, a1, a1, a0};
    const double vs[4] = {b0, b0, b1, b1};
    for (int i = 0; i < 4; ++i) {
        loop[i][axis] = level;
        loop[i][u] = us[i];
        loop[i][v] = vs[i];
    }
    return loop;
}

inline Aabb boxOfPoints(const std::vector<DVec3>& points) {
    Aabb box;
    for (const DVec3& p : points) box.add(p);
    return box;
}

}  // namespace radbake::testing
