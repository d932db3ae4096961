// Light scope (issue 13): a VRML97 DirectionalLight lights only its siblings and their
// descendants (ISO/IEC 14772-1, DirectionalLight), a VRML 1.0 light only what follows it in its
// Separator; PointLight and SpotLight are global in VRML97.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "radbake.h"
#include "../export/temp_files.h"

using namespace radbake;
using testfs::TempDir;

namespace {

// Two grey floors facing up, side by side (they cannot see each other): "A" at x in [0, 2],
// "B" at x in [3, 5].
std::string floorShape(float x0) {
    const std::string a = std::to_string(x0), b = std::to_string(x0 + 2.0f);
    return "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
           " geometry IndexedFaceSet { coord Coordinate { point [ " + a + " 0 0, " + a + " 0 2, " + b + " 0 2, " + b +
           " 0 0 ] } coordIndex [ 0 1 2 3 -1 ] } }\n";
}

struct Baked {
    Bake bake;
    std::vector<std::string> warnings;
};

Baked bakeFile(const std::string& path, Quality quality = Quality::Draft) {
    BakeOptions options = BakeOptions::forQuality(quality);
    options.lightmaps.enabled = false;
    options.threading.threads = 2;
    Progress progress(false);
    Diagnostics diagnostics;
    Baked out{bake(path, options, progress, diagnostics), {}};
    for (const Diagnostic& d : diagnostics.all()) out.warnings.push_back(formatDiagnostic(d));
    REQUIRE(std::string(toString(out.bake.status)) == "ok");
    return out;
}

// Every vertex of mesh m holds `expected` (H / pi, grey).
void checkMesh(const Bake& bake, size_t m, double expected) {
    for (const Vec3& v : bake.vertices.values.at(m)) CHECK(v.x == doctest::Approx(expected).epsilon(1e-4));
}

}  // namespace

TEST_CASE("light scope: a VRML97 DirectionalLight in a Group lights that group's surfaces only") {
    TempDir dir;
    const std::string path = testfs::writeText(dir, "rooms.wrl",
                                   "#VRML V2.0 utf8\n"
                                   "Group { children [ " + floorShape(0.0f) +
                                       " Transform { children DirectionalLight { direction 0 -1 0 } } ] }\n"
                                       "Group { children [ " + floorShape(3.0f) + " ] }\n");
    Diagnostics diagnostics;
    const std::optional<Scene> scene = importScene(path, {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->lights.size() == 1);
    // Inside the Transform, the light's siblings are nothing: it lights no shape, and says so.
    CHECK(scene->lights[0].scoped);
    CHECK(scene->lights[0].scope.empty());
    bool warned = false;
    for (const Diagnostic& d : diagnostics.all()) warned = warned || formatDiagnostic(d).find("lights no shape") != std::string::npos;
    CHECK(warned);

    // The light beside the floor in its Group: E = 1 W/m^2 straight down, H / pi = 1 / pi.
    const std::string lit = testfs::writeText(dir, "lit.wrl",
                                  "#VRML V2.0 utf8\n"
                                  "Group { children [ " + floorShape(0.0f) +
                                      " DirectionalLight { direction 0 -1 0 } ] }\n"
                                      "Group { children [ " + floorShape(3.0f) + " ] }\n");
    const Baked rooms = bakeFile(lit);
    REQUIRE(rooms.bake.scene->lights.size() == 1);
    CHECK(rooms.bake.scene->lights[0].scope == std::vector<uint32_t>{0});
    checkMesh(rooms.bake, 0, 1.0 / kPi);
    checkMesh(rooms.bake, 1, 0.0);
    // The reference preset reads every vertex with the exhaustive gather: the same scope.
    const Baked reference = bakeFile(lit, Quality::Reference);
    checkMesh(reference.bake, 0, 1.0 / kPi);
    checkMesh(reference.bake, 1, 0.0);
}

TEST_CASE("light scope: a top-level DirectionalLight and a grouped PointLight light everything") {
    TempDir dir;
    const Baked top = bakeFile(testfs::writeText(dir, "top.wrl",
                                     "#VRML V2.0 utf8\nDirectionalLight { direction 0 -1 0 }\n"
                                     "Group { children [ " + floorShape(0.0f) + " ] }\nGroup { children [ " +
                                         floorShape(3.0f) + " ] }\n"));
    CHECK_FALSE(top.bake.scene->lights[0].scoped);
    checkMesh(top.bake, 0, 1.0 / kPi);
    checkMesh(top.bake, 1, 1.0 / kPi);

    const Baked point = bakeFile(testfs::writeText(dir, "point.wrl",
                                       "#VRML V2.0 utf8\n"
                                       "Group { children [ " + floorShape(0.0f) +
                                           " PointLight { location 2.5 10 1 intensity 100 radius 1000 } ] }\n"
                                           "Group { children [ " + floorShape(3.0f) + " ] }\n"));
    CHECK_FALSE(point.bake.scene->lights[0].scoped);
    for (size_t m = 0; m < 2; ++m)
        for (const Vec3& v : point.bake.vertices.values[m]) CHECK(v.x > 0.25f);
}

TEST_CASE("light scope: a VRML 1.0 light lights what follows it in its Separator") {
    TempDir dir;
    const auto floor10 = [](float x0) {
        const std::string a = std::to_string(x0), b = std::to_string(x0 + 2.0f);
        return "Coordinate3 { point [ " + a + " 0 0, " + a + " 0 2, " + b + " 0 2, " + b +
               " 0 0 ] }\nIndexedFaceSet { coordIndex [ 0 1 2 3 -1 ] }\n";
    };
    // Floor 0 precedes the light, floor 1 follows it in its Separator, floor 2 is outside.
    const Baked v1 = bakeFile(testfs::writeText(dir, "separators.wrl",
                                    "#VRML V1.0 ascii\nSeparator {\n Material { diffuseColor 0.5 0.5 0.5 }\n"
                                    " Separator { " + floor10(0.0f) + " DirectionalLight { direction 0 -1 0 } " +
                                        floor10(3.0f) + " }\n " + floor10(6.0f) + "}\n"));
    // VRML 1.0 faces are two-sided by the ShapeHints default: three floors and their back twins,
    // and the light's scope takes in floor 1's twin too.
    REQUIRE(v1.bake.scene->meshes.size() == 6);
    CHECK(v1.bake.scene->lights[0].scope == std::vector<uint32_t>{1, v1.bake.scene->meshes[1].twin});
    checkMesh(v1.bake, 0, 0.0);
    checkMesh(v1.bake, 1, 1.0 / kPi);
    checkMesh(v1.bake, 2, 0.0);
}

TEST_CASE("light scope: a scoped DirectionalLight lights a two-sided wall's back through its twin") {
    // Two solid FALSE walls in the plane z = 0, fronts facing +z; the light, in wall A's Group,
    // shines along +z onto the backs. The twins get new mesh indices (after every original
    // mesh), and the light's scope must take in A's twin: A's back reads E = 1, H / pi = 1 / pi,
    // A's front 0, and B (outside the scope) 0 on both sides.
    TempDir dir;
    const auto wall = [](float x0) {
        const std::string a = std::to_string(x0), b = std::to_string(x0 + 2.0f);
        return "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
               " geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ " + a + " 0 0, " + b + " 0 0, " + b +
               " 2 0, " + a + " 2 0 ] } coordIndex [ 0 1 2 3 -1 ] } }\n";
    };
    const Baked walls = bakeFile(testfs::writeText(dir, "walls.wrl",
                                       "#VRML V2.0 utf8\n"
                                       "Group { children [ " + wall(0.0f) + " DirectionalLight { direction 0 0 1 } ] }\n"
                                       "Group { children [ " + wall(3.0f) + " ] }\n"));
    const Scene& scene = *walls.bake.scene;
    REQUIRE(scene.meshes.size() == 4);
    const uint32_t a_back = scene.meshes[0].twin, b_back = scene.meshes[1].twin;
    REQUIRE(a_back == 2);
    REQUIRE(b_back == 3);
    CHECK(scene.lights[0].scoped);
    CHECK(scene.lights[0].scope == std::vector<uint32_t>{0, a_back});
    checkMesh(walls.bake, a_back, 1.0 / kPi);
    checkMesh(walls.bake, 0, 0.0);
    checkMesh(walls.bake, 1, 0.0);
    checkMesh(walls.bake, b_back, 0.0);
}
