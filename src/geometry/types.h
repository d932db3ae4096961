#pragma once
// Plain geometric structs shared by parts, shafts and the solver. Positions are float as
// stored in the Scene; planes and tests are evaluated in double so that conservative tests
// can bound their own rounding.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/math.h"

namespace radbake {

struct Aabb {
    DVec3 min{std::numeric_limits<double>::max()};
    DVec3 max{-std::numeric_limits<double>::max()};

    bool empty() const { return min.x > max.x; }
    void add(const DVec3& p) { min = glm::min(min, p); max = glm::max(max, p); }
    void add(const Aabb& b) { min = glm::min(min, b.min); max = glm::max(max, b.max); }
    DVec3 center() const { return 0.5 * (min + max); }
    DVec3 extent() const { return max - min; }
};

// Oriented box: center + sum_i t_i * axes[i] * half_extents[i], t_i in [-1, 1].
// axes are orthonormal and right-handed; a flat part's box has half_extents.z == 0 and
// axes[2] == its polygon's normal.
struct Obb {
    DVec3 center{0.0};
    std::array<DVec3, 3> axes{DVec3(1, 0, 0), DVec3(0, 1, 0), DVec3(0, 0, 1)};
    DVec3 half_extents{0.0};
};

// Points p with dot(normal, p) + offset <= 0 are inside; normal points out and is unit length.
struct Plane {
    DVec3 normal{0.0, 0.0, 1.0};
    double offset = 0.0;
    double eval(const DVec3& p) const { return glm::dot(normal, p) + offset; }
};

// A convex piece of the scene's geometry: a closed convex polytope (closed == true), or a
// flat convex polygon (closed == false, vertices in order around its normal).
struct ConvexPart {
    std::vector<DVec3> vertices;  // hull vertices (closed) or polygon loop (flat)
    std::vector<Plane> planes;    // closed: outward face planes; flat: the supporting plane
    // closed: faces[i] is the loop of plane i (indices into vertices, counter-clockwise seen
    // from outside); flat: empty (the loop is `vertices` itself, around planes[0].normal).
    std::vector<std::vector<uint32_t>> faces;
    bool closed = false;
    double area = 0.0;    // flat: polygon area; closed: surface area
    double volume = 0.0;  // closed: hull volume; flat: 0
    // How far the part may reach beyond the surface it stands for (a detected solid is its
    // mesh's hull, a merged plate is fitted within a plane tolerance). A conservative
    // occlusion test shrinks the part by this much before it claims anything.
    double inflation = 0.0;
    Aabb aabb;
    Obb obb;
    uint32_t mesh = 0;            // Scene::meshes index it came from
    // Its mesh lets light through (meshTransmittance > 0): a candidate that never occludes a
    // shaft on its own, so the rays that cross it weigh what it lets through.
    bool transmits = false;
    std::vector<uint32_t> polygons;  // source polygons of that mesh it covers
};

}  // namespace radbake
