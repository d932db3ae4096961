#pragma once
// Per-vertex attributes the exporters share.
#include <vector>

#include "core/math.h"
#include "scene/scene.h"

namespace radbake {

// Unit normal per vertex: the mesh's own normals when it has one per vertex, otherwise the
// area-weighted sum of the normals of the triangles using the vertex. A vertex whose sum
// vanishes (unused, or only degenerate triangles) gets +Z, so files always hold unit normals.
std::vector<Vec3> vertexNormals(const Mesh& mesh);

// The baked value of every vertex of `mesh`, with missing or non-finite entries as 0;
// `replaced` counts the entries that were not finite numbers.
std::vector<Vec3> finiteVertexValues(const Mesh& mesh, const std::vector<Vec3>* values, size_t& replaced);

}  // namespace radbake
