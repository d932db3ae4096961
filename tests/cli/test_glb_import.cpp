// A .glb written by radbake reads back through radbake's own importer (Assimp) with the
// same triangles: every written triangle's corner positions appear, exactly, in the import.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <set>
#include <tuple>

#include "cli_support.h"
#include "export/gltf_writer.h"
#include "io/import.h"

using namespace radbake;
using namespace clitest;

namespace {

using Corner = std::tuple<float, float, float>;
using Triangle = std::array<Corner, 3>;

// A triangle as its corners rotated so the smallest comes first (winding kept).
Triangle canonical(const Vec3& a, const Vec3& b, const Vec3& c) {
    Triangle t{Corner{a.x, a.y, a.z}, Corner{b.x, b.y, b.z}, Corner{c.x, c.y, c.z}};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    return t;
}

std::multiset<Triangle> trianglesOf(const Scene& scene) {
    std::multiset<Triangle> out;
    for (const Mesh& mesh : scene.meshes)
        for (const UVec3& t : mesh.triangles)
            out.insert(canonical(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]));
    return out;
}

Scene literalScene() {
    Scene scene;
    scene.name = "readback";
    Material grey;
    grey.name = "grey";
    grey.reflectance = Vec3(0.25f, 0.5f, 0.75f);
    Material lamp;
    lamp.name = "lamp";
    lamp.reflectance = Vec3(0.0f);
    lamp.emission = Vec3(0.5f, 0.25f, 1.0f);
    scene.materials = {grey, lamp};
    Mesh floor;
    floor.name = "floor";
    floor.positions = {{-1.5f, 0, -1}, {-1.5f, 0, 1}, {1.25f, 0, 1}, {1.25f, 0, -1}, {0.1f, 0.0f, 0.3f}};
    floor.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
    floor.triangle_polygon = {0, 1, 2, 3};
    floor.polygon_count = 4;
    Mesh lampMesh;
    lampMesh.name = "lamp";
    lampMesh.positions = {{-0.5f, 2, -0.5f}, {0.5f, 2, -0.5f}, {0.5f, 2, 0.5f}, {-0.5f, 2, 0.5f}};
    lampMesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    lampMesh.triangle_polygon = {0, 0};
    lampMesh.polygon_count = 1;
    lampMesh.material = 1;
    scene.meshes = {floor, lampMesh};
    return scene;
}

}  // namespace

TEST_CASE("a radbake .glb imports back with the same triangles and materials") {
    TempDir tmp;
    const Scene scene = literalScene();
    VertexBake bake;
    bake.values = {std::vector<Vec3>(5, Vec3(0.5f, 2.0f, 3.0f)), std::vector<Vec3>(4, Vec3(1.0f))};
    Diagnostics diagnostics;
    REQUIRE(writeGlb(tmp.path / "readback.glb", scene, bake, {"radbake test"}, diagnostics));

    const std::optional<Scene> back = importScene((tmp.path / "readback.glb").string(), {}, diagnostics);
    REQUIRE(back.has_value());
    CHECK_FALSE(diagnostics.hasErrors());
    CHECK(back->meshes.size() == 2);
    CHECK(trianglesOf(*back) == trianglesOf(scene));

    // Base colour and emission come back as reflectance and emitted radiance.
    bool found_lamp = false;
    for (const Mesh& mesh : back->meshes) {
        const Material& material = back->materials.at(mesh.material);
        if (mesh.positions.size() == 4) {
            found_lamp = true;
            CHECK(material.emission.x == doctest::Approx(0.5f));
            CHECK(material.emission.y == doctest::Approx(0.25f));
            CHECK(material.emission.z == doctest::Approx(1.0f));
        } else {
            CHECK(material.reflectance.x == doctest::Approx(0.25f));
            CHECK(material.reflectance.z == doctest::Approx(0.75f));
        }
    }
    CHECK(found_lamp);
}
