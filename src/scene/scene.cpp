#include "scene/scene.h"

#include <algorithm>
#include <limits>

namespace radbake {

double triangleArea(const Mesh& mesh, size_t triangle) {
    const UVec3& t = mesh.triangles[triangle];
    const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

Vec3 polygonReflectance(const Scene& scene, const Mesh& mesh, uint32_t polygon) {
    if (polygon < mesh.polygon_reflectance.size()) return mesh.polygon_reflectance[polygon];
    return mesh.material < scene.materials.size() ? scene.materials[mesh.material].reflectance : Vec3(0.0f);
}

Vec3 polygonEmission(const Scene& scene, const Mesh& mesh, uint32_t polygon) {
    if (polygon < mesh.polygon_emission.size()) return mesh.polygon_emission[polygon];
    return mesh.material < scene.materials.size() ? scene.materials[mesh.material].emission : Vec3(0.0f);
}

float meshTransmittance(const Scene& scene, const Mesh& mesh) {
    if (mesh.material >= scene.materials.size()) return 0.0f;
    const float t = scene.materials[mesh.material].transparency;
    return t > 0.0f ? std::min(t, 1.0f) : 0.0f;  // NaN and negatives: opaque
}

bool Light::lights(uint32_t mesh) const {
    return !scoped || std::binary_search(scope.begin(), scope.end(), mesh);
}

SceneSummary summarize(const Scene& scene) {
    SceneSummary summary;
    summary.materials = scene.materials.size();
    summary.lights = scene.lights.size();
    Vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Mesh& mesh : scene.meshes) {
        // A back twin (scene/two_sided.h) is its front's surface seen from behind: counted
        // once, as a two-sided mesh, not as more triangles or area.
        if (mesh.back) continue;
        summary.two_sided_closed_meshes += mesh.closed_two_sided ? 1 : 0;
        if (!mesh.solid && !mesh.triangles.empty()) {
            ++summary.two_sided_meshes;
            summary.two_sided_polygons += mesh.polygon_count;
        }
        summary.triangles += mesh.triangles.size();
        summary.polygons += mesh.polygon_count;
        summary.vertices += mesh.positions.size();
        for (size_t t = 0; t < mesh.triangles.size(); ++t) summary.area += triangleArea(mesh, t);
        for (const Vec3& p : mesh.positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        if (mesh.material < scene.materials.size() && scene.materials[mesh.material].isEmitter())
            summary.emitters += mesh.polygon_count;
    }
    if (lo.x <= hi.x) {
        summary.bounds_min = lo;
        summary.bounds_max = hi;
    }
    return summary;
}

}  // namespace radbake
