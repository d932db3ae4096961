#pragma once
// The scene's geometry re-expressed for the lightmap UV set (TEXCOORD_1): each chart face
// becomes a fan of triangles over vertices of its own chart, so vertices are split at chart
// seams, at the cuts of split charts and at seams of the source UVs (Mesh::uv0), as a second
// UV set requires.
#include <cstdint>
#include <span>
#include <vector>

#include "bake/lightmap_charts.h"
#include "core/math.h"

namespace radbake {

struct LightmapMesh {
    std::vector<Vec3> positions;           // world space
    std::vector<Vec2> uv;                  // in the chart's atlas: u right, v down from the top row
    std::vector<int> atlas;                // per vertex, the atlas its uv refers to
    std::vector<UVec3> triangles;          // counter-clockwise from the front, like the source
    std::vector<uint32_t> source_triangle; // per triangle: index into the source mesh's triangles
    // Per vertex: where it lies on the source mesh, as barycentric weights over the corners of
    // a source triangle it lies on, so any per-source-vertex attribute (baked value, normal)
    // can be carried over (interpolateSource).
    std::vector<UVec3> source_corners;     // source vertex indices
    std::vector<Vec3> barycentric;         // weights of those corners, summing to 1
};

// The source attribute (one value per source vertex: baked value, normal, UV) at lightmap vertex v.
Vec3 interpolateSource(const LightmapMesh& mesh, size_t v, std::span<const Vec3> per_source_vertex);
Vec2 interpolateSource(const LightmapMesh& mesh, size_t v, std::span<const Vec2> per_source_vertex);

// One LightmapMesh per scene mesh (empty for meshes without charts). Charts must be placed.
std::vector<LightmapMesh> lightmapMeshes(const Scene& scene, const LightmapLayout& layout);

}  // namespace radbake
