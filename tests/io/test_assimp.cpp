// The Assimp importer through radbake::importScene, on small literal files written here.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "core/memory.h"
#include "io/assimp/gltf_guard.h"
#include "io/import.h"
#include "import_test_support.h"

namespace fs = std::filesystem;
using namespace radbake;
using importtest::TempDir;

namespace {

double totalArea(const Scene& scene) { return summarize(scene).area; }

bool hasMessage(const Diagnostics& diagnostics, Severity severity, const std::string& part) {
    for (const Diagnostic& d : diagnostics.all())
        if (d.severity == severity && d.message.find(part) != std::string::npos) return true;
    return false;
}

int countMessages(const Diagnostics& diagnostics, Severity severity, const std::string& part) {
    int count = 0;
    for (const Diagnostic& d : diagnostics.all())
        if (d.severity == severity && d.message.find(part) != std::string::npos) ++count;
    return count;
}

const Material* findMaterial(const Scene& scene, const std::string& name) {
    for (const Material& m : scene.materials)
        if (m.name == name) return &m;
    return nullptr;
}

const char* kQuadMtl = R"(newmtl white
Kd 0.5 0.6 0.7
newmtl lamp
Kd 0.1 0.1 0.1
Ke 4 5 6
)";

// A 2 x 3 quad in z = 0 and a 1 x 1 emitting quad at z = 2.
const char* kQuadObj = R"(mtllib quad.mtl
v 0 0 0
v 2 0 0
v 2 3 0
v 0 3 0
v 0 0 2
v 0 1 2
v 1 1 2
v 1 0 2
o floor
usemtl white
f 1 2 3 4
o light
usemtl lamp
f 5 6 7 8
)";

// The end of a glTF file whose accessor 0 is one triangle (0,0,0), (1,0,0), (0,1,0).
const std::string kUnitTriangleBuffers = R"(
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "buffers": [{"byteLength": 36,
    "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]
})";

}  // namespace

TEST_CASE("OBJ quad stays one polygon of two triangles; MTL Kd and Ke mapped") {
    TempDir dir;
    dir.write("quad.mtl", kQuadMtl);
    const std::string obj = dir.write("quad.obj", kQuadObj);
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(obj, {}, diagnostics);
    REQUIRE(scene);
    CHECK(diagnostics.errorCount() == 0);
    CHECK(scene->name == "quad");
    REQUIRE(scene->meshes.size() == 2);
    const SceneSummary s = summarize(*scene);
    CHECK(s.polygons == 2);
    CHECK(s.triangles == 4);
    CHECK(s.area == doctest::Approx(7.0).epsilon(1e-9));
    CHECK(s.emitters == 1);
    CHECK(s.bounds_min == Vec3(0, 0, 0));
    CHECK(s.bounds_max == Vec3(2, 3, 2));
    for (const Mesh& mesh : scene->meshes) {
        CHECK(mesh.polygon_count == 1);
        CHECK(mesh.triangles.size() == 2);
        CHECK(mesh.positions.size() == 4);
        CHECK(mesh.triangle_polygon == std::vector<uint32_t>{0, 0});
        CHECK(mesh.location.file == obj);
        CHECK(mesh.solid);  // OBJ promises nothing about sides: one-sided, the front lit
    }
    const Material* white = findMaterial(*scene, "white");
    const Material* lamp = findMaterial(*scene, "lamp");
    REQUIRE(white);
    REQUIRE(lamp);
    CHECK(white->reflectance == Vec3(0.5f, 0.6f, 0.7f));
    CHECK(!white->isEmitter());
    CHECK(lamp->emission == Vec3(4.0f, 5.0f, 6.0f));
    CHECK(lamp->reflectance == Vec3(0.1f));
    // The floor mesh points at "white" and faces up; the light mesh points at "lamp" and
    // faces down: both keep the file's winding.
    for (const Mesh& mesh : scene->meshes) {
        const Material& m = scene->materials.at(mesh.material);
        const bool floor = mesh.positions[0].z == 0.0f;
        CHECK(m.name == (floor ? "white" : "lamp"));
        for (const UVec3& t : mesh.triangles) {
            const Vec3 n =
                glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
            CHECK(n.z == doctest::Approx(floor ? 6.0 : -1.0));  // twice the triangle's area, signed
        }
    }
}

TEST_CASE("--emission-scale multiplies Ke and --unit-scale scales area by its square") {
    TempDir dir;
    dir.write("quad.mtl", kQuadMtl);
    const std::string obj = dir.write("quad.obj", kQuadObj);
    Diagnostics diagnostics;
    ImportOptions options;
    options.unit_scale = 0.01f;  // centimetres
    options.emission_scale = 2.0f;
    std::optional<Scene> scene = importScene(obj, options, diagnostics);
    REQUIRE(scene);
    const SceneSummary s = summarize(*scene);
    CHECK(s.area == doctest::Approx(7.0 * 1e-4).epsilon(1e-6));
    CHECK(s.bounds_max.x == doctest::Approx(0.02));
    CHECK(s.bounds_max.y == doctest::Approx(0.03));
    REQUIRE(findMaterial(*scene, "lamp"));
    CHECK(findMaterial(*scene, "lamp")->emission == Vec3(8.0f, 10.0f, 12.0f));
}

TEST_CASE("concave OBJ polygon: one polygon, exact area") {
    TempDir dir;
    // An L shape: a 2 x 2 square less its 1 x 1 upper-right quarter, area 3; six corners, so
    // four triangles. The loop starts at (2, 0), from where a fan would also cover the
    // missing quarter (area 4, with two overlapping triangles).
    const std::string obj = dir.write("ell.obj", R"(v 2 0 0
v 2 1 0
v 1 1 0
v 1 2 0
v 0 2 0
v 0 0 0
f 1 2 3 4 5 6
)");
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(obj, {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->meshes.size() == 1);
    const Mesh& mesh = scene->meshes[0];
    CHECK(mesh.polygon_count == 1);
    CHECK(mesh.triangles.size() == 4);
    CHECK(totalArea(*scene) == doctest::Approx(3.0).epsilon(1e-9));
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const UVec3 tri = mesh.triangles[t];
        const Vec3 n = glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                                  mesh.positions[tri.z] - mesh.positions[tri.x]);
        CHECK(n.z > 0.0f);  // every triangle keeps the loop's winding
    }
}

TEST_CASE("points and lines are dropped with one counted warning per kind") {
    TempDir dir;
    const std::string obj = dir.write("mixed.obj", R"(v 0 0 0
v 1 0 0
v 1 1 0
v 5 5 5
p 1
p 4
l 1 2
l 2 3 4
f 1 2 3
)");
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(obj, {}, diagnostics);
    REQUIRE(scene);
    const SceneSummary s = summarize(*scene);
    CHECK(s.triangles == 1);
    CHECK(s.area == doctest::Approx(0.5));
    CHECK(countMessages(diagnostics, Severity::Warning, "point primitive(s) ignored") == 1);
    CHECK(countMessages(diagnostics, Severity::Warning, "line primitive(s) ignored") == 1);
    CHECK(hasMessage(diagnostics, Severity::Warning, "2 point primitive(s)"));
    // "l 2 3 4" is a polyline: Assimp makes two segments of it.
    CHECK(hasMessage(diagnostics, Severity::Warning, "3 line primitive(s)"));
    CHECK(s.bounds_max == Vec3(1, 1, 0));  // the point-only vertex is gone
}

TEST_CASE("glTF node transforms are baked into world space") {
    TempDir dir;
    // One triangle (0,0,0) (1,0,0) (0,1,0) under a node translated by (10, 20, 30) inside a
    // parent scaled by 2. Buffer: 3 float3 positions (36 bytes), base64.
    const std::string gltf = dir.write("tri.gltf", R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [
    {"name": "parent", "scale": [2, 2, 2], "children": [1]},
    {"name": "child", "translation": [10, 20, 30], "mesh": 0}
  ],
  "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
  "materials": [{"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [0.25, 0.5, 0.75, 1]},
                 "emissiveFactor": [1, 0, 0]}],
)" + kUnitTriangleBuffers);
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(gltf, {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->meshes.size() == 1);
    const Mesh& mesh = scene->meshes[0];
    REQUIRE(mesh.positions.size() == 3);
    CHECK(mesh.positions[0] == Vec3(20, 40, 60));
    CHECK(mesh.positions[1] == Vec3(22, 40, 60));
    CHECK(mesh.positions[2] == Vec3(20, 42, 60));
    CHECK(totalArea(*scene) == doctest::Approx(2.0));  // 0.5 scaled by 2^2
    CHECK(mesh.name.find("child") != std::string::npos);
    CHECK(mesh.solid);  // glTF materials are single-sided unless marked doubleSided
    const Material& material = scene->materials.at(mesh.material);
    CHECK(material.name == "paint");
    CHECK(material.reflectance == Vec3(0.25f, 0.5f, 0.75f));
    CHECK(material.emission == Vec3(1, 0, 0));
}

TEST_CASE("glTF doubleSided (through Assimp's AI_MATKEY_TWOSIDED) makes a two-sided mesh") {
    TempDir dir;
    // Two one-triangle meshes, one per material: "thin" marked doubleSided, "plain" not.
    const std::string gltf = dir.write("sides.gltf", R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"name": "a", "mesh": 0}, {"name": "b", "mesh": 1}],
  "meshes": [{"name": "thin", "primitives": [{"attributes": {"POSITION": 0}, "material": 0}]},
             {"name": "plain", "primitives": [{"attributes": {"POSITION": 0}, "material": 1}]}],
  "materials": [{"name": "leaf", "doubleSided": true}, {"name": "paint", "doubleSided": false}],
)" + kUnitTriangleBuffers);
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(gltf, {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->meshes.size() == 2);
    for (const Mesh& mesh : scene->meshes) {
        CAPTURE(mesh.name);
        const std::string& material = scene->materials.at(mesh.material).name;
        CHECK(mesh.solid == (material == "paint"));
    }
    CHECK(summarize(*scene).two_sided_meshes == 1);
}

TEST_CASE("a non-finite vertex is a located error and importScene returns nullopt") {
    // 1e39 overflows float to infinity (Assimp reads the text "nan" as a number of its own).
    TempDir dir;
    const std::string obj = dir.write("nan.obj", R"(o bad
v 0 0 0
v 1 0 0
v 1e39 1 0
f 1 2 3
)");
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(obj, {}, diagnostics);
    CHECK(!scene);
    REQUIRE(diagnostics.hasErrors());
    bool located = false;
    for (const Diagnostic& d : diagnostics.all())
        if (d.severity == Severity::Error && d.location.file == obj && d.message.find("not finite") != std::string::npos)
            located = true;
    CHECK(located);
}

TEST_CASE("reflectance above 1 from an MTL file is clamped with a warning naming the material") {
    TempDir dir;
    dir.write("bright.mtl", "newmtl glowing_white\nKd 1.5 0.5 1.0\n");
    const std::string obj = dir.write("bright.obj", "mtllib bright.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl glowing_white\nf 1 2 3\n");
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(obj, {}, diagnostics);
    REQUIRE(scene);
    const Material* m = findMaterial(*scene, "glowing_white");
    REQUIRE(m);
    CHECK(m->reflectance == Vec3(0.999f, 0.5f, 0.999f));
    CHECK(countMessages(diagnostics, Severity::Warning, "'glowing_white'") == 1);
}

TEST_CASE("a missing file and an unreadable file give located errors") {
    TempDir dir;
    SUBCASE("missing") {
        const std::string path = (dir.path / "absent.obj").string();
        Diagnostics diagnostics;
        CHECK(!importScene(path, {}, diagnostics));
        REQUIRE(diagnostics.errorCount() >= 1);
        CHECK(diagnostics.all().back().location.file == path);
    }
    SUBCASE("garbage in a format Assimp cannot read") {
        const std::string path = dir.write("junk.xyzzy", std::string("\x01\x02\x03 not a scene \xff\xfe", 19));
        Diagnostics diagnostics;
        CHECK(!importScene(path, {}, diagnostics));
        REQUIRE(diagnostics.errorCount() == 1);
        const Diagnostic& error = diagnostics.all().back();
        CHECK(error.location.file == path);
        CHECK(error.message.find("Assimp") != std::string::npos);
        CHECK(formatDiagnostic(error).rfind(path + ": error: ", 0) == 0);
    }
    SUBCASE("a directory is not a scene file") {
        Diagnostics diagnostics;
        CHECK(!importScene(dir.path.string(), {}, diagnostics));
        REQUIRE(diagnostics.errorCount() == 1);
        CHECK(diagnostics.all().back().location.file == dir.path.string());
    }
    SUBCASE("a file without read permission") {
        const std::string path = dir.write("locked.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        fs::permissions(path, fs::perms::none);
        std::ifstream probe(path);
        if (probe.good()) {
            MESSAGE("running as root: permissions are not enforced, subcase skipped");
            return;
        }
        Diagnostics diagnostics;
        CHECK(!importScene(path, {}, diagnostics));
        REQUIRE(diagnostics.errorCount() >= 1);
        CHECK(diagnostics.all().back().location.file == path);
    }
}

TEST_CASE("an OBJ face index out of range is a located error, not a crash") {
    TempDir dir;
    const std::string obj = dir.write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(obj, {}, diagnostics);
    // Assimp rejects the index itself; either way the scene must not contain it.
    if (scene) {
        for (const Mesh& mesh : scene->meshes)
            for (const UVec3& t : mesh.triangles) CHECK(glm::all(glm::lessThan(t, UVec3(mesh.positions.size()))));
    } else {
        REQUIRE(diagnostics.errorCount() >= 1);
        CHECK(diagnostics.all().back().location.file == obj);
    }
}

TEST_CASE("mirroring node transform keeps the front face (winding reversed)") {
    TempDir dir;
    // Same triangle as above under a node scaled by (-1, 1, 1): the geometric normal must stay +z.
    const std::string gltf = dir.write("mirror.gltf", R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [{"name": "m", "scale": [-1, 1, 1], "mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
)" + kUnitTriangleBuffers);
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(gltf, {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->meshes.size() == 1);
    const Mesh& mesh = scene->meshes[0];
    const UVec3 t = mesh.triangles.at(0);
    const Vec3 n = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
    CHECK(n.z > 0.0f);
    CHECK(summarize(*scene).bounds_min.x == -1.0f);
}

TEST_CASE("glTF punctual lights and a camera are placed by their nodes") {
    TempDir dir;
    // bulb: point light at (1, 2, 3); sun: directional, node turned -90 degrees about x so
    // its -z points down; cone: spot light with half-angles 0.25 / 0.5; eye: camera at
    // (0, 1, 10) with yfov 0.6 and aspect 1.5 (so 0.6 is the smaller angle).
    const std::string gltf = dir.write("lights.gltf", R"({
  "asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"name": "bulb", "type": "point", "color": [1, 0.5, 0.25], "intensity": 8},
    {"name": "sun", "type": "directional", "intensity": 2},
    {"name": "cone", "type": "spot", "intensity": 1, "spot": {"innerConeAngle": 0.25, "outerConeAngle": 0.5}}]}},
  "scene": 0,
  "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
  "nodes": [
    {"name": "tri", "mesh": 0},
    {"name": "bulbNode", "translation": [1, 2, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"name": "sunNode", "rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"name": "coneNode", "translation": [0, 5, 0], "extensions": {"KHR_lights_punctual": {"light": 2}}},
    {"name": "eye", "translation": [0, 1, 10], "camera": 0}
  ],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "aspectRatio": 1.5, "znear": 0.1}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]
})");
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(gltf, {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->lights.size() == 3);
    const Light* bulb = nullptr;
    const Light* sun = nullptr;
    const Light* cone = nullptr;
    for (const Light& light : scene->lights) {
        if (light.type == LightType::Point) bulb = &light;
        if (light.type == LightType::Directional) sun = &light;
        if (light.type == LightType::Spot) cone = &light;
    }
    REQUIRE(bulb);
    REQUIRE(sun);
    REQUIRE(cone);
    CHECK(bulb->position == Vec3(1, 2, 3));
    CHECK(bulb->intensity == doctest::Approx(8.0));
    CHECK(bulb->color.x == doctest::Approx(1.0));
    CHECK(bulb->color.y == doctest::Approx(0.5));
    CHECK(bulb->color.z == doctest::Approx(0.25));
    CHECK(bulb->location.file == gltf);
    CHECK(sun->direction.x == doctest::Approx(0.0).epsilon(1e-6));
    CHECK(sun->direction.y == doctest::Approx(-1.0).epsilon(1e-6));
    CHECK(sun->direction.z == doctest::Approx(0.0).epsilon(1e-6));
    CHECK(cone->position == Vec3(0, 5, 0));
    CHECK(cone->beam_width == doctest::Approx(0.25));
    CHECK(cone->cut_off_angle == doctest::Approx(0.5));

    REQUIRE(scene->cameras.size() == 1);
    const Camera& eye = scene->cameras[0];
    CHECK(eye.position == Vec3(0, 1, 10));
    CHECK(eye.field_of_view == doctest::Approx(0.6).epsilon(1e-5));
    // Looking down -z with +y up, as the default view: the identity rotation.
    const Vec3 forward = eye.orientation * Vec3(0, 0, -1);
    const Vec3 up = eye.orientation * Vec3(0, 1, 0);
    CHECK(forward.z == doctest::Approx(-1.0).epsilon(1e-6));
    CHECK(up.y == doctest::Approx(1.0).epsilon(1e-6));
    CHECK(summarize(*scene).lights == 3);
}

TEST_CASE("an ASCII PLY quad is one polygon of two triangles") {
    TempDir dir;
    const std::string ply = dir.write("quad.ply", R"(ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 1
property list uchar int vertex_indices
end_header
0 0 0
4 0 0
4 2 0
0 2 0
4 0 1 2 3
)");
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(ply, {}, diagnostics);
    REQUIRE(scene);
    const SceneSummary s = summarize(*scene);
    CHECK(s.polygons == 1);
    CHECK(s.triangles == 2);
    CHECK(s.area == doctest::Approx(8.0));
    CHECK(s.bounds_max == Vec3(4, 2, 0));
}

TEST_CASE("OBJ degenerate polygon and unused vertices: dropped and counted in exactly one warning") {
    TempDir dir;
    // Face 1 is a good triangle; face 2 a quad whose corners all lie on one line (two
    // degenerate triangles); vertex 8 is used by nothing (Assimp leaves it out of the mesh,
    // so only the quad's four vertices are counted unused).
    const std::string obj = dir.write("flat.obj", R"(o thing
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 5
v 1 0 5
v 2 0 5
v 3 0 5
v 9 9 9
f 1 2 3
f 4 5 6 7
)");
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(obj, {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(diagnostics.warningCount() == 1);
    CHECK(diagnostics.all()[0].message ==
          "mesh 'thing': dropped 2 degenerate triangle(s), 4 unused vertex(es), 1 polygon(s) left without triangles");
    CHECK(diagnostics.all()[0].location.file == obj);
    const SceneSummary s = summarize(*scene);
    CHECK(s.polygons == 1);
    CHECK(s.triangles == 1);
    CHECK(s.bounds_max == Vec3(1, 1, 0));
}

// ---------------------------------------------------------------------------------------
// Regressions from tools/fuzz (docs/fuzzing.md).

TEST_CASE("fuzz: an OBJ whose mtllib resolves to a folder reads as a missing MTL, not a failed read") {
    // fuzz_assimp_obj, minimized: `mtllib i\\` (plus bytes Assimp ignores). Assimp 5.2.5 tries
    // variants of the name, one of them the OBJ's own folder; fopen opens a folder on Linux,
    // the read fails with EISDIR, the OBJ importer throws and leaks the stream (LeakSanitizer).
    // The reader now opens regular files only.
    TempDir dir;
    const std::string minimized("mtllib i\\\\\0\0\0\"\0\0", 16);
    const std::string obj = dir.write("input.obj", minimized);
    Diagnostics diagnostics;
    const std::optional<Scene> scene = importScene(obj, {}, diagnostics);
    // Nothing to bake, but a clean answer: no exception from inside Assimp reached us.
    for (const Diagnostic& d : diagnostics.all()) {
        CHECK(d.location.file == obj);
        CHECK(d.message.find("exception") == std::string::npos);
        CHECK(d.message.find("Is a directory") == std::string::npos);
    }
    if (scene) CHECK(scene->meshes.empty());

    // A usable scene whose mtllib names a folder: the folder is never read, the mesh is kept
    // with the default material and a warning about the MTL.
    TempDir with_folder;
    std::filesystem::create_directories(with_folder.path / "materials.mtl");
    const std::string tri = with_folder.write("tri.obj", "mtllib materials.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    Diagnostics tri_diagnostics;
    const std::optional<Scene> tri_scene = importScene(tri, {}, tri_diagnostics);
    REQUIRE(tri_scene);
    CHECK(tri_diagnostics.errorCount() == 0);
    REQUIRE(tri_scene->meshes.size() == 1);
    CHECK(totalArea(*tri_scene) == doctest::Approx(0.5));
    CHECK(hasMessage(tri_diagnostics, Severity::Warning, "materials.mtl"));
    // Refused by name, never read; still an input (a file put in its place rebuilds).
    REQUIRE(tri_scene->refused_inputs.size() == 1);
    CHECK(std::filesystem::path(tri_scene->refused_inputs.front()).filename() == "materials.mtl");
}

TEST_CASE("fuzz: a PLY header without end_header is a located error before Assimp reads it") {
    // fuzz_assimp_ply, minimized: Assimp 5.2.5's PLY importer runs past its buffer when the
    // header does not end (SEGV under ASan; without ASan memory can grow without bound), and
    // hangs when end_header is the file's last bytes.
    TempDir dir;
    const std::string no_end("ply\nformat binary_tm\0\0", 22);
    const std::string not_a_token("ply\nformat binary_\nend_header\x03z\n\0\x03", 34);
    for (const std::string& text : {no_end, not_a_token, std::string("ply\nformat binary_little_endian 1.0\n"),
                                    std::string("PLY\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\n"),
                                    std::string("ply\nformat binary_nz\nty uchdices\nend_header")}) {
        CAPTURE(text);
        const std::string ply = dir.write("broken.ply", text);
        Diagnostics diagnostics;
        CHECK_FALSE(importScene(ply, {}, diagnostics));
        REQUIRE(diagnostics.errorCount() == 1);
        const Diagnostic& error = diagnostics.all().back();
        CHECK(error.location.file == ply);
        CHECK(error.location.line == 1);
        CHECK(error.message.find("end_header") != std::string::npos);
    }
    // A complete header (ASCII, CRLF, indented end_header) still reaches Assimp and reads.
    const std::string good = dir.write("good.ply", "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\n"
                                                   "property float y\r\nproperty float z\r\nelement face 1\r\n"
                                                   "property list uchar int vertex_indices\r\n  end_header\r\n"
                                                   "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n");
    Diagnostics diagnostics;
    const std::optional<Scene> scene = importScene(good, {}, diagnostics);
    REQUIRE(scene);
    CHECK(totalArea(*scene) == doctest::Approx(0.5));
}

namespace {

// A glTF 2.0 triangle, its buffer embedded; `before_asset` goes first in the top-level object.
std::string gltfTriangle(const std::string& before_asset = "") {
    return "{" + before_asset + R"("asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
                                R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
                                R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],)"
                                R"("bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":36,)"
                                R"("uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
}

// The error importScene reports for `text` written as `name`, which must fail with one error.
Diagnostic refusal(const TempDir& dir, const std::string& name, const std::string& text) {
    return importtest::refusal(dir.write(name, text));
}

std::string little32(uint32_t value) {
    std::string bytes(4, '\0');
    for (int i = 0; i < 4; ++i) bytes[static_cast<size_t>(i)] = static_cast<char>((value >> (8 * i)) & 0xff);
    return bytes;
}

}  // namespace

TEST_CASE("fuzz: glTF 1.0 is a located error before Assimp reads it") {
    // fuzz_assimp_gltf: Assimp 5.2.5 tries its glTF 1.0 reader on every .gltf and .glb file,
    // and that reader leaks every object it was building when the file is malformed (here a
    // buffer shorter than its byteLength: 2.5 KB per import under LeakSanitizer, reported as
    // "No suitable reader found"). glTF 1.0 is refused by its asset.version instead.
    TempDir dir;
    const std::string broken_v1 =
        R"({"asset":{"version":"1.0"},"scene":"s","scenes":{"s":{"nodes":["n"]}},"nodes":{"n":{"meshes":["m"]}},)"
        R"("meshes":{"m":{"primitives":[{"attributes":{"POSITION":"p"}}]}},)"
        R"("accessors":{"p":{"bufferView":"v","count":3,"componentType":5126,"type":"VEC3"}},)"
        R"("bufferViews":{"v":{"buffer":"b","byteLength":36}},)"
        R"("buffers":{"b":{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAA"}}})";
    // Whatever the extension, and however many blanks Assimp's JSON parser would skip.
    const std::pair<std::string, std::string> files[] = {
        {"v1.gltf", "\xEF\xBB\xBF \n"}, {"v1.json", std::string(5000, ' ')}, {"v1.obj", ""}};
    for (const auto& [name, before] : files) {
        const Diagnostic error = refusal(dir, name, before + broken_v1);
        CHECK(error.location.line == 1);
        CHECK(error.message.find("glTF version '1.0' is not read") != std::string::npos);
    }
    // Binary glTF 1.0 (KHR_binary_glTF: version 1, one JSON content block).
    const std::string glb_v1 = "glTF" + little32(1) + little32(20 + static_cast<uint32_t>(broken_v1.size())) +
                               little32(static_cast<uint32_t>(broken_v1.size())) + little32(0) + broken_v1;
    CHECK(refusal(dir, "v1.glb", glb_v1).message.find("binary glTF 1.0") != std::string::npos);
    // A glb version 2 whose JSON says 1.0, with the byte the JSON starts at named.
    const std::string json_v1 = R"({"asset":{"version":"1.0"}})";
    const std::string glb_v2 = "glTF" + little32(2) + little32(20 + static_cast<uint32_t>(json_v1.size())) +
                               little32(static_cast<uint32_t>(json_v1.size())) + little32(0x4E4F534A) + json_v1;
    CHECK(refusal(dir, "mixed.glb", glb_v2).message.find("glTF version '1.0'") != std::string::npos);
    // JSON that is not glTF 2.0 at all, and JSON broken before its version.
    CHECK(refusal(dir, "none.gltf", R"({"scenes":[]})").message.find("without a top-level asset.version") != std::string::npos);
    const Diagnostic malformed = refusal(dir, "broken.gltf", "{\n  \"scenes\": [}\n");
    CHECK(malformed.location.line == 2);
    CHECK(malformed.message.find("malformed") != std::string::npos);
}

TEST_CASE("fuzz: glTF JSON nested too deep is a located error before Assimp reads it") {
    // Assimp 5.2.5 parses glTF JSON recursively: a 400 KB file of nested arrays overflows the
    // stack (radbake info: SIGSEGV). Nesting is bounded before Assimp sees the file.
    TempDir dir;
    const size_t levels = 200'000;
    const Diagnostic error =
        refusal(dir, "deep.gltf", gltfTriangle(R"("extras":)" + std::string(levels, '[') + std::string(levels, ']') + ","));
    CHECK(error.location.line == 1);
    CHECK(error.location.column == 10 + kMaxGltfNesting);  // the first '[' too deep
    CHECK(error.message.find("nests") != std::string::npos);
}

TEST_CASE("fuzz: a glTF data: URI with a byte that is not base64 is a located error before Assimp reads it") {
    // fuzz_assimp_gltf: Assimp 5.2.5's base64 decoder allocates its output, then throws on a
    // byte above 0x7f and leaks the output (LeakSanitizer; 104 bytes for this buffer).
    TempDir dir;
    const std::string good = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
    // Each replaces as many characters as it decodes to, so the payload keeps its length.
    const std::pair<std::string, size_t> bad_bytes[] = {{"\xf0", 1}, {"\\u00e9", 2}, {"\\ud83d\\ude00", 4}};
    for (const auto& [bad, decoded] : bad_bytes) {
        std::string text = gltfTriangle();
        text.replace(text.find(good) + 40, decoded, bad);
        CAPTURE(text);
        const Diagnostic error = refusal(dir, "uri.gltf", text);
        CHECK(error.location.line == 1);
        CHECK(error.location.column == static_cast<int>(text.find("\"data:") + 1));
        CHECK(error.message.find("data: URI") != std::string::npos);
    }
    // fuzz_assimp_gltf, 30 minutes: Assimp keeps where a data: URI's parts start in chars, so
    // past 127 bytes of header it decodes from before the string (here into the JSON before
    // it; a leak again when that holds a high byte). Real headers are short.
    std::string long_header = gltfTriangle();
    long_header.insert(long_header.find("octet-stream") + 12, ";x=" + std::string(100, 'y'));
    const Diagnostic error = refusal(dir, "header.gltf", long_header);
    CHECK(error.location.column == static_cast<int>(long_header.find("\"data:") + 1));
    CHECK(error.message.find("data: URI") != std::string::npos);
}

TEST_CASE("fuzz: glTF 2.0 still reads past the glTF checks") {
    TempDir dir;
    // The asset after other keys, moderate nesting, brackets inside strings.
    const std::string nested = R"("extras":{"a":[[[[[[[[{"b":"[[[[{{{{\"]"}]]]]]]]]},"generator":"}",)";
    std::string escaped = gltfTriangle();  // escapes in a URI are decoded, as Assimp's parser does
    escaped.replace(escaped.find("data:"), 5, "d\\u0061ta:");
    for (const std::string& text : {gltfTriangle(), gltfTriangle(nested), escaped}) {
        CAPTURE(text);
        Diagnostics diagnostics;
        const std::optional<Scene> scene = importScene(dir.write("tri.gltf", text), {}, diagnostics);
        REQUIRE(scene);
        CHECK(totalArea(*scene) == doctest::Approx(0.5));
    }
}

TEST_CASE("fuzz: a file is read by the importers of its extension, its format not guessed from the content") {
    // fuzz_assimp_gltf, 20 bytes: refused by both glTF importers, Assimp 5.2.5 guessed the
    // format from the content and read it as OpenGEX ("IndexArray"), whose parser reads past
    // its buffer (heap-buffer-overflow in strlen under ASan).
    TempDir dir;
    const Diagnostic error = refusal(dir, "opengex.gltf", "indexarray\"--------,\n");
    CHECK(error.message.find("No suitable reader") != std::string::npos);
    // Nor is an OBJ named .gltf read as OBJ; with an extension no importer claims it still is.
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    CHECK(refusal(dir, "obj.gltf", obj).message.find("No suitable reader") != std::string::npos);
    Diagnostics diagnostics;
    const std::optional<Scene> scene = importScene(dir.write("obj.dat", obj), {}, diagnostics);
    REQUIRE(scene);
    CHECK(totalArea(*scene) == doctest::Approx(0.5));
    // OpenGEX is never read: not by its extension, not guessed from the content.
    CHECK(refusal(dir, "scene.OGEX", "indexarray\"--------,\n").message.find("OpenGEX files are not read") != std::string::npos);
    CHECK(refusal(dir, "opengex.dat", "indexarray\"--------,\n").message.find("No suitable reader") != std::string::npos);
}

namespace {

// The import fails with a located error from the OBJ check (so Assimp never read the file).
void checkObjRefused(const std::string& path, int line, const std::string& part) {
    const Diagnostic error = importtest::refusal(path);
    CHECK(error.location.line == line);
    CHECK_MESSAGE(error.message.find(part) != std::string::npos, error.message);
}

}  // namespace

TEST_CASE("fuzz: an OBJ statement naming a vertex that is not there is refused before Assimp reads it") {
    TempDir dir;
    // Assimp 5.2.5 leaks the meshes it finished when a later one fails ("vertex index out of
    // range", "no vertices"): finding 3's minimized input and finding 10's kind.
    checkObjRefused(dir.write("finding3.obj", std::string("l\nv 0 0 0\nv 1 0 0\nv 0 1 0\n\xa1 1 2 3\nusemtl 3\n2\nf 1 2 3\n"
                                                          "usemtl h -1\nlp 3\n")),
                    10, "single vertex");
    checkObjRefused(dir.write("later.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\no a\nf 1 2 3\no b\nf 1 2 9\n"), 7,
                    "names vertex 9, but the file defines 3 vertices");
    // Of an extension no importer claims, the OBJ importer may take it by its content.
    checkObjRefused(dir.write("later.data", "v 0 0 0\nv 1 0 0\nv 0 1 0\no a\nf 1 2 3\no b\nf 1 2 9\n"), 7,
                    "names vertex 9, but the file defines 3 vertices");
    checkObjRefused(dir.write("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\nv 0 0 1\n"), 4, "names vertex -4");
    // A vertex inside a cstype section is not a vertex to Assimp.
    checkObjRefused(dir.write("cstype.obj", "v 0 0 0\nv 1 0 0\ncstype bspline\nv 0 1 0\nend\nf 1 2 3\n"), 6,
                    "names vertex 3, but the file defines 2 vertices");
    // Two components are not a vertex either.
    checkObjRefused(dir.write("short.obj", "v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n"), 4, "defines 2 vertices");
    // Statements Assimp reads past their line's end.
    checkObjRefused(dir.write("parts.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1/1 2 3\n"), 6,
                    "more than three parts");
    checkObjRefused(dir.write("vtab.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \v3\n"), 4, "vertical tab");
    checkObjRefused(dir.write("huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2147483648\n"), 4, "beyond the range of an int");
    // Without texture coordinates Assimp takes a corner's second part as its normal.
    checkObjRefused(dir.write("normal_parts.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1/1/1 2 3\n"), 5,
                    "more than three parts");
}

TEST_CASE("fuzz: OBJ files Assimp reads pass the OBJ check") {
    TempDir dir;
    const std::string header = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n";
    for (const std::string& body : {std::string("f 1 2 3\n"), std::string("f -3 -2 -1\n"), std::string("f 1/1 2/2 3/3\n"),
                                    std::string("f 1/1/1 2/2/1 3/3/1\n"), std::string("f 1//1 2//1 3//1\n"),
                                    std::string("f 1 2 \\\n3\n"), std::string("f\t1\t2\t3\r\n"), std::string("f +1 02 3\n"),
                                    std::string("cstype bspline\nf 1 2 9\nend\nf 1 2 3\n"), std::string("# f 9 9 9\nf 1 2 3\n")}) {
        CAPTURE(body);
        Diagnostics diagnostics;
        std::optional<Scene> scene = importScene(dir.write("ok.obj", header + body), {}, diagnostics);
        REQUIRE(scene);
        CHECK(summarize(*scene).triangles == 1);
        CHECK(summarize(*scene).area == doctest::Approx(0.5));
    }
    // A face index that is not a number: Assimp refuses the file itself, with no leak.
    Diagnostics diagnostics;
    CHECK_FALSE(importScene(dir.write("word.obj", header + "f 1 2 x\n"), {}, diagnostics));
    CHECK(hasMessage(diagnostics, Severity::Error, "Invalid face index"));
}

TEST_CASE("memory: an Assimp read and the scene it yields are asked of --max-memory first, a located error when over") {
    TempDir dir;
    std::string grid = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    std::string faces;
    for (int i = 0; i < 500000; ++i) faces += "f 1 2 3\n";
    const std::string path = dir.write("many.obj", grid + faces);
    {
        // 16 bytes of reading per byte of the file do not fit in 20 MiB more than now.
        ImportOptions options;
        options.max_memory_mb = residentMegabytes() + 20.0;
        Diagnostics diagnostics;
        CHECK_FALSE(importScene(path, options, diagnostics));
        REQUIRE(diagnostics.errorCount() == 1);
        CHECK(diagnostics.all().back().location.file == path);
        CHECK(hasMessage(diagnostics, Severity::Error, "file with Assimp takes about 61 MiB"));
    }
    {
        // The read fits, the 500,000 triangles it yields (over 100 MiB through the import) do not.
        ImportOptions options;
        options.max_memory_mb = residentMegabytes() + 100.0;
        Diagnostics diagnostics;
        CHECK_FALSE(importScene(path, options, diagnostics));
        CHECK(hasMessage(diagnostics, Severity::Error, "the file expands to 500000 triangles in 1 mesh"));
    }
}
