#pragma once
// Convex hulls: 2D (monotone chain), 3D (quickhull), and the minimum-area enclosing
// rectangle of a 2D convex polygon (rotating calipers).
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/types.h"

namespace radbake {

// Indices of the hull vertices of `points`, counter-clockwise, without collinear points.
// Degenerate input: 1 or 2 indices (all points equal / collinear); empty for empty input.
std::vector<uint32_t> convexHull2d(std::span<const DVec2> points, double tolerance = 0.0);

struct Hull3 {
    // 3: a solid with faces; 2: all points coplanar (within tolerance); 1: collinear;
    // 0: one point; -1: no points. Faces/planes are filled only for dimension 3.
    int dimension = -1;
    std::vector<DVec3> vertices;                // the extreme points
    std::vector<std::vector<uint32_t>> faces;   // loops into vertices, CCW seen from outside,
                                                // coplanar triangles merged, collinear corners dropped
    std::vector<Plane> planes;                  // outward unit plane per face
    double volume = 0.0;
};

// Quickhull. `tolerance` is absolute: points within it of a face count as on it; when
// <= 0 a tolerance is derived from the input's extent and double rounding.
Hull3 quickhull(std::span<const DVec3> points, double tolerance = 0.0);

struct Rect2 {
    DVec2 center{0.0};
    DVec2 axis_u{1.0, 0.0};  // unit; axis_v = (-axis_u.y, axis_u.x)
    DVec2 half_extents{0.0};
    double area() const { return 4.0 * half_extents.x * half_extents.y; }
};

// Minimum-area rectangle enclosing a convex polygon given counter-clockwise (as
// convexHull2d returns it, as points). Handles 1 and 2 point inputs.
Rect2 minAreaRect(std::span<const DVec2> hull_ccw);

}  // namespace radbake
