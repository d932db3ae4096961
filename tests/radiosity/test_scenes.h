#pragma once
// Small scenes built in code for the solver tests.
#include <optional>

#include "core/progress.h"
#include "geometry/parts.h"
#include "radiosity/solution.h"
#include "radiosity/solver.h"
#include "scene/scene.h"

namespace radbake::test {

inline uint32_t addMaterial(Scene& scene, Vec3 reflectance, Vec3 emission) {
    Material m;
    m.name = "m" + std::to_string(scene.materials.size());
    m.reflectance = reflectance;
    m.emission = emission;
    scene.materials.push_back(m);
    return static_cast<uint32_t>(scene.materials.size() - 1);
}

// One mesh holding one quad polygon p0 p1 p2 p3 (counter-clockwise seen from its front).
inline void addQuad(Scene& scene, uint32_t material, Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3) {
    Mesh mesh;
    mesh.name = "quad" + std::to_string(scene.meshes.size());
    mesh.positions = {p0, p1, p2, p3};
    mesh.triangles = {UVec3(0, 1, 2), UVec3(0, 2, 3)};
    mesh.triangle_polygon = {0, 0};
    mesh.polygon_count = 1;
    mesh.material = material;
    scene.meshes.push_back(mesh);
}

// Axis-aligned box [lo, hi] with its six faces facing inwards.
inline void addInwardBox(Scene& scene, uint32_t material, Vec3 lo, Vec3 hi) {
    const float x0 = lo.x, y0 = lo.y, z0 = lo.z, x1 = hi.x, y1 = hi.y, z1 = hi.z;
    addQuad(scene, material, {x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0});  // floor z0, faces +z
    addQuad(scene, material, {x0, y0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1});  // ceiling, faces -z
    addQuad(scene, material, {x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1});  // x0 wall, faces +x
    addQuad(scene, material, {x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0});  // x1 wall, faces -x
    addQuad(scene, material, {x0, y0, z0}, {x0, y0, z1}, {x1, y0, z1}, {x1, y0, z0});  // y0 wall, faces +y
    addQuad(scene, material, {x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1});  // y1 wall, faces -y
}

// Axis-aligned box [lo, hi] as one closed convex solid facing outwards.
inline void addOutwardBox(Scene& scene, uint32_t material, Vec3 lo, Vec3 hi) {
    Scene tmp;
    addInwardBox(tmp, material, lo, hi);
    Mesh solid;
    solid.name = "block" + std::to_string(scene.meshes.size());
    solid.material = material;
    solid.convex_solid = true;
    for (const Mesh& face : tmp.meshes) {
        const uint32_t base = static_cast<uint32_t>(solid.positions.size());
        // Reverse the winding: outward.
        for (int k = 3; k >= 0; --k) solid.positions.push_back(face.positions[k]);
        solid.triangles.push_back(UVec3(base, base + 1, base + 2));
        solid.triangles.push_back(UVec3(base, base + 2, base + 3));
        solid.triangle_polygon.push_back(solid.polygon_count);
        solid.triangle_polygon.push_back(solid.polygon_count);
        ++solid.polygon_count;
    }
    scene.meshes.push_back(solid);
}

// Two worker threads for the stages that take a runner (results do not depend on it).
inline ParallelRunner& testRunner() {
    static ParallelRunner runner(Threading{.threads = 2});
    return runner;
}

inline std::optional<Solution> solve(const Scene& scene, const SolverOptions& options, Diagnostics& diagnostics,
                                     int threads = 2) {
    const PartSet parts = buildParts(scene, PartOptions{}, diagnostics);
    Progress progress(false);
    ParallelRunner runner(Threading{.threads = threads});
    auto solution = solveRadiosity(scene, parts, options, runner, progress, diagnostics);
    if (!solution)  // say why, so the REQUIRE that follows is not a bare {?}
        for (const Diagnostic& d : diagnostics.all()) MESSAGE("solve failed: " << d.message);
    return solution;
}

}  // namespace radbake::test
