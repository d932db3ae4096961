// validateScene on scenes built in code.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

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
              "mesh 'floor': 1 duplicate coplanar face(s) covering the same area (e.g. polygon 0 and polygon 1, at "
              "(0.666667, 0.333333, 0))");
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
              "mesh 'a' and mesh 'b': 5 duplicate coplanar face(s) covering the same area (e.g. polygon 0 and polygon 0, "
              "at (0.666667, 0.333333, 0))");
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

namespace {

// A w x h rectangle at (x, y) in z = z0, one polygon of two triangles, facing +z (or -z).
Mesh rectangle(const std::string& name, float x, float y, float w, float h, float z0 = 0.0f, bool up = true) {
    Mesh mesh = square(name, z0);
    mesh.positions = {{x, y, z0}, {x + w, y, z0}, {x + w, y + h, z0}, {x, y + h, z0}};
    if (!up)
        for (UVec3& t : mesh.triangles) std::swap(t.y, t.z);
    return mesh;
}

std::vector<std::string> warnings(const Diagnostics& diagnostics) {
    std::vector<std::string> out;
    for (const Diagnostic& d : diagnostics.all())
        if (d.severity == Severity::Warning) out.push_back(d.message);
    return out;
}

}  // namespace

TEST_CASE("partly overlapping coplanar faces facing the same way are reported, with a point of the overlap") {
    SUBCASE("two unit squares overlapping by half") {
        Scene scene = sceneWith({square("a"), square("b", 0.0f, 0.5f)});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        REQUIRE(diagnostics.warningCount() == 1);
        const Diagnostic& w = diagnostics.all()[0];
        CHECK(w.message.starts_with(
            "mesh 'a' and mesh 'b': 1 coplanar face pair(s) partly overlapping, facing the same way (e.g. polygon 0 "
            "and polygon 0, at ("));
        CHECK(w.location.line == 10);
        // The point lies in the overlap [0.5, 1] x [0, 1] at z = 0.
        const size_t at = w.message.find("at (");
        REQUIRE(at != std::string::npos);
        float x = -1, y = -1, z = -1;
        REQUIRE(std::sscanf(w.message.c_str() + at, "at (%f, %f, %f)", &x, &y, &z) == 3);
        CHECK(x >= 0.5f);
        CHECK(x <= 1.0f);
        CHECK(y >= 0.0f);
        CHECK(y <= 1.0f);
        CHECK(z == 0.0f);
    }
    SUBCASE("a face inside a larger coplanar one, both in one mesh, on a tilted plane far from the origin") {
        Mesh big = rectangle("", 0, 0, 4, 4);
        Mesh inner = rectangle("", 1, 1, 0.5f, 0.5f);
        Mesh mesh;
        mesh.name = "wall";
        mesh.positions = big.positions;
        mesh.positions.insert(mesh.positions.end(), inner.positions.begin(), inner.positions.end());
        mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
        mesh.triangle_polygon = {0, 0, 1, 1};
        mesh.polygon_count = 2;
        // Tilt about x by 30 degrees and move far away: the tolerances follow the extent.
        const float c = std::cos(0.5235988f), s = std::sin(0.5235988f);
        for (Vec3& p : mesh.positions) p = Vec3(p.x + 1000.0f, c * p.y - s * p.z + 2000.0f, s * p.y + c * p.z - 500.0f);
        Scene scene = sceneWith({mesh});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        REQUIRE(diagnostics.warningCount() == 1);
        CHECK(diagnostics.all()[0].message.starts_with(
            "mesh 'wall': 1 coplanar face pair(s) partly overlapping, facing the same way (e.g. polygon 0 and polygon 1"));
    }
    SUBCASE("counts are per face pair: a large face over three small ones in another mesh") {
        Mesh small;
        small.name = "tiles";
        for (int i = 0; i < 3; ++i) {
            Mesh tile = rectangle("", 0.2f + i, 0.2f, 0.5f, 0.5f);
            const uint32_t base = static_cast<uint32_t>(small.positions.size());
            small.positions.insert(small.positions.end(), tile.positions.begin(), tile.positions.end());
            for (UVec3 t : tile.triangles) small.triangles.push_back(t + UVec3(base));
            small.triangle_polygon.insert(small.triangle_polygon.end(), 2, small.polygon_count++);
        }
        Scene scene = sceneWith({rectangle("slab", 0, 0, 4, 1), small, rectangle("below", 0, 0, 4, 1, -0.5f)});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        CHECK(warnings(diagnostics) ==
              std::vector<std::string>{"mesh 'slab' and mesh 'tiles': 3 coplanar face pair(s) partly overlapping, facing "
                                       "the same way (e.g. polygon 0 and polygon 0, at (0.533333, 0.366667, 0))"});
    }
    SUBCASE("duplicates and partial overlaps between the same meshes share one warning") {
        Mesh a = rectangle("a", 0, 0, 1, 1);
        Mesh b = rectangle("b", 0, 0, 1, 1);
        Mesh more = rectangle("", 5, 0, 1, 1);
        a.positions.insert(a.positions.end(), more.positions.begin(), more.positions.end());
        a.triangles.insert(a.triangles.end(), {{4, 5, 6}, {4, 6, 7}});
        a.triangle_polygon.insert(a.triangle_polygon.end(), {1, 1});
        a.polygon_count = 2;
        more = rectangle("", 5.9f, 0, 1, 1);
        b.positions.insert(b.positions.end(), more.positions.begin(), more.positions.end());
        b.triangles.insert(b.triangles.end(), {{4, 5, 6}, {4, 6, 7}});
        b.triangle_polygon.insert(b.triangle_polygon.end(), {1, 1});
        b.polygon_count = 2;
        Scene scene = sceneWith({a, b});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        REQUIRE(diagnostics.warningCount() == 1);
        CHECK(diagnostics.all()[0].message.starts_with(
            "mesh 'a' and mesh 'b': 1 duplicate coplanar face(s) covering the same area, 1 coplanar face pair(s) partly "
            "overlapping, facing the same way (e.g. polygon 0 and polygon 0, at"));
    }
}

TEST_CASE("overlap warnings stop after 20 mesh pairs; one note counts the rest") {
    std::vector<Mesh> meshes;
    for (int i = 0; i < 25; ++i) {
        meshes.push_back(rectangle("a" + std::to_string(i), 3.0f * i, 0, 1, 1));
        meshes.push_back(rectangle("b" + std::to_string(i), 3.0f * i + 0.5f, 0, 1, 1));
    }
    Scene scene = sceneWith(meshes);
    Diagnostics diagnostics;
    CHECK(validateScene(scene, diagnostics));
    CHECK(diagnostics.warningCount() == 20);
    CHECK(countMessages(diagnostics, Severity::Warning, "mesh 'a0' and mesh 'b0': 1 coplanar face pair(s)") == 1);
    CHECK(countMessages(diagnostics, Severity::Note, "5 more mesh pair(s) with 5 overlapping coplanar face pair(s) not reported") == 1);
}

TEST_CASE("coplanar faces that only touch, or overlap back to back, or barely, are not reported") {
    SUBCASE("sharing an edge") {
        Scene scene = sceneWith({square("a"), square("b", 0.0f, 1.0f), rectangle("c", 0, 1, 2, 1)});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        CHECK(warnings(diagnostics).empty());
    }
    SUBCASE("touching at a corner") {
        Scene scene = sceneWith({square("a"), rectangle("b", 1, 1, 1, 1), rectangle("c", 1, -1, 1, 1)});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        CHECK(warnings(diagnostics).empty());
    }
    SUBCASE("back to back, overlapping in part or in full: a double-sided wall") {
        Scene scene = sceneWith({rectangle("front", 0, 0, 1, 1), rectangle("back", 0.5f, 0, 1, 1, 0.0f, false),
                                 rectangle("front2", 3, 0, 1, 1), rectangle("back2", 3, 0, 1, 1, 0.0f, false)});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        CHECK(warnings(diagnostics).empty());
    }
    SUBCASE("overlapping by 0.5 % of the smaller face, below the 1 % threshold; at 2 % it is reported") {
        Diagnostics diagnostics;
        Scene scene = sceneWith({square("a"), square("b", 0.0f, 0.995f)});
        CHECK(validateScene(scene, diagnostics));
        CHECK(warnings(diagnostics).empty());
        Diagnostics diagnostics2;
        Scene scene2 = sceneWith({square("a"), square("b", 0.0f, 0.98f)});
        CHECK(validateScene(scene2, diagnostics2));
        CHECK(diagnostics2.warningCount() == 1);
    }
    SUBCASE("parallel, 1e-3 of the extent apart") {
        Scene scene = sceneWith({square("a"), rectangle("b", 0.5f, 0, 1, 1, 0.0015f)});
        Diagnostics diagnostics;
        CHECK(validateScene(scene, diagnostics));
        CHECK(warnings(diagnostics).empty());
    }
}

TEST_CASE("overlaps are found in a large flat mesh (grid broad phase) against brute force") {
    // A 60 x 60 grid of unit quads in z = 0 (7200 coplanar triangles, one plane group) with
    // a second mesh of 25 quads shifted by (0.5, 0.25): each overlaps 4 grid quads.
    Mesh grid;
    grid.name = "grid";
    const int n = 60;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) grid.positions.push_back({float(i), float(j), 0.0f});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = j * (n + 1) + i;
            grid.triangles.push_back({a, a + 1, a + n + 2});
            grid.triangles.push_back({a, a + n + 2, a + n + 1});
            grid.triangle_polygon.insert(grid.triangle_polygon.end(), 2, grid.polygon_count++);
        }
    Mesh patches;
    patches.name = "patches";
    for (int k = 0; k < 25; ++k) {
        Mesh quad = rectangle("", 10.5f + 2 * (k % 5), 20.25f + 2 * (k / 5), 1, 1);
        const uint32_t base = static_cast<uint32_t>(patches.positions.size());
        patches.positions.insert(patches.positions.end(), quad.positions.begin(), quad.positions.end());
        for (UVec3 t : quad.triangles) patches.triangles.push_back(t + UVec3(base));
        patches.triangle_polygon.insert(patches.triangle_polygon.end(), 2, patches.polygon_count++);
    }
    Scene scene = sceneWith({grid, patches});
    Diagnostics diagnostics;
    CHECK(validateScene(scene, diagnostics));
    REQUIRE(diagnostics.warningCount() == 1);
    // 25 patches x 4 grid quads; overlaps of 0.5 x 0.25 .. 0.5 x 0.75 of a unit quad (all >= 1 %).
    CHECK(diagnostics.all()[0].message.starts_with("mesh 'grid' and mesh 'patches': 100 coplanar face pair(s) partly overlapping"));
}

TEST_CASE("overlap counts match brute force on random rectangles, on a tilted plane far from the origin") {
    // 400 rectangles in one plane, a quarter of them facing the other way, one in ten an exact
    // copy of an earlier one, in one mesh (one polygon each). Corners and sizes are multiples of
    // 1/4 with sizes up to 2, so an overlap is 0 or at least 1/16 of at most 4 (above the 1 %
    // threshold), and only exact copies cover 99 % of both: no case sits near a threshold.
    std::mt19937 random(7);
    auto quarter = [&](int lo, int hi) { return 0.25f * float(lo + int(random() % uint32_t(hi - lo + 1))); };
    struct Rect {
        float x, y, w, h;
        bool up;
    };
    std::vector<Rect> rects;
    for (int i = 0; i < 400; ++i) {
        if (i > 0 && random() % 10 == 0) {
            rects.push_back(rects[random() % rects.size()]);
            continue;
        }
        rects.push_back({quarter(0, 120), quarter(0, 120), quarter(1, 8), quarter(1, 8), random() % 4 != 0});
    }
    size_t expected_partial = 0, expected_duplicates = 0;
    for (size_t i = 0; i < rects.size(); ++i)
        for (size_t j = i + 1; j < rects.size(); ++j) {
            const Rect& a = rects[i];
            const Rect& b = rects[j];
            if (a.up != b.up) continue;
            const double w = std::min(a.x + a.w, b.x + b.w) - std::max(a.x, b.x);
            const double h = std::min(a.y + a.h, b.y + b.h) - std::max(a.y, b.y);
            if (w <= 0 || h <= 0) continue;
            if (a.x == b.x && a.y == b.y && a.w == b.w && a.h == b.h)
                ++expected_duplicates;
            else
                ++expected_partial;
        }
    REQUIRE(expected_partial > 20);
    REQUIRE(expected_duplicates > 5);

    Mesh mesh;
    mesh.name = "tiles";
    const float c = std::cos(0.3f), s = std::sin(0.3f);
    for (const Rect& r : rects) {
        const Mesh quad = rectangle("", r.x, r.y, r.w, r.h, 0.0f, r.up);
        const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
        for (Vec3 p : quad.positions)  // tilt about y, then move 500 away
            mesh.positions.push_back({c * p.x + s * p.z + 500.0f, p.y - 200.0f, -s * p.x + c * p.z + 300.0f});
        for (UVec3 t : quad.triangles) mesh.triangles.push_back(t + UVec3(base));
        mesh.triangle_polygon.insert(mesh.triangle_polygon.end(), 2, mesh.polygon_count++);
    }
    Scene scene = sceneWith({mesh});
    Diagnostics diagnostics;
    CHECK(validateScene(scene, diagnostics));
    REQUIRE(diagnostics.warningCount() == 1);
    CHECK(diagnostics.all()[0].message.starts_with("mesh 'tiles': " + std::to_string(expected_duplicates) +
                                                   " duplicate coplanar face(s) covering the same area, " +
                                                   std::to_string(expected_partial) +
                                                   " coplanar face pair(s) partly overlapping"));
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
