#pragma once
// Literal scenes shared by the lightmap tests.
#include <vector>

#include "scene/scene.h"

namespace lightmap_test {

// One flat convex polygon as a fan of triangles (polygon 0).
inline radbake::Mesh polygonMesh(const std::vector<radbake::Vec3>& loop) {
    radbake::Mesh mesh;
    mesh.positions = loop;
    for (uint32_t k = 1; k + 1 < loop.size(); ++k) {
        mesh.triangles.push_back({0, k, k + 1});
        mesh.triangle_polygon.push_back(0);
    }
    mesh.polygon_count = 1;
    return mesh;
}

// The meshes with one default material each.
inline radbake::Scene sceneOf(std::vector<radbake::Mesh> meshes) {
    radbake::Scene scene;
    scene.materials.resize(meshes.size());
    for (uint32_t m = 0; m < meshes.size(); ++m) meshes[m].material = m;
    scene.meshes = std::move(meshes);
    return scene;
}

}  // namespace lightmap_test
