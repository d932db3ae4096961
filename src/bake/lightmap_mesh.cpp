// Lightmap meshes: chart faces back in world space with their atlas UVs.
#include "bake/lightmap_mesh.h"

#include <algorithm>
#include <map>
#include <tuple>
#include <utility>

namespace radbake {
namespace {

// Barycentric weights of p (on or next to the triangle's plane) in triangle abc, projected
// onto the plane; clamped to the triangle so a point a rounding error outside stays inside.
Vec3 barycentricOf(const DVec3& p, const DVec3& a, const DVec3& b, const DVec3& c) {
    const DVec3 ab = b - a, ac = c - a, ap = p - a;
    const double d00 = glm::dot(ab, ab), d01 = glm::dot(ab, ac), d11 = glm::dot(ac, ac);
    const double d20 = glm::dot(ap, ab), d21 = glm::dot(ap, ac);
    const double det = d00 * d11 - d01 * d01;
    if (!(det > 0.0)) return Vec3(1.0f, 0.0f, 0.0f);
    double v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
    v = std::max(v, 0.0);
    w = std::max(w, 0.0);
    if (v + w > 1.0) {
        const double sum = v + w;
        v /= sum;
        w /= sum;
    }
    return Vec3(static_cast<float>(1.0 - v - w), static_cast<float>(v), static_cast<float>(w));
}

}  // namespace

Vec3 interpolateSource(const LightmapMesh& mesh, size_t v, std::span<const Vec3> per_source_vertex) {
    const UVec3& corners = mesh.source_corners[v];
    const Vec3& w = mesh.barycentric[v];
    return w.x * per_source_vertex[corners.x] + w.y * per_source_vertex[corners.y] + w.z * per_source_vertex[corners.z];
}

Vec2 interpolateSource(const LightmapMesh& mesh, size_t v, std::span<const Vec2> per_source_vertex) {
    const UVec3& corners = mesh.source_corners[v];
    const Vec3& w = mesh.barycentric[v];
    return w.x * per_source_vertex[corners.x] + w.y * per_source_vertex[corners.y] + w.z * per_source_vertex[corners.z];
}

std::vector<LightmapMesh> lightmapMeshes(const Scene& scene, const LightmapLayout& layout) {
    std::vector<LightmapMesh> meshes(scene.meshes.size());
    for (const LightmapChart& chart : layout.charts) {
        if (chart.atlas < 0 || chart.mesh >= meshes.size()) continue;
        const LightmapAtlas& atlas = layout.atlases[chart.atlas];
        LightmapMesh& out = meshes[chart.mesh];
        // Faces of one chart share corners: the same plane point is one vertex (points
        // computed from the same float position are bit-identical).
        // With source UVs the key also holds the source UV there, so a seam of the source UVs
        // inside a chart splits the vertex too.
        std::map<std::tuple<double, double, float, float>, uint32_t> ids;
        const Mesh& source = scene.meshes[chart.mesh];
        const bool has_uv = source.uv0.size() == source.positions.size();
        const auto vertex = [&](const DVec2& p, const ChartFace& face) {
            const uint32_t triangle = face.triangle;
            const DVec3 p_world = face.worldPoint(p);  // on its own face: charts may bend
            const UVec3 corners = source.triangles[triangle];
            const Vec3 weights = barycentricOf(p_world, DVec3(source.positions[corners.x]),
                                               DVec3(source.positions[corners.y]), DVec3(source.positions[corners.z]));
            const Vec2 uv = has_uv ? weights.x * source.uv0[corners.x] + weights.y * source.uv0[corners.y] +
                                         weights.z * source.uv0[corners.z]
                                   : Vec2(0.0f);
            const auto [it, added] =
                ids.emplace(std::make_tuple(p.x, p.y, uv.x, uv.y), static_cast<uint32_t>(out.positions.size()));
            if (added) {
                const DVec2 texel = chart.atlasTexel(p);
                out.source_corners.push_back(corners);
                out.barycentric.push_back(weights);
                out.positions.push_back(Vec3(p_world));
                out.uv.push_back(Vec2(static_cast<float>(texel.x / atlas.width), static_cast<float>(texel.y / atlas.height)));
                out.atlas.push_back(chart.atlas);
            }
            return it->second;
        };
        for (const ChartFace& face : chart.faces) {
            std::vector<uint32_t> loop;
            for (const DVec2& p : face.p_plane) loop.push_back(vertex(p, face));
            for (size_t k = 1; k + 1 < loop.size(); ++k) {
                out.triangles.push_back(UVec3(loop[0], loop[k], loop[k + 1]));
                out.source_triangle.push_back(face.triangle);
            }
        }
    }
    return meshes;
}

}  // namespace radbake
