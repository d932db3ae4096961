#include "export/mesh_attributes.h"

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

}  // namespace radbake
