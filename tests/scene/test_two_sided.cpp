// addBackTwins (scene/two_sided.h): the back twin's geometry, idempotence, summaries, and
// that validation never reports a twin as an overlap.
#include <doctest/doctest.h>

#include "scene/scene.h"
#include "scene/two_sided.h"
#include "scene/validate.h"

using namespace radbake;

namespace {

// A unit quad z = 0 facing +z, with normals, UVs and a per-polygon reflectance.
Mesh quad(bool solid) {
    Mesh mesh;
    mesh.name = "wall";
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.normals.assign(4, Vec3(0, 0, 1));
    mesh.uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mesh.triangles = {UVec3(0, 1, 2), UVec3(0, 2, 3)};
    mesh.triangle_polygon = {0, 0};
    mesh.polygon_count = 1;
    mesh.polygon_reflectance = {Vec3(0.25f)};
    mesh.solid = solid;
    return mesh;
}

}  // namespace

TEST_CASE("addBackTwins: a two-sided mesh gets a reversed twin after every mesh, once") {
    Scene scene;
    scene.materials.push_back(Material{});
    scene.meshes = {quad(false), quad(true)};
    CHECK(addBackTwins(scene) == 1);
    REQUIRE(scene.meshes.size() == 3);
    const Mesh& front = scene.meshes[0];
    const Mesh& back = scene.meshes[2];
    CHECK(front.twin == 2);
    CHECK_FALSE(front.back);
    CHECK(back.twin == 0);
    CHECK(back.back);
    CHECK(scene.meshes[1].twin == kNoMesh);  // solid: one-sided
    CHECK(back.name == "wall (back)");
    CHECK(back.positions == front.positions);
    CHECK(back.uv0 == front.uv0);
    CHECK(back.triangle_polygon == front.triangle_polygon);
    CHECK(back.polygon_reflectance == front.polygon_reflectance);
    CHECK(back.material == front.material);
    for (size_t t = 0; t < back.triangles.size(); ++t) {
        CHECK(back.triangles[t] == UVec3(front.triangles[t].x, front.triangles[t].z, front.triangles[t].y));
        const DVec3 a(back.positions[back.triangles[t].x]), b(back.positions[back.triangles[t].y]),
            c(back.positions[back.triangles[t].z]);
        CHECK(glm::cross(b - a, c - a).z < 0.0);  // facing -z
    }
    for (const Vec3& n : back.normals) CHECK(n == Vec3(0, 0, -1));
    CHECK(frontMesh(scene, 2) == 0);
    CHECK(frontMesh(scene, 1) == 1);

    CHECK(addBackTwins(scene) == 0);  // idempotent
    CHECK(scene.meshes.size() == 3);
}

TEST_CASE("summaries count a two-sided surface once, and say it is two-sided") {
    Scene scene;
    scene.materials.push_back(Material{});
    scene.meshes = {quad(false), quad(true)};
    const SceneSummary before = summarize(scene);
    addBackTwins(scene);
    const SceneSummary after = summarize(scene);
    CHECK(after.triangles == before.triangles);
    CHECK(after.polygons == before.polygons);
    CHECK(after.area == doctest::Approx(before.area));
    CHECK(after.area == doctest::Approx(2.0));
    CHECK(before.two_sided_meshes == 1);
    CHECK(after.two_sided_meshes == 1);
    CHECK(after.two_sided_polygons == 1);
}

TEST_CASE("validation does not take a back twin for an overlap") {
    Scene scene;
    scene.source_path = "wall.wrl";
    scene.materials.push_back(Material{});
    scene.meshes = {quad(false)};
    addBackTwins(scene);
    Diagnostics diagnostics;
    CHECK(validateScene(scene, diagnostics));
    CHECK(diagnostics.warningCount() == 0);
    CHECK(scene.meshes.size() == 2);
}
