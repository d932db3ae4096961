#include "export/mesh_attributes.h"

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
        for (const UVec3& t : mesh.triangles) {
            if (t.x >= n || t.y >= n || t.z >= n) continue;
            const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
            const DVec3 twice_area_normal = glm::cross(b - a, c - a);  // length = 2 * area: area weighting
            sums[t.x] += twice_area_normal;
            sums[t.y] += twice_area_normal;
            sums[t.z] += twice_area_normal;
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
    const size_t n = lightmap_mesh.positions.size();
    std::vector<Vec3> out(n, Vec3(0.0f, 0.0f, 1.0f));
    if (mesh.normals.size() == mesh.positions.size()) {
        const std::vector<Vec3> source = vertexNormals(mesh);
        for (size_t v = 0; v < n; ++v) out[v] = unitOrUp(DVec3(interpolateSource(lightmap_mesh, v, source)));
        return out;
    }
    // Each vertex takes the face normal of the first triangle that uses it (all of a
    // vertex's triangles lie on one source face or on coplanar ones).
    std::vector<bool> set(n, false);
    for (size_t t = 0; t < lightmap_mesh.triangles.size(); ++t) {
        const UVec3& source = mesh.triangles[lightmap_mesh.source_triangle[t]];
        const DVec3 a(mesh.positions[source.x]), b(mesh.positions[source.y]), c(mesh.positions[source.z]);
        const Vec3 normal = unitOrUp(glm::cross(b - a, c - a));
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = lightmap_mesh.triangles[t][k];
            if (set[v]) continue;
            out[v] = normal;
            set[v] = true;
        }
    }
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
