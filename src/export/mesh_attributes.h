#pragma once
// Per-vertex attributes the exporters share.
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "export/lightmap_files.h"
#include "scene/scene.h"

namespace radbake {

// Unit normal per vertex: the mesh's own normals when it has one per vertex, otherwise the
// corner-angle-weighted sum of the normals of the triangles using the vertex: after splitHardEdges
// (scene/creases.h) those are the faces of its crease group, so a hard edge keeps each face's
// normal and a smooth surface is smooth. A vertex whose sum vanishes (unused, or only
// degenerate triangles) gets +Z, so files always hold unit normals.
std::vector<Vec3> vertexNormals(const Mesh& mesh);

// The baked value of every vertex of `mesh`, with missing or non-finite entries as 0;
// `replaced` counts the entries that were not finite numbers.
std::vector<Vec3> finiteVertexValues(const Mesh& mesh, const std::vector<Vec3>* values, size_t& replaced);

// True when `lightmaps` fits `scene`: one LightmapMesh per mesh, per-vertex arrays of one
// length, indices within their meshes, every atlas index naming a file and the three corners
// of each triangle in one atlas. Otherwise reports (internal error) and returns false.
bool checkLightmapsMatchScene(const Scene& scene, const LightmapFiles& lightmaps, Diagnostics& diagnostics);

// Unit normal per lightmap vertex: vertexNormals of the source mesh carried over with
// interpolateSource (smooth across a chart seam within a crease group, as the glb's mesh
// without lightmaps is).
std::vector<Vec3> lightmapVertexNormals(const Mesh& mesh, const LightmapMesh& lightmap_mesh);

// The baked value per lightmap vertex: interpolateSource over finiteVertexValues.
std::vector<Vec3> lightmapVertexValues(const Mesh& mesh, const LightmapMesh& lightmap_mesh,
                                       const std::vector<Vec3>* values, size_t& replaced);

}  // namespace radbake
