// Lightmap meshes: chart faces back in world space with their atlas UVs.
#include "bake/lightmap_mesh.h"

#include <map>
#include <utility>

namespace radbake {

std::vector<LightmapMesh> lightmapMeshes(const Scene& scene, const LightmapLayout& layout) {
    std::vector<LightmapMesh> meshes(scene.meshes.size());
    for (const LightmapChart& chart : layout.charts) {
        if (chart.atlas < 0 || chart.mesh >= meshes.size()) continue;
        const LightmapAtlas& atlas = layout.atlases[chart.atlas];
        LightmapMesh& out = meshes[chart.mesh];
        // Faces of one chart share corners: the same plane point is one vertex (points
        // computed from the same float position are bit-identical).
        std::map<std::pair<double, double>, uint32_t> ids;
        const auto vertex = [&](const DVec2& p) {
            const auto [it, added] = ids.emplace(std::make_pair(p.x, p.y), static_cast<uint32_t>(out.positions.size()));
            if (added) {
                const DVec2 texel = chart.atlasTexel(p);
                out.positions.push_back(Vec3(chart.worldPoint(p)));
                out.uv.push_back(Vec2(static_cast<float>(texel.x / atlas.width), static_cast<float>(texel.y / atlas.height)));
                out.atlas.push_back(chart.atlas);
            }
            return it->second;
        };
        for (const ChartFace& face : chart.faces) {
            std::vector<uint32_t> loop;
            for (const DVec2& p : face.p_plane) loop.push_back(vertex(p));
            for (size_t k = 1; k + 1 < loop.size(); ++k) {
                out.triangles.push_back(UVec3(loop[0], loop[k], loop[k + 1]));
                out.source_triangle.push_back(face.triangle);
            }
        }
    }
    return meshes;
}

}  // namespace radbake
