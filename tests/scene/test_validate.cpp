// validateScene on scenes built in code.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>

#include "scene/validate.h"

using namespace radbake;

namespace {

int countMessages(const Diagnostics& diagnostics, Severity severity, const std::string& part) {
    int count = 0;
    for (const Diagnostic& d : diagnostics.all())
        if (d.severity == severity && d.message.find(part) != std::string::npos) ++count;
    return count;
}

const Diagnostic* findMessage(const Diagnostics& diagnostics, Severity severity, const std::string& part) {
    for (const Diagnostic& d : diagnostics.all())
        if (d.severity == severity && d.message.find(part) != std::string::npos) return &d;
    return nullptr;
}

Material plainMaterial(const std::string& name) {
    Material m;
    m.name = name;
    m.location = {"scene.obj", 3, 1};
    return m;
}

// A unit square in z = z0 as one polygon of two triangles, plus `extra` vertices.
Mesh square(const std::string& name, float z0 = 0.0f, float offset_x = 0.0f) {
    Mesh mesh;
    mesh.name = name;
    mesh.location = {"scene.obj", 10, 1};
    mesh.positions = {{offset_x, 0, z0}, {offset_x + 1, 0, z0}, {offset_x + 1, 1, z0}, {offset_x, 1, z0}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    mesh.triangle_polygon = {0, 0};
    mesh.polygon_count = 1;
    return mesh;
}

Scene sceneWith(std::vector<Mesh> meshes) {
    Scene scene;
    scene.source_path = "scene.obj";
    scene.materials.push_back(plainMaterial("white"));
    scene.meshes = std::move(meshes);
    return scene;
}

}  // namespace

TEST_CASE("a clean scene passes untouched, with no diagnostics") {
    Scene scene = sceneWith({square("a"), square("b", 0.0f, 2.0f)});
    Diagnostics diagnostics;
    CHECK(validateScene(scene, diagnostics));
    CHECK(diagnostics.all().empty());
    CHECK(scene.meshes.size() == 2);
    CHECK(summarize(scene).area == doctest::Approx(2.0));
}

TEST_CASE("degenerate, out-of-range and unused are dropped and counted in exactly one warning") {
    Mesh mesh = square("floor");
    // Vertices 4, 5 (unused), 6 collinear with 0 and 1, 7 a copy of 0.
    mesh.positions.push_back({5, 5, 5});
    mesh.positions.push_back({6, 6, 6});
    mesh.positions.push_back({0.5f, 0, 0});
    mesh.positions.push_back({0, 0, 0});
    mesh.normals.assign(mesh.positions.size(), Vec3(0, 0, 1));
    mesh.normals[3] = Vec3(0, 0, 0.5f);  // marks vertex 3 to follow it through renumbering
    // polygon 1: out of range; polygon 2: degenerate (collinear); polygon 3: two vertices the same
    // position (zero area); polygon 4: repeated index; polygon 5: a good triangle reusing vertex 3.
    mesh.triangles.push_back({0, 1, 99});
    mesh.triangles.push_back({0, 6, 1});
    mesh.triangles.push_back({0, 7, 2});
    mesh.triangles.push_back({2, 2, 3});
    mesh.triangles.push_back({3, 2, 1});
    mesh.triangle_polygon = {0, 0, 1, 2, 3, 4, 5};
    mesh.polygon_count = 6;
    mesh.polygon_colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};
    Scene scene = sceneWith({mesh});
    Diagnostics diagnostics;
    REQUIRE(validateScene(scene, diagnostics));
    REQUIRE(diagnostics.warningCount() == 1);
    const Diagnostic& w = diagnostics.all().front();
    CHECK(w.message == "mesh 'floor': dropped 1 triangle(s) with out-of-range indices, 3 degenerate triangle(s), "
                       "4 unused vertex(es), 4 polygon(s) left without triangles");
    CHECK(w.location.file == "scene.obj");
    CHECK(w.location.line == 10);

    const Mesh& out = scene.meshes.at(0);
    CHECK(out.positions.size() == 4);
    CHECK(out.normals.size() == 4);
    CHECK(out.normals[3] == Vec3(0, 0, 0.5f));
    CHECK(out.polygon_count == 2);
    CHECK(out.triangles == std::vector<UVec3>{{0, 1, 2}, {0, 2, 3}, {3, 2, 1}});
    CHECK(out.triangle_polygon == std::vector<uint32_t>{0, 0, 1});
    CHECK(out.polygon_colors == std::vector<Vec3>{{1, 0, 0}, {1, 0, 1}});
    CHECK(summarize(scene).area == doctest::Approx(1.5));
}

TEST_CASE("the degenerate tolerance is relative to the scene's extent") {
    // A sliver 1e-4 high on a 1-long base: fine in a 1 m scene, below float resolution
    // (4 * 2^-24 * 14142 = 3.4e-3, the diagonal of a 10 km square) in a scene 10 km across.
    Mesh sliver;
    sliver.name = "sliver";
    sliver.positions = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1e-4f, 0}};
    sliver.triangles = {{0, 1, 2}};
    sliver.triangle_polygon = {0};
    sliver.polygon_count = 1;
    {
        Scene scene = sceneWith({sliver});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        CHECK(diagnostics.warningCount() == 0);
        CHECK(scene.meshes.size() == 1);
    }
    {
        Mesh far = square("far");
        for (Vec3& p : far.positions) p *= 10000.0f;
        Scene scene = sceneWith({sliver, far});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        CHECK(countMessages(diagnostics, Severity::Warning, "mesh 'sliver': dropped 1 degenerate triangle(s), 3 unused") == 1);
        CHECK(countMessages(diagnostics, Severity::Warning, "1 empty mesh(es) removed") == 1);
        REQUIRE(scene.meshes.size() == 1);
        CHECK(scene.meshes[0].name == "far");
    }
}

TEST_CASE("a non-finite vertex is an error naming the mesh and its location") {
    Mesh mesh = square("wall");
    mesh.positions[2].y = std::numeric_limits<float>::quiet_NaN();
    Scene scene = sceneWith({square("ok"), mesh});
    Diagnostics diagnostics;
    CHECK(!validateScene(scene, diagnostics));
    REQUIRE(diagnostics.errorCount() == 1);
    const Diagnostic* e = findMessage(diagnostics, Severity::Error, "mesh 'wall'");
    REQUIRE(e);
    CHECK(e->message == "mesh 'wall': 1 vertex position(s) not finite (first: vertex 2)");
    CHECK(formatDiagnostic(*e) == "scene.obj:10:1: error: mesh 'wall': 1 vertex position(s) not finite (first: vertex 2)");
}

TEST_CASE("non-finite colours and light values are errors naming what holds them") {
    Scene scene = sceneWith({square("a")});
    scene.materials[0].emission.x = std::numeric_limits<float>::infinity();
    Light light;
    light.type = LightType::Spot;
    light.location = {"scene.wrl", 40, 5};
    light.direction.z = std::numeric_limits<float>::quiet_NaN();
    scene.lights.push_back(light);
    Light unbounded;  // an infinite radius is legitimate (no range given)
    unbounded.radius = std::numeric_limits<float>::infinity();
    scene.lights.push_back(unbounded);
    scene.meshes[0].vertex_colors.assign(4, Vec3(0.5f));
    scene.meshes[0].vertex_colors[1].z = -std::numeric_limits<float>::infinity();
    Diagnostics diagnostics;
    CHECK(!validateScene(scene, diagnostics));
    CHECK(diagnostics.errorCount() == 3);
    const Diagnostic* m = findMessage(diagnostics, Severity::Error, "material 'white'");
    REQUIRE(m);
    CHECK(m->location.line == 3);
    const Diagnostic* l = findMessage(diagnostics, Severity::Error, "spot light #0");
    REQUIRE(l);
    CHECK(formatDiagnostic(*l) == "scene.wrl:40:5: error: spot light #0 has a non-finite value");
    CHECK(findMessage(diagnostics, Severity::Error, "mesh 'a': 1 vertex colour(s) not finite (first: vertex 1)"));
}

TEST_CASE("reflectance 1.5 is clamped with a warning naming the material; negatives clamped to 0") {
    Scene scene = sceneWith({square("a")});
    scene.materials[0].reflectance = Vec3(1.5f, 0.5f, 1.0f);
    Material dark = plainMaterial("dark");
    dark.reflectance = Vec3(-0.25f, 0.5f, 0.5f);
    dark.emission = Vec3(2.0f, -1.0f, 0.0f);
    scene.materials.push_back(dark);
    Diagnostics diagnostics;
    CHECK(validateScene(scene, diagnostics));
    CHECK(scene.materials[0].reflectance == Vec3(0.999f, 0.5f, 0.999f));
    CHECK(scene.materials[1].reflectance == Vec3(0.0f, 0.5f, 0.5f));
    CHECK(scene.materials[1].emission == Vec3(2.0f, 0.0f, 0.0f));
    CHECK(diagnostics.warningCount() == 3);  // nothing about 'dark' emitting on no polygon: that is fine
    CHECK(countMessages(diagnostics, Severity::Warning, "material 'white' has reflectance") == 1);
    CHECK(countMessages(diagnostics, Severity::Warning, "material 'dark' has negative reflectance") == 1);
    CHECK(countMessages(diagnostics, Severity::Warning, "material 'dark' has negative emission") == 1);
}

TEST_CASE("duplicate coplanar faces are reported once per mesh pair") {
    SUBCASE("the same quad twice in one mesh, triangulated the other way and in another vertex order") {
        Mesh mesh = square("floor");
        mesh.positions.insert(mesh.positions.end(), {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}});
        mesh.triangles.insert(mesh.triangles.end(), {{4, 5, 7}, {7, 5, 6}});
        mesh.triangle_polygon = {0, 0, 1, 1};
        mesh.polygon_count = 2;
        Scene scene = sceneWith({mesh});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        REQUIRE(diagnostics.warningCount() == 1);
        CHECK(diagnostics.all()[0].message ==
              "mesh 'floor': 1 duplicate coplanar face(s) covering the same area (e.g. polygon 0 and polygon 1)");
    }
    SUBCASE("many duplicates between two meshes make one warning with their count") {
        Mesh a, b;
        a.name = "a";
        b.name = "b";
        for (int i = 0; i < 5; ++i) {
            Mesh tile = square("", 0.0f, 2.0f * i);
            for (Mesh* m : {&a, &b}) {
                const uint32_t base = static_cast<uint32_t>(m->positions.size());
                m->positions.insert(m->positions.end(), tile.positions.begin(), tile.positions.end());
                for (UVec3 t : tile.triangles) m->triangles.push_back(t + UVec3(base));
                m->triangle_polygon.insert(m->triangle_polygon.end(), 2, m->polygon_count++);
            }
        }
        Mesh lifted = square("lifted", 0.001f);  // parallel, 1 mm above: not a duplicate
        Scene scene = sceneWith({a, b, lifted});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        REQUIRE(diagnostics.warningCount() == 1);
        CHECK(diagnostics.all()[0].message ==
              "mesh 'a' and mesh 'b': 5 duplicate coplanar face(s) covering the same area (e.g. polygon 0 and polygon 0)");
    }
    SUBCASE("back-to-back faces (a thin wall) and neighbours sharing an edge are not duplicates") {
        Mesh front = square("front");
        Mesh back = square("back");
        for (UVec3& t : back.triangles) std::swap(t.y, t.z);
        Scene scene = sceneWith({front, back, square("beside", 0.0f, 1.0f)});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        CHECK(diagnostics.warningCount() == 0);
    }
}

TEST_CASE("arrays out of step are dropped; a broken polygon map falls back to one polygon per triangle") {
    Mesh mesh = square("m");
    mesh.normals = {{0, 0, 1}};  // one normal for four vertices
    mesh.triangle_polygon = {0, 2};
    mesh.polygon_count = 3;
    Scene scene = sceneWith({mesh});
    Diagnostics diagnostics;
    CHECK(validateScene(scene, diagnostics));
    CHECK(countMessages(diagnostics, Severity::Warning, "mesh 'm': 1 normals for 4, ignored") == 1);
    CHECK(countMessages(diagnostics, Severity::Warning, "inconsistent triangle-to-polygon map") == 1);
    CHECK(scene.meshes[0].normals.empty());
    CHECK(scene.meshes[0].polygon_count == 2);
    CHECK(scene.meshes[0].triangle_polygon == std::vector<uint32_t>{0, 1});
}

TEST_CASE("a mesh pointing past the materials is an error") {
    Mesh mesh = square("m");
    mesh.material = 4;
    Scene scene = sceneWith({mesh});
    Diagnostics diagnostics;
    CHECK(!validateScene(scene, diagnostics));
    CHECK(countMessages(diagnostics, Severity::Error, "mesh 'm' refers to material 4 of 1") == 1);
}
