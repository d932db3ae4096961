#include "bake/lightmap_quantity.h"

#include <algorithm>
#include <limits>

#include "bake/chart_texels.h"

namespace radbake {
namespace {

Vec3 reflectanceOf(const Scene& scene, uint32_t mesh_index, uint32_t triangle) {
    const Mesh& mesh = scene.meshes[mesh_index];
    if (!mesh.polygon_reflectance.empty() && triangle < mesh.triangle_polygon.size())
        return mesh.polygon_reflectance[mesh.triangle_polygon[triangle]];
    return scene.materials[mesh.material].reflectance;
}

// Squared distance from `p` to the face's polygon, 0 on it.
double squaredDistance(const ChartFace& face, const DVec2& p) {
    if (onFace(face, p)) return 0.0;
    const std::vector<DVec2>& poly = face.p_plane;
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const DVec2 a = poly[j], ab = poly[i] - poly[j];
        const double t = glm::dot(ab, ab) > 0.0 ? std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0) : 0.0;
        const DVec2 d = p - (a + t * ab);
        best = std::min(best, glm::dot(d, d));
    }
    return best;
}

}  // namespace

const char* toString(LightmapQuantity quantity) {
    return quantity == LightmapQuantity::Radiance ? "radiance" : "irradiance";
}

void toReflectedRadiance(const Scene& scene, int padding, Lightmaps& lightmaps) {
    for (const LightmapChart& chart : lightmaps.layout.charts) {
        if (chart.atlas < 0 || chart.faces.empty()) continue;
        LightmapImage& image = lightmaps.images[static_cast<size_t>(chart.atlas)];
        std::vector<Vec3> reflectance;
        for (const ChartFace& face : chart.faces) reflectance.push_back(reflectanceOf(scene, chart.mesh, face.triangle));
        const bool uniform = std::all_of(reflectance.begin(), reflectance.end(),
                                         [&](const Vec3& r) { return r == reflectance.front(); });
        for (int ty = std::max(0, chart.y - padding); ty < std::min(image.height, chart.y + chart.height + padding); ++ty)
            for (int tx = std::max(0, chart.x - padding); tx < std::min(image.width, chart.x + chart.width + padding); ++tx) {
                size_t face = 0;
                if (!uniform) {
                    const DVec2 centre = texelCentre(chart, tx, ty);
                    double nearest = std::numeric_limits<double>::infinity();
                    for (size_t f = 0; f < chart.faces.size() && nearest > 0.0; ++f)
                        if (const double d = squaredDistance(chart.faces[f], centre); d < nearest) {
                            nearest = d;
                            face = f;
                        }
                }
                float* rgb = &image.rgb[(static_cast<size_t>(ty) * static_cast<size_t>(image.width) + static_cast<size_t>(tx)) * 3];
                for (int c = 0; c < 3; ++c) rgb[c] *= reflectance[face][c];
            }
    }
}

}  // namespace radbake
