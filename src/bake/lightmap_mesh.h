#pragma once
// The scene's geometry re-expressed for the lightmap UV set (TEXCOORD_1): each chart face
// becomes a fan of triangles over vertices of its own chart, so vertices are split at chart
// seams and at the cuts of split charts, as a second UV set requires.
#include <cstdint>
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
};

// One LightmapMesh per scene mesh (empty for meshes without charts). Charts must be placed.
std::vector<LightmapMesh> lightmapMeshes(const Scene& scene, const LightmapLayout& layout);

}  // namespace radbake
