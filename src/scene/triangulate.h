#pragma once
// Polygon triangulation shared by the scene readers (VRML, Assimp).
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"

namespace radbake {

// Appends triangles covering the polygon `loop` (indices into `positions`) to `out`, with the
// loop's winding, and returns how many it appended. Convex loops become a fan. Non-convex
// loops are ear-clipped in their dominant plane (Newell normal); collinear, duplicate and
// self-touching points are tolerated, zero-area slivers are left out, and a loop that no
// longer has a clean ear falls back to a fan, so the call always ends. Loops with fewer than
// three points append nothing.
size_t triangulatePolygon(const std::vector<Vec3>& positions, std::span<const uint32_t> loop, bool convex,
                          std::vector<UVec3>& out);

}  // namespace radbake
