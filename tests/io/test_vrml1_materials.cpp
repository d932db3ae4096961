// VRML 1.0 reader: materials and their bindings (split into one mesh per material), lights,
// cameras and WWWInline, on small literal files read through importScene.
#include <doctest/doctest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <unistd.h>

#include "io/import.h"
#include "test_vrml1_support.h"

using namespace radbake;
namespace fs = std::filesystem;

namespace {

using namespace vrml1_test;

Read read(const std::string& body) { return readAt(tempDir() / "m.wrl", body); }

bool near(const Vec3& a, const Vec3& b, float tolerance = 1e-5f) { return glm::length(a - b) <= tolerance; }

Vec3 reflectanceOf(const Scene& scene, const Mesh& mesh) { return scene.materials[mesh.material].reflectance; }

// Three unit squares side by side along x, one face each.
const char* kThreeSquares = R"(
  Coordinate3 { point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0,  2 0 0, 2 1 0,  3 0 0, 3 1 0 ] }
)";
const char* kFaces = "  IndexedFaceSet { coordIndex [ 0 1 2 3 -1, 1 4 5 2 -1, 4 6 7 5 -1 ] ";
const char* kThreeMaterials = R"(
  Material { diffuseColor [ 0.5 0 0, 0 0.5 0, 0 0 0.5 ] emissiveColor [ 0 0 0, 0 0 0, 2 3 4 ] }
)";

float minX(const Mesh& mesh) {
    float x = 1e30f;
    for (const Vec3& p : mesh.positions) x = std::min(x, p.x);
    return x;
}

}  // namespace

TEST_CASE("vrml1 materials: OVERALL and the default binding use material 0") {
    const Read r = read(std::string("Separator {") + kThreeSquares + kThreeMaterials + kFaces + "}\n}\n");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 1);
    CHECK(r.scene->meshes[0].polygon_count == 3);
    CHECK(reflectanceOf(*r.scene, r.scene->meshes[0]) == Vec3(0.5f, 0.0f, 0.0f));
    CHECK(r.scene->materials.size() == 1);
    CHECK(r.scene->materials[0].name == "Material[0]");
}

TEST_CASE("vrml1 materials: PER_FACE splits one mesh per material, in material order") {
    const Read r = read(std::string("Separator {") + kThreeSquares + kThreeMaterials +
                        "  MaterialBinding { value PER_FACE }\n" + kFaces + "}\n}\n");
    REQUIRE(r.scene);
    const auto& m = r.scene->meshes;
    REQUIRE(m.size() == 3);
    for (int i = 0; i < 3; ++i) {
        CHECK(m[i].polygon_count == 1);
        CHECK(m[i].triangles.size() == 2);
        CHECK(m[i].positions.size() == 4);  // only the vertices this mesh uses
        CHECK(minX(m[i]) == static_cast<float>(i));
        CHECK(m[i].triangle_polygon == std::vector<uint32_t>{0, 0});
    }
    CHECK(reflectanceOf(*r.scene, m[1]) == Vec3(0.0f, 0.5f, 0.0f));
    CHECK(r.scene->materials[m[2].material].emission == Vec3(2.0f, 3.0f, 4.0f));
    CHECK(r.scene->materials[m[2].material].isEmitter());
    CHECK_FALSE(r.scene->materials[m[0].material].isEmitter());
    const SceneSummary summary = summarize(*r.scene);
    CHECK(summary.emitters == 1);
    CHECK(summary.polygons == 3);
}

TEST_CASE("vrml1 materials: PER_FACE_INDEXED and PER_PART_INDEXED follow materialIndex") {
    for (const char* binding : {"PER_FACE_INDEXED", "PER_PART_INDEXED"}) {
        CAPTURE(binding);
        const Read r = read(std::string("Separator {") + kThreeSquares + kThreeMaterials +
                            "  MaterialBinding { value " + binding + " }\n" + kFaces +
                            " materialIndex [ 2, 0, 2 ] }\n}\n");
        REQUIRE(r.scene);
        const auto& m = r.scene->meshes;
        REQUIRE(m.size() == 2);
        CHECK(reflectanceOf(*r.scene, m[0]) == Vec3(0.5f, 0.0f, 0.0f));
        CHECK(m[0].polygon_count == 1);
        CHECK(minX(m[0]) == 1.0f);
        CHECK(reflectanceOf(*r.scene, m[1]) == Vec3(0.0f, 0.0f, 0.5f));
        CHECK(m[1].polygon_count == 2);  // faces 0 and 2, renumbered 0 and 1
        CHECK(m[1].triangle_polygon == std::vector<uint32_t>{0, 0, 1, 1});
        CHECK(m[1].positions.size() == 8);
    }
}

TEST_CASE("vrml1 materials: PER_VERTEX_INDEXED takes each face's first corner; out of range -> 0") {
    const Read r = read(std::string("Separator {") + kThreeSquares + kThreeMaterials +
                        "  MaterialBinding { value PER_VERTEX_INDEXED }\n" + kFaces +
                        " materialIndex [ 1 1 1 1 -1, 2 0 0 0 -1, 7 1 1 1 -1 ] }\n}\n");
    REQUIRE(r.scene);
    const auto& m = r.scene->meshes;
    REQUIRE(m.size() == 3);
    CHECK(minX(m[0]) == 2.0f);  // material 7 does not exist: material 0
    CHECK(reflectanceOf(*r.scene, m[0]) == Vec3(0.5f, 0.0f, 0.0f));
    CHECK(minX(m[1]) == 0.0f);
    CHECK(reflectanceOf(*r.scene, m[1]) == Vec3(0.0f, 0.5f, 0.0f));
    CHECK(minX(m[2]) == 1.0f);
    CHECK(r.count(Severity::Warning, "1 face(s) with a material index out of range (3 materials)") == 1);
    CHECK(r.count(Severity::Warning, "per-vertex materials reduced to one per face") == 1);
}

TEST_CASE("vrml1 materials: PER_VERTEX without an index counts corners") {
    // Corners 0..3 are face 0, 4..7 face 1, 8..11 face 2: each face takes its first corner's.
    const Read r = read(std::string("Separator {") + kThreeSquares +
                        "  Material { diffuseColor [ 0.1 0.1 0.1, 0.2 0.2 0.2, 0.3 0.3 0.3, 0.4 0.4 0.4, "
                        "0.5 0.5 0.5, 0.6 0.6 0.6, 0.7 0.7 0.7, 0.8 0.8 0.8, 0.9 0.9 0.9 ] }\n"
                        "  MaterialBinding { value PER_VERTEX }\n" +
                        kFaces + "}\n}\n");
    REQUIRE(r.scene);
    const auto& m = r.scene->meshes;
    REQUIRE(m.size() == 3);
    CHECK(reflectanceOf(*r.scene, m[0]) == Vec3(0.1f));
    CHECK(reflectanceOf(*r.scene, m[1]) == Vec3(0.5f));
    CHECK(reflectanceOf(*r.scene, m[2]) == Vec3(0.9f));
}

TEST_CASE("vrml1 materials: shorter lists fall back to their first entry; ambient and transparency kept") {
    const Read r = read(R"(Separator {
  DEF Paint Material { diffuseColor [ 0.2 0.4 0.6, 0.8 0.6 0.4 ] ambientColor 0.1 0.2 0.3 transparency [ 0.25 ] }
  MaterialBinding { value PER_PART }
  Cube { }
})");
    REQUIRE(r.scene);
    const auto& m = r.scene->meshes;
    REQUIRE(m.size() == 2);  // parts 0 and 1 (front, back) have their own; the rest fall to 0
    CHECK(m[0].polygon_count == 5);
    CHECK(m[1].polygon_count == 1);
    const Material& second = r.scene->materials[m[1].material];
    CHECK(second.name == "Paint[1]");
    CHECK(second.reflectance == Vec3(0.8f, 0.6f, 0.4f));
    CHECK(second.transparency == 0.25f);
    // ambient 0.6 in sum against diffuse 1.8: VRML97's ambientIntensity 1/3
    CHECK(second.ambient_intensity == doctest::Approx(1.0 / 3.0));
    // The back face (-Z) carries material 1.
    for (const Vec3& p : m[1].positions) CHECK(p.z == -1.0f);
    CHECK_FALSE(m[0].convex_solid);  // split over two meshes: neither is the whole solid
}

TEST_CASE("vrml1 materials: Cube PER_FACE numbers front, back, left, right, top, bottom") {
    const Read r = read(R"(Separator {
  Material { diffuseColor [ 0 0 0.1, 0 0 0.2, 0.1 0 0, 0.2 0 0, 0 0.1 0, 0 0.2 0 ] }
  MaterialBinding { value PER_FACE }
  Cube { }
})");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 6);
    for (const Mesh& mesh : r.scene->meshes) {
        const Vec3 c = (mesh.positions[0] + mesh.positions[1] + mesh.positions[2] + mesh.positions[3]) * 0.25f;
        const Vec3 rho = reflectanceOf(*r.scene, mesh);
        // Each face's centre lies on the axis its colour names, on the side its value says.
        const Vec3 expected_centre = Vec3(rho.x == 0.1f ? -1.0f : rho.x == 0.2f ? 1.0f : 0.0f,
                                          rho.y == 0.1f ? 1.0f : rho.y == 0.2f ? -1.0f : 0.0f,
                                          rho.z == 0.1f ? 1.0f : rho.z == 0.2f ? -1.0f : 0.0f);
        CHECK(near(c, expected_centre));
    }
}

TEST_CASE("vrml1 lights are placed in world space") {
    const Read r = read(R"(Separator {
  Translation { translation 1 2 3 }
  PointLight { location 1 0 0 color 1 0.5 0.25 intensity 0.75 }
  Rotation { rotation 0 1 0 1.5707963 }
  DirectionalLight { direction 0 0 -1 }
  SpotLight { location 0 0 1 direction 0 0 -1 cutOffAngle 0.5 dropOffRate 0 on FALSE }
})");
    REQUIRE(r.scene);
    const auto& l = r.scene->lights;
    REQUIRE(l.size() == 3);
    CHECK(l[0].type == LightType::Point);
    CHECK(near(l[0].position, Vec3(2.0f, 2.0f, 3.0f)));
    CHECK(l[0].color == Vec3(1.0f, 0.5f, 0.25f));
    CHECK(l[0].intensity == 0.75f);
    CHECK(std::isinf(l[0].radius));
    CHECK(l[0].location.line == 4);
    // R_y(90) maps -Z to -X.
    CHECK(l[1].type == LightType::Directional);
    CHECK(near(l[1].direction, Vec3(-1.0f, 0.0f, 0.0f)));
    CHECK(l[2].type == LightType::Spot);
    CHECK(near(l[2].position, Vec3(2.0f, 2.0f, 3.0f)));  // (0,0,1) -> (1,0,0) -> + (1,2,3)
    CHECK(near(l[2].direction, Vec3(-1.0f, 0.0f, 0.0f)));
    CHECK(l[2].cut_off_angle == 0.5f);
    CHECK(l[2].beam_width == 0.5f);
    CHECK_FALSE(l[2].on);
}

TEST_CASE("vrml1 PerspectiveCamera keeps position, orientation and heightAngle") {
    const Read r = read(R"(Separator {
  Translation { translation 0 0 -10 }
  DEF Front PerspectiveCamera { position 0 1 5 orientation 0 1 0 3.14159265 heightAngle 0.5 }
})");
    REQUIRE(r.scene);
    REQUIRE(r.scene->cameras.size() == 1);
    const Camera& c = r.scene->cameras[0];
    CHECK(c.name == "Front");
    CHECK(near(c.position, Vec3(0.0f, 1.0f, -5.0f)));
    CHECK(c.field_of_view == 0.5f);
    // The default view looks down -Z; turned half way round it looks down +Z.
    CHECK(near(c.orientation * Vec3(0.0f, 0.0f, -1.0f), Vec3(0.0f, 0.0f, 1.0f)));
    CHECK(near(c.orientation * Vec3(0.0f, 1.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f)));
}

TEST_CASE("vrml1 WWWInline places the inlined file and guards against recursion") {
    const fs::path dir = tempDir();
    writeFile(dir / "Part.wrl", "#VRML V1.0 ascii\nSeparator {\n  Cube { }\n  PointLight { location 0 0 0 }\n}\n");
    writeFile(dir / "loop.wrl", "#VRML V1.0 ascii\nSeparator { Sphere { } WWWInline { name \"loop.wrl\" } }\n");
    writeFile(dir / "main.wrl", R"(#VRML V1.0 ascii
Separator {
  Translation { translation 10 0 0 }
  WWWInline { name "Part.wrl" bboxSize 2 2 2 }
  Scale { scaleFactor 1 1 -1 }
  WWWInline { name "part.wrl" }
  WWWInline { name "loop.wrl" }
  WWWInline { name "http://example.com/remote.wrl" }
}
)");
    const Read r = readPath(dir / "main.wrl");
    REQUIRE(r.scene);
    const auto& m = r.scene->meshes;
    REQUIRE(m.size() == 3);  // two cubes, the looping file's sphere once
    float lo = 1e30f, hi = -1e30f;
    for (const Vec3& p : m[0].positions) {
        lo = std::min(lo, p.x);
        hi = std::max(hi, p.x);
    }
    CHECK(lo == 9.0f);
    CHECK(hi == 11.0f);
    REQUIRE(r.scene->lights.size() == 2);
    CHECK(near(r.scene->lights[0].position, Vec3(10.0f, 0.0f, 0.0f)));
    // The mirrored copy (case-insensitive name) keeps its faces turned outwards.
    double volume = 0.0;
    for (const UVec3& t : m[1].triangles) {
        const DVec3 a(m[1].positions[t.x] - Vec3(10, 0, 0)), b(m[1].positions[t.y] - Vec3(10, 0, 0)),
            c(m[1].positions[t.z] - Vec3(10, 0, 0));
        volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    CHECK(volume == doctest::Approx(8.0));
    CHECK(r.count(Severity::Warning, "WWWInline 'loop.wrl' includes itself") == 1);
    CHECK(r.count(Severity::Warning, "is not a local file") == 1);
}
