// VRML 1.0 reader: structure, geometry, transforms, DEF/USE and errors, on small literal files
// read through importScene.
#include <doctest/doctest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "io/import.h"
#include "io/vrml/primitives.h"
#include "test_vrml1_support.h"

using namespace radbake;
namespace fs = std::filesystem;

namespace {

using namespace vrml1_test;

Read read(const std::string& body, bool strict = false) { return readAt(tempDir() / "t.wrl", body, strict); }

double meshArea(const Mesh& mesh) {
    double area = 0.0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) area += triangleArea(mesh, t);
    return area;
}

Vec3 lowCorner(const Mesh& mesh) {
    Vec3 lo(1e30f);
    for (const Vec3& p : mesh.positions) lo = glm::min(lo, p);
    return lo;
}

Vec3 highCorner(const Mesh& mesh) {
    Vec3 hi(-1e30f);
    for (const Vec3& p : mesh.positions) hi = glm::max(hi, p);
    return hi;
}

bool near(const Vec3& a, const Vec3& b, float tolerance = 1e-5f) {
    return glm::length(a - b) <= tolerance;
}

Vec3 triangleNormal(const Mesh& mesh, size_t t) {
    const UVec3 tri = mesh.triangles[t];
    return glm::normalize(glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                                     mesh.positions[tri.z] - mesh.positions[tri.x]));
}

// One unit quad in the z = 0 plane, counter-clockwise seen from +Z.
const char* kQuadCoords = "Coordinate3 { point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0 ] }\n";

}  // namespace

TEST_CASE("vrml1: IndexedFaceSet polygons, areas and convex patches") {
    const Read r = read(R"(Separator {
  Coordinate3 { point [ 0 0 0, 2 0 0, 2 1 0, 0 1 0,  0 0 1, 3 0 1, 3 0 2 ] }
  IndexedFaceSet { coordIndex [ 0, 1, 2, 3, -1, 4, 5, 6 ] }  # last face has no -1
})");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 1);
    const Mesh& mesh = r.scene->meshes[0];
    CHECK(mesh.polygon_count == 2);
    CHECK(mesh.triangles.size() == 3);
    CHECK(mesh.positions.size() == 7);
    CHECK(meshArea(mesh) == doctest::Approx(2.0 + 1.5));
    CHECK(mesh.triangle_polygon == std::vector<uint32_t>{0, 0, 1});
    CHECK(mesh.location.line == 4);
    CHECK(mesh.location.column == 3);
    CHECK_FALSE(mesh.solid);  // default ShapeHints: ordering unknown, two-sided
    CHECK(mesh.crease_angle == doctest::Approx(0.5f));
    CHECK(triangleNormal(mesh, 0).z == doctest::Approx(1.0f));
}

TEST_CASE("vrml1: Transform, Translation, Rotation, Scale and MatrixTransform place points") {
    const Read r = read(std::string(R"(Separator {
  Translation { translation 10 0 0 }
  Rotation { rotation 0 0 1 1.5707963 }
  Scale { scaleFactor 2 3 1 }
)") + kQuadCoords + R"(  IndexedFaceSet { coordIndex [ 0 1 2 3 -1 ] }
}
Separator {
  Transform { translation 0 5 0  rotation 0 1 0 3.14159265  scaleFactor 2 2 2  center 1 0 0 }
)" + kQuadCoords + R"(  IndexedFaceSet { coordIndex [ 0 1 2 3 -1 ] }
}
Separator {
  MatrixTransform { matrix 1 0 0 0  0 1 0 0  0 0 1 0  7 8 9 1 }
)" + kQuadCoords + R"(  IndexedFaceSet { coordIndex [ 0 1 2 3 -1 ] }
})");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 3);
    // p -> T(10,0,0) R_z(90) S(2,3,1) p: (1,0,0) -> (2,0,0) -> (0,2,0) -> (10,2,0).
    const Mesh& a = r.scene->meshes[0];
    CHECK(near(a.positions[1], Vec3(10.0f, 2.0f, 0.0f)));
    CHECK(near(a.positions[3], Vec3(7.0f, 0.0f, 0.0f)));  // (0,1,0) -> (0,3,0) -> (-3,0,0)
    CHECK(meshArea(a) == doctest::Approx(6.0));
    // p -> T(0,5,0) C R_y(180) S(2) C^-1 p with C = (1,0,0): (0,0,0) -> (-2,0,0) -> (2,0,0) -> (3,5,0).
    const Mesh& b = r.scene->meshes[1];
    CHECK(near(b.positions[0], Vec3(3.0f, 5.0f, 0.0f)));
    CHECK(near(b.positions[2], Vec3(1.0f, 7.0f, 0.0f)));  // (1,1,0) -> (0,2,0) -> (1,7,0)
    // Inventor matrices are row-major for row vectors: the last row translates.
    const Mesh& c = r.scene->meshes[2];
    CHECK(near(c.positions[0], Vec3(7.0f, 8.0f, 9.0f)));
    CHECK(near(c.positions[2], Vec3(8.0f, 9.0f, 9.0f)));
}

TEST_CASE("vrml1: Separator restores state, Group and TransformSeparator do not (except the transform)") {
    const Read r = read(std::string(R"(Separator {
  Separator { Translation { translation 5 0 0 } Material { diffuseColor 1 0 0 } }
)") + kQuadCoords + R"(  IndexedFaceSet { coordIndex [ 0 1 2 3 ] }
  TransformSeparator { Translation { translation 0 5 0 } Material { diffuseColor 0 0.5 0 } }
  IndexedFaceSet { coordIndex [ 0 1 2 3 ] }
  Group { Translation { translation 0 0 5 } }
  IndexedFaceSet { coordIndex [ 0 1 2 3 ] }
})");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 3);
    const auto& m = r.scene->meshes;
    CHECK(lowCorner(m[0]) == Vec3(0.0f));
    CHECK(r.scene->materials[m[0].material].reflectance == Vec3(0.8f));  // the default material
    CHECK(lowCorner(m[1]) == Vec3(0.0f));                                // transform restored...
    CHECK(r.scene->materials[m[1].material].reflectance == Vec3(0.0f, 0.5f, 0.0f));  // ...material not
    CHECK(lowCorner(m[2]) == Vec3(0.0f, 0.0f, 5.0f));                    // Group leaks its transform
}

TEST_CASE("vrml1: Switch draws whichChild, LOD its first level; hidden children still DEFine") {
    const Read r = read(R"(Separator {
  Switch { whichChild -1  DEF Hidden Cube { width 4 } }
  Switch { whichChild 1  Cube { width 1 }  Sphere { radius 2 }  Translation { translation 100 0 0 } }
  Switch { whichChild -3  Cube { width 6 }  Translation { translation 0 50 0 } }
  LOD { range [ 10 ]  Cube { width 8 }  Cube { width 9 } }
  USE Hidden
})");
    REQUIRE(r.scene);
    const auto& m = r.scene->meshes;
    REQUIRE(m.size() == 4);
    CHECK(m[0].name == "Sphere");
    CHECK(highCorner(m[0]).y == doctest::Approx(2.0f));
    CHECK(highCorner(m[1]).x == doctest::Approx(3.0f));   // width 6 cube, Switch -3 draws all
    CHECK(lowCorner(m[1]).y == doctest::Approx(-1.0f));   // ...the Translation came after it
    CHECK(highCorner(m[2]).x == doctest::Approx(4.0f));   // LOD level 0, moved up by Switch -3's translation
    CHECK(lowCorner(m[2]).y == doctest::Approx(49.0f));
    CHECK(m[3].name == "Hidden");                          // USE of a DEF in an undrawn child
    CHECK(highCorner(m[3]).x == doctest::Approx(2.0f));
    CHECK(lowCorner(m[3]).y == doctest::Approx(49.0f));
}

TEST_CASE("vrml1: DEF/USE re-applies the node in the current state; redefinition wins") {
    const Read r = read(R"(Separator {
  DEF Block Separator { Material { diffuseColor 0.1 0.2 0.3 } Cube { width 1 height 1 depth 1 } }
  Translation { translation 10 0 0 }
  USE Block
  DEF Block Cube { width 2 height 2 depth 2 }
  Translation { translation 10 0 0 }
  USE Block
  DEF Mat Material { diffuseColor 0.5 0.5 0 }
  Translation { translation 10 0 0 }
  Separator { USE Mat  Cube { } }
  USE Nothing
})");
    REQUIRE(r.scene);
    const auto& m = r.scene->meshes;
    REQUIRE(m.size() == 5);
    CHECK(near(lowCorner(m[1]), Vec3(9.5f, -0.5f, -0.5f)));
    CHECK(m[1].material == m[0].material);  // the same Material node, one scene material
    CHECK(r.scene->materials[m[1].material].reflectance == Vec3(0.1f, 0.2f, 0.3f));
    CHECK(near(lowCorner(m[3]), Vec3(19.0f, -1.0f, -1.0f)));  // the second Block
    CHECK(r.scene->materials[m[4].material].reflectance == Vec3(0.5f, 0.5f, 0.0f));
    CHECK(m[4].location.line == 11);  // the Cube
    // Shapes are named after themselves or their nearest DEF'd group, USEs included.
    CHECK(m[0].name == "Block");
    CHECK(m[1].name == "Block");
    CHECK(m[2].name == "Block");
    CHECK(m[4].name == "Cube");
    const Diagnostic* undefined = r.find(Severity::Warning, "USE of undefined name 'Nothing'");
    REQUIRE(undefined);
    CHECK(undefined->location.line == 12);
    CHECK(undefined->location.column == 7);
    CHECK(r.scene->materials.size() == 3);  // Block's, the default, Mat
}

TEST_CASE("vrml1: a USE'd node keeps the DEF's file location") {
    const Read r = read("DEF A Separator {\n  Translation { translation 1 0 0 }\n    Cube { }\n}\nUSE A\n");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 2);
    CHECK(r.scene->meshes[1].location.line == 4);
    CHECK(r.scene->meshes[1].location.column == 5);
    CHECK(r.scene->meshes[1].location.line == r.scene->meshes[0].location.line);
}

TEST_CASE("vrml1: primitives with sizes and parts") {
    const Read r = read(R"(Separator {
  Cube { width 2 height 4 depth 6 }
  Translation { translation 10 0 0 }
  Cylinder { parts (SIDES | TOP) radius 1 height 3 }
  Translation { translation 10 0 0 }
  Cone { parts BOTTOM bottomRadius 2 }
  Translation { translation 10 0 0 }
  Sphere { radius 0.5 }
})");
    REQUIRE(r.scene);
    const auto& m = r.scene->meshes;
    REQUIRE(m.size() == 4);
    CHECK(m[0].polygon_count == 6);
    CHECK(meshArea(m[0]) == doctest::Approx(2.0 * (8 + 24 + 12)));
    CHECK(m[0].convex_solid);
    CHECK(m[0].solid);
    const double n = vrml::kRoundSegments;
    CHECK(m[1].polygon_count == vrml::kRoundSegments + 1);
    CHECK_FALSE(m[1].convex_solid);
    CHECK(meshArea(m[1]) == doctest::Approx(n * 2.0 * std::sin(kPi / n) * 3.0 + 0.5 * n * std::sin(2 * kPi / n))
                                .epsilon(1e-5));
    CHECK(highCorner(m[1]).y == doctest::Approx(1.5f));
    CHECK(m[2].polygon_count == 1);
    CHECK(meshArea(m[2]) == doctest::Approx(0.5 * n * 4.0 * std::sin(2 * kPi / n)).epsilon(1e-5));
    CHECK(lowCorner(m[2]).y == doctest::Approx(-1.0f));
    CHECK(m[3].convex_solid);
    CHECK(near(highCorner(m[3]), Vec3(30.5f, 0.5f, 0.5f), 1e-4f));
}

TEST_CASE("vrml1: ShapeHints set winding, sidedness, convexity and crease angle") {
    const Read r = read(std::string(R"(Separator {
  ShapeHints { vertexOrdering CLOCKWISE shapeType SOLID creaseAngle 1.25 }
)") + kQuadCoords + R"(  IndexedFaceSet { coordIndex [ 0 1 2 3 ] }
  ShapeHints { vertexOrdering COUNTERCLOCKWISE shapeType UNKNOWN_SHAPE_TYPE faceType UNKNOWN_FACE_TYPE }
  Coordinate3 { point [ 0 0 0, 2 0 0, 2 1 0, 1 1 0, 1 2 0, 0 2 0 ] }
  IndexedFaceSet { coordIndex [ 0 1 2 3 4 5 ] }
  ShapeHints { faceType CONVEX }
  IndexedFaceSet { coordIndex [ 2 3 4 5 0 1 ] }
})");
    REQUIRE(r.scene);
    const auto& m = r.scene->meshes;
    REQUIRE(m.size() == 3);
    CHECK(m[0].solid);
    CHECK(m[0].crease_angle == doctest::Approx(1.25f));
    CHECK(triangleNormal(m[0], 0).z == doctest::Approx(-1.0f));  // clockwise: front faces -Z
    CHECK_FALSE(m[1].solid);
    // The L-shaped hexagon (area 3) is ear-clipped, not fanned.
    CHECK(m[1].polygon_count == 1);
    CHECK(m[1].triangles.size() == 4);
    CHECK(meshArea(m[1]) == doctest::Approx(3.0));
    for (size_t t = 0; t < m[1].triangles.size(); ++t) CHECK(triangleNormal(m[1], t).z == doctest::Approx(1.0f));
    // Declared CONVEX but is not: still ear-clipped (a fan from (2,1) would fold over and
    // cover 4 square units).
    CHECK(meshArea(m[2]) == doctest::Approx(3.0));
    for (size_t t = 0; t < m[2].triangles.size(); ++t) CHECK(triangleNormal(m[2], t).z == doctest::Approx(1.0f));
}

TEST_CASE("vrml1: faces with bad indices are dropped and counted in one warning") {
    const Read r = read(std::string(kQuadCoords) +
                        "IndexedFaceSet { coordIndex [ 0 1 2 -1  0 1 9 -1  0 1 -1  2 3 -5 0 -1  0 2 3 -1 ] }\n");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 1);
    CHECK(r.scene->meshes[0].polygon_count == 2);
    CHECK(r.count(Severity::Warning, "3 face(s) with fewer than 3 corners or coordinate indices out of range") ==
          1);
}

TEST_CASE("vrml1: ignored and unknown nodes, unknown fields") {
    const Read r = read(R"(Separator {
  IndexedLineSet { coordIndex [ 0 1 ] }
  IndexedLineSet { coordIndex [ 1 2 ] }
  PointSet { numPoints 2 }
  AsciiText { string "hello { world" }
  Info { string "made by hand" }
  Texture2 { filename "wood.gif" wrapS REPEAT }
  MyExtension { fields [ SFFloat size, MFVec3f pts ] size 2 pts [ 1 2 3, 4 5 6 ] }
  Cube { colour 1 2 3  width 2 }
  Cube { colour 1  width 2 }
  Cube { colour 1  width 2 }
})");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 3);
    CHECK(r.count(Severity::Warning, "IndexedLineSet ignored") == 1);
    CHECK(r.count(Severity::Warning, "PointSet ignored") == 1);
    CHECK(r.count(Severity::Warning, "AsciiText ignored") == 1);
    const Diagnostic* unknown = r.find(Severity::Warning, "unknown node type 'MyExtension'");
    REQUIRE(unknown);
    CHECK(unknown->location.line == 9);
    CHECK(unknown->location.column == 3);
    const Diagnostic* field = r.find(Severity::Warning, "unknown field 'colour' in Cube");
    REQUIRE(field);
    CHECK(field->location.line == 10);
    CHECK(r.count(Severity::Warning, "unknown field 'colour'") == 1);  // repeats are counted, not repeated
    CHECK(r.count(Severity::Note, "unknown field 'colour' in Cube: 2 more occurrence(s)") == 1);
    CHECK(meshArea(r.scene->meshes[0]) == doctest::Approx(24.0));  // width read after the bad field
    const TextureRef& texture = r.scene->materials[r.scene->meshes[0].material].base_color_texture;
    CHECK(texture.path.ends_with("wood.gif"));  // resolved against the file
    CHECK_FALSE(texture.rgb_replaces);           // VRML 1.0: texture times the diffuse colour
}

TEST_CASE("vrml1: strict mode turns unknown nodes and fields into errors") {
    const Read unknown_node = read("Separator {\n  Fancy { }\n}\n", true);
    CHECK_FALSE(unknown_node.scene);
    const Diagnostic* e = unknown_node.find(Severity::Error, "unknown node type 'Fancy'");
    REQUIRE(e);
    CHECK(e->location.line == 3);
    CHECK(e->location.column == 3);
    const Read unknown_field = read("Cube { colour 1 }\n", true);
    CHECK_FALSE(unknown_field.scene);
    CHECK(unknown_field.count(Severity::Error, "unknown field 'colour' in Cube") == 1);
}

TEST_CASE("vrml1: syntax errors are located") {
    SUBCASE("missing brace") {
        const Read r = read("Separator {\n  Cube { width 2 }\n");
        CHECK_FALSE(r.scene);
        const Diagnostic* e = r.find(Severity::Error, "Separator has no closing '}'");
        REQUIRE(e);
        CHECK(e->location.line == 2);
        CHECK(e->location.column == 1);
    }
    SUBCASE("bad number") {
        const Read r = read("Separator {\n  Cube { width 2x }\n}\n");
        CHECK_FALSE(r.scene);
        const Diagnostic* e = r.find(Severity::Error, "field 'width': expected a number, found '2x'");
        REQUIRE(e);
        CHECK(e->location.line == 3);
        CHECK(e->location.column == 16);
    }
    SUBCASE("node without a body") {
        const Read r = read("Separator {\n  Cube\n}\n");
        CHECK_FALSE(r.scene);
        const Diagnostic* e = r.find(Severity::Error, "'Cube' has no value");
        REQUIRE(e);
        CHECK(e->location.line == 3);
        CHECK(e->location.column == 3);
    }
    SUBCASE("unterminated list") {
        const Read r = read("Coordinate3 { point [ 0 0 0, 1 1 1 }\n");
        CHECK_FALSE(r.scene);
        const Diagnostic* e = r.find(Severity::Error, "field 'point': missing ']'");
        REQUIRE(e);
        CHECK(e->location.line == 2);
    }
}

TEST_CASE("vrml1: hostile nesting and DEF/USE chains end with an error, not a crash") {
    std::string deep;
    for (int i = 0; i < 100000; ++i) deep += "Separator { ";
    const Read nested = read(deep);
    CHECK_FALSE(nested.scene);
    CHECK(nested.count(Severity::Error, "nested deeper than") == 1);

    // Each level USEs the previous one twice: 2^40 cubes if expanded.
    std::string chain = "DEF L0 Cube { }\n";
    for (int i = 1; i <= 40; ++i)
        chain += "DEF L" + std::to_string(i) + " Group { USE L" + std::to_string(i - 1) + " USE L" +
                 std::to_string(i - 1) + " }\n";
    const Read expanded = read(chain);
    CHECK_FALSE(expanded.scene);
    CHECK(expanded.count(Severity::Error, "USE expansion too large") == 1);
}

TEST_CASE("vrml1: extension nodes describe their fields and may name the node they extend (isA)") {
    const Read r = read(R"(Group {
  Glass {
    fields [ MFString isA, MFFloat indexOfRefraction, MFColor diffuseColor ]
    isA [ "Material" ]
    indexOfRefraction .34
    diffuseColor 0.6 0 0
  }
  Cube {
    fields [ SFFloat width, SFFloat height, SFFloat depth, SFBool shiny ]
    width 10 height 4 depth 3 shiny TRUE
  }
  Blob { fields [ SFFloat size ] isA [ "NoSuchNode" ] size 2 }
})");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 1);
    CHECK(meshArea(r.scene->meshes[0]) == doctest::Approx(2.0 * (40 + 12 + 30)));
    const Material& material = r.scene->materials[r.scene->meshes[0].material];
    CHECK(material.reflectance == Vec3(0.6f, 0.0f, 0.0f));
    CHECK(r.diagnostics.warningCount() == 1);  // only Blob: declared fields pass quietly
    const Diagnostic* blob = r.find(Severity::Warning, "unknown node type 'Blob' skipped");
    REQUIRE(blob);
    CHECK(blob->location.line == 13);
}

TEST_CASE("vrml1: a missing WWWInline file is skipped with a located warning; strict makes it an error") {
    const fs::path dir = tempDir();
    const std::string body =
        "Separator {\n"
        "  WWWInline { name \"nowhere.wrl\" }\n"
        "  Coordinate3 { point [ 0 0 0, 1 0 0, 1 1 0 ] }\n"
        "  IndexedFaceSet { coordIndex [ 0, 1, 2, -1 ] }\n"
        "}\n";
    const Read lenient = readAt(dir / "main.wrl", body);
    REQUIRE(lenient.scene);
    CHECK(lenient.scene->meshes.size() == 1);
    const Diagnostic* warning = lenient.find(Severity::Warning, "not found");
    REQUIRE(warning != nullptr);
    CHECK(warning->location.line == 3);
    const Read strict = readAt(dir / "strict.wrl", body, true);
    CHECK_FALSE(strict.scene);
    CHECK(strict.count(Severity::Error, "not found") == 1);
}

TEST_CASE("vrml1: WWWInline places the inlined file by the current transform; a cycle is cut") {
    const fs::path dir = tempDir();
    writeFile(dir / "child.wrl",
              "#VRML V1.0 ascii\nSeparator {\n  Coordinate3 { point [ 0 0 0, 1 0 0, 1 1 0 ] }\n"
              "  IndexedFaceSet { coordIndex [ 0, 1, 2, -1 ] }\n  WWWInline { name \"main.wrl\" }\n}\n");
    const Read r = readAt(dir / "main.wrl", "Separator { Translation { translation 0 0 5 } WWWInline { name \"child.wrl\" } }\n");
    REQUIRE(r.scene);
    REQUIRE(r.scene->meshes.size() == 1);  // main -> child -> main is cut at the second main
    CHECK(r.scene->meshes[0].positions[0].z == doctest::Approx(5.0));
    CHECK(r.count(Severity::Warning, "already being read") == 1);
}
