#include "export/mesh_attributes.h"

#include <cmath>
#include <string>

namespace radbake {

namespace {
Vec3 unitOrUp(const DVec3& v) {
    const double length = glm::length(v);
    if (!(length > 0.0) || !std::isfinite(length)) return Vec3(0.0f, 0.0f, 1.0f);
    return Vec3(v / length);
}
}  // namespace

std::vector<Vec3> vertexNormals(const Mesh& mesh) {
    const size_t n = mesh.positions.size();
    std::vector<DVec3> sums(n, DVec3(0.0));
    if (mesh.normals.size() == n) {
        for (size_t v = 0; v < n; ++v) sums[v] = DVec3(mesh.normals[v]);
    } else {
        // Weighted by each corner's angle: a polygon then counts as a whole whichever way it
        // was cut into triangles (area weights tilt a cylinder's normals towards the side
        // whose quad gives the vertex two triangles).
        for (const UVec3& t : mesh.triangles) {
            if (t.x >= n || t.y >= n || t.z >= n) continue;
            const DVec3 p[3] = {DVec3(mesh.positions[t.x]), DVec3(mesh.positions[t.y]), DVec3(mesh.positions[t.z])};
            const DVec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
            const double length = glm::length(cross);
            if (!(length > 0.0) || !std::isfinite(length)) continue;
            for (int k = 0; k < 3; ++k) {
                const DVec3 u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
                const double angle = std::atan2(glm::length(glm::cross(u, w)), glm::dot(u, w));
                sums[t[k]] += angle * (cross / length);
            }
        }
    }
    std::vector<Vec3> normals(n);
    for (size_t v = 0; v < n; ++v) normals[v] = unitOrUp(sums[v]);
    return normals;
}

std::vector<Vec3> finiteVertexValues(const Mesh& mesh, const std::vector<Vec3>* values, size_t& replaced) {
    std::vector<Vec3> out(mesh.positions.size(), Vec3(0.0f));
    if (!values) return out;
    for (size_t v = 0; v < out.size() && v < values->size(); ++v) {
        if (isFinite((*values)[v])) {
            out[v] = (*values)[v];
        } else {
            ++replaced;
        }
    }
    return out;
}

namespace {

// The first inconsistency of one lightmap mesh against its source mesh, or empty.
std::string lightmapMeshProblem(const Mesh& mesh, const LightmapMesh& lm, size_t atlas_count) {
    const size_t n = lm.positions.size();
    if (lm.uv.size() != n || lm.atlas.size() != n || lm.source_corners.size() != n || lm.barycentric.size() != n)
        return "per-vertex arrays differ in length";
    if (lm.source_triangle.size() != lm.triangles.size()) return "source_triangle does not match the triangles";
    for (size_t v = 0; v < n; ++v) {
        const UVec3& c = lm.source_corners[v];
        if (c.x >= mesh.positions.size() || c.y >= mesh.positions.size() || c.z >= mesh.positions.size())
            return "a source corner is not a vertex of the mesh";
        if (lm.atlas[v] < 0 || static_cast<size_t>(lm.atlas[v]) >= atlas_count) return "an atlas index has no file";
    }
    for (size_t t = 0; t < lm.triangles.size(); ++t) {
        const UVec3& tri = lm.triangles[t];
        if (tri.x >= n || tri.y >= n || tri.z >= n) return "a triangle index is out of range";
        if (lm.atlas[tri.x] != lm.atlas[tri.y] || lm.atlas[tri.x] != lm.atlas[tri.z])
            return "a triangle spans two atlases";
        if (lm.source_triangle[t] >= mesh.triangles.size()) return "a source triangle is out of range";
    }
    return {};
}

}  // namespace

bool checkLightmapsMatchScene(const Scene& scene, const LightmapFiles& lightmaps, Diagnostics& diagnostics) {
    if (lightmaps.meshes.size() != scene.meshes.size()) {
        diagnostics.error({}, "internal: lightmap meshes for " + std::to_string(lightmaps.meshes.size()) +
                                  " meshes, scene has " + std::to_string(scene.meshes.size()));
        return false;
    }
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const std::string problem = lightmapMeshProblem(scene.meshes[m], lightmaps.meshes[m], lightmaps.atlas_files.size());
        if (!problem.empty()) {
            diagnostics.error(scene.meshes[m].location,
                              "internal: lightmap mesh of '" + scene.meshes[m].name + "' is inconsistent: " + problem);
            return false;
        }
    }
    return true;
}

std::vector<Vec3> lightmapVertexNormals(const Mesh& mesh, const LightmapMesh& lightmap_mesh) {
    const std::vector<Vec3> source = vertexNormals(mesh);
    std::vector<Vec3> out(lightmap_mesh.positions.size());
    for (size_t v = 0; v < out.size(); ++v) out[v] = unitOrUp(DVec3(interpolateSource(lightmap_mesh, v, source)));
    return out;
}

std::vector<Vec3> lightmapVertexValues(const Mesh& mesh, const LightmapMesh& lightmap_mesh,
                                       const std::vector<Vec3>* values, size_t& replaced) {
    const std::vector<Vec3> source = finiteVertexValues(mesh, values, replaced);
    std::vector<Vec3> out(lightmap_mesh.positions.size());
    for (size_t v = 0; v < out.size(); ++v) out[v] = interpolateSource(lightmap_mesh, v, source);
    return out;
}

}  // namespace radbake
