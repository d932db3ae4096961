// addBackTwins (scene/two_sided.h): the back twin's geometry, idempotence, summaries, and
// that validation never reports a twin as an overlap.
#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

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

// --- closed two-sided meshes (settleClosedTwoSided) -----------------------------------------

namespace {

// The cube [0,1]^3 as six quads facing out, vertices not shared between faces (the weld joins them).
Mesh cube(bool solid, bool inward = false, bool skip_top = false) {
    Mesh mesh;
    mesh.name = "cube";
    const auto face = [&](std::vector<Vec3> loop) {
        if (inward) std::reverse(loop.begin(), loop.end());
        const uint32_t base = uint32_t(mesh.positions.size());
        for (const Vec3& p : loop) mesh.positions.push_back(p);
        mesh.triangles.push_back(UVec3(base, base + 1, base + 2));
        mesh.triangles.push_back(UVec3(base, base + 2, base + 3));
        mesh.triangle_polygon.push_back(mesh.polygon_count);
        mesh.triangle_polygon.push_back(mesh.polygon_count);
        ++mesh.polygon_count;
    };
    face({{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}});  // -z
    if (!skip_top) face({{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}});  // +z
    face({{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}});  // -y
    face({{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}});  // +y
    face({{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}});  // -x
    face({{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}});  // +x
    mesh.solid = solid;
    return mesh;
}

Scene sceneWith(std::vector<Mesh> meshes) {
    Scene scene;
    scene.materials.push_back(Material{});
    Material lamp;
    lamp.emission = Vec3(1.0f);
    scene.materials.push_back(lamp);  // material 1 emits
    scene.meshes = std::move(meshes);
    return scene;
}

Light pointLight(Vec3 position) {
    Light light;
    light.type = LightType::Point;
    light.position = position;
    return light;
}

// A one-sided emitting triangle (material 1).
Mesh lampTriangle(Vec3 a, Vec3 b, Vec3 c) {
    Mesh mesh;
    mesh.name = "lamp";
    mesh.positions = {a, b, c};
    mesh.triangles = {UVec3(0, 1, 2)};
    mesh.triangle_polygon = {0};
    mesh.polygon_count = 1;
    mesh.material = 1;
    return mesh;
}

}  // namespace

TEST_CASE("a closed two-sided mesh with nothing lit inside needs no back twin") {
    Scene scene = sceneWith({cube(false)});
    scene.lights.push_back(pointLight(Vec3(3, 0.5f, 0.5f)));  // outside
    const SceneSummary before = summarize(scene);
    CHECK(before.two_sided_meshes == 1);
    CHECK(addBackTwins(scene) == 0);
    REQUIRE(scene.meshes.size() == 1);
    CHECK(scene.meshes[0].solid);  // baked one-sided: its backs are dark
    CHECK(scene.meshes[0].closed_two_sided);
    CHECK(scene.meshes[0].twin == kNoMesh);
    const SceneSummary after = summarize(scene);
    CHECK(after.two_sided_meshes == 0);
    CHECK(after.two_sided_closed_meshes == 1);
    CHECK(after.polygons == before.polygons);
}

TEST_CASE("a two-sided mesh keeps its back twin unless it is provably dark inside") {
    SUBCASE("open: one face missing") {
        Scene scene = sceneWith({cube(false, false, true)});
        CHECK(addBackTwins(scene) == 1);
    }
    SUBCASE("inside out: its fronts face its own volume") {
        Scene scene = sceneWith({cube(false, true)});
        CHECK(addBackTwins(scene) == 1);
    }
    SUBCASE("a point light inside") {
        Scene scene = sceneWith({cube(false)});
        scene.lights.push_back(pointLight(Vec3(0.5f)));
        CHECK(addBackTwins(scene) == 1);
    }
    SUBCASE("a spot light on its surface") {
        Scene scene = sceneWith({cube(false)});
        Light spot = pointLight(Vec3(0.5f, 0.5f, 1.0f));
        spot.type = LightType::Spot;
        scene.lights.push_back(spot);
        CHECK(addBackTwins(scene) == 1);
    }
    SUBCASE("a point light on a corner") {
        Scene scene = sceneWith({cube(false)});
        scene.lights.push_back(pointLight(Vec3(1.0f)));
        CHECK(addBackTwins(scene) == 1);
    }
    SUBCASE("an emitting triangle of another mesh inside") {
        Scene scene = sceneWith({cube(false), lampTriangle({0.2f, 0.2f, 0.5f}, {0.8f, 0.2f, 0.5f}, {0.5f, 0.8f, 0.5f})});
        CHECK(addBackTwins(scene) == 1);
        CHECK(scene.meshes[0].twin == 2);
    }
    SUBCASE("an emitting triangle passing through it, every corner outside") {
        Scene scene = sceneWith({cube(false), lampTriangle({-5, 0.5f, -5}, {5, 0.5f, -5}, {0, 0.5f, 5})});
        CHECK(addBackTwins(scene) == 1);
    }
    SUBCASE("an emitting triangle piercing one face, every corner outside") {
        // A long thin triangle through the box along x, its corners beyond both ends.
        Scene scene = sceneWith({cube(false), lampTriangle({-1, 0.5f, 0.5f}, {2, 0.49f, 0.5f}, {2, 0.51f, 0.5f})});
        CHECK(addBackTwins(scene) == 1);
    }
    SUBCASE("it emits itself: its backs light its own inside") {
        Scene scene = sceneWith({cube(false)});
        scene.meshes[0].material = 1;
        CHECK(addBackTwins(scene) == 1);
    }
}

TEST_CASE("lights and emitters outside a closed two-sided mesh leave it dark inside") {
    Scene scene = sceneWith({cube(false), lampTriangle({-1, -1, 2}, {2, -1, 2}, {0.5f, 2, 2})});
    scene.lights.push_back(pointLight(Vec3(0.5f, 0.5f, 1.001f)));  // just above the top face
    Light sun;
    sun.type = LightType::Directional;
    scene.lights.push_back(sun);
    CHECK(addBackTwins(scene) == 0);
    CHECK(scene.meshes[0].closed_two_sided);
    CHECK_FALSE(scene.meshes[1].closed_two_sided);  // one-sided from the start
}

namespace {

// A unit quad at height z, facing +z (up) or -z, two-sided unless `solid`.
Mesh quadAt(float z, bool up, bool solid = false) {
    Mesh mesh = quad(solid);
    for (Vec3& p : mesh.positions) p.z = z;
    if (!up) {
        for (UVec3& t : mesh.triangles) std::swap(t.y, t.z);
        for (Vec3& n : mesh.normals) n = -n;
    }
    return mesh;
}

Vec3 backReflectance(const Scene& scene, uint32_t front) {
    return polygonReflectance(scene, scene.meshes[scene.meshes[front].twin], 0);
}

}  // namespace

TEST_CASE("backs in contact: a back twin that another surface covers from in front reflects nothing") {
    SUBCASE("two touching back-to-back slabs: both backs lie in the gap") {
        Scene scene;
        scene.materials.push_back(Material{});
        scene.meshes = {quadAt(0.0f, true), quadAt(-5e-6f, false)};  // 5e-6: above rounding, in contact
        addBackTwins(scene);
        CHECK(scene.covered_back_polygons == 2);
        CHECK(backReflectance(scene, 0) == Vec3(0.0f));
        CHECK(backReflectance(scene, 1) == Vec3(0.0f));
        CHECK(polygonReflectance(scene, scene.meshes[0], 0) == Vec3(0.25f));  // fronts untouched
        CHECK(polygonReflectance(scene, scene.meshes[1], 0) == Vec3(0.25f));
    }
    SUBCASE("two sheets facing up, one just above the other: the upper one's back is in the gap") {
        Scene scene;
        scene.materials.push_back(Material{});
        scene.meshes = {quadAt(5e-6f, true), quadAt(0.0f, true)};  // the upper first: geometry decides
        addBackTwins(scene);
        CHECK(scene.covered_back_polygons == 1);
        CHECK(backReflectance(scene, 0) == Vec3(0.0f));
        CHECK(backReflectance(scene, 1) == Vec3(0.25f));  // the underside: open
    }
    SUBCASE("the same face given twice: one back stays, the later one is a duplicate") {
        Scene scene;
        scene.materials.push_back(Material{});
        scene.meshes = {quadAt(0.0f, true), quadAt(0.0f, true)};
        addBackTwins(scene);
        CHECK(scene.covered_back_polygons == 1);
        CHECK(backReflectance(scene, 0) == Vec3(0.25f));
        CHECK(backReflectance(scene, 1) == Vec3(0.0f));
    }
    SUBCASE("a one-sided face just behind a back covers it; half of it covers half") {
        Scene scene;
        scene.materials.push_back(Material{});
        Mesh half = quadAt(-5e-6f, true, true);
        for (Vec3& p : half.positions) p.x *= 0.5f;
        scene.meshes = {quadAt(0.0f, true), half};
        addBackTwins(scene);
        CHECK(scene.covered_back_polygons == 1);
        CHECK(backReflectance(scene, 0).x == doctest::Approx(0.125).epsilon(1e-4));
    }
    SUBCASE("surfaces apart, or behind the back, cover nothing") {
        Scene scene;
        scene.materials.push_back(Material{});
        scene.meshes = {quadAt(0.0f, true), quadAt(-0.1f, true), quadAt(5e-6f, false, true)};
        addBackTwins(scene);
        CHECK(scene.covered_back_polygons == 0);
        CHECK(backReflectance(scene, 0) == Vec3(0.25f));
        CHECK(backReflectance(scene, 1) == Vec3(0.25f));
    }
}
