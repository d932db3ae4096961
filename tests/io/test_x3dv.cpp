// X3D classic encoding (.x3dv): VRML97 syntax under a "#X3D V3.x utf8" header, with the X3D
// statements (PROFILE, COMPONENT, META, UNIT, IMPORT, EXPORT) skipped, one warning per kind.
#include <doctest/doctest.h>

#include <string>

#include "io/import.h"
#include "test_vrml97_support.h"

using namespace vrml_test;

namespace {

// A unit square in z = 0 facing +z.
const char* kSquare =
    "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
    "  geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0] } coordIndex [0 1 2 3 -1] } }\n";

Read readX3dv(const std::string& name, const std::string& text, bool strict = false) {
    return readPath(writeFile(tempDir(name) / "scene.x3dv", text), strict);
}

int warningsWith(const Read& r, const std::string& part) {
    int count = 0;
    for (const auto& d : r.diagnostics.all())
        if (d.severity == radbake::Severity::Warning && d.message.find(part) != std::string::npos) ++count;
    return count;
}

}  // namespace

TEST_CASE("x3dv: the X3D header is recognised as a VRML-family file") {
    CHECK(radbake::looksLikeVrml("#X3D V3.2 utf8\n"));
    CHECK(radbake::looksLikeVrml("\xEF\xBB\xBF#X3D V3.0 utf8"));
    CHECK_FALSE(radbake::looksLikeVrml("<?xml version="));  // XML-encoded X3D is not ours
    Read r = readX3dv("plain", std::string("#X3D V3.3 utf8\n") + kSquare);
    CHECK(r.ok);
    CHECK(r.diagnostics.all().empty());
    CHECK(r.triangles() == 2);
    CHECK(r.area() == doctest::Approx(1.0));
}

TEST_CASE("x3dv: X3D statements are skipped with one located warning per kind") {
    const std::string text =
        "#X3D V3.2 utf8\n"
        "PROFILE Interchange\n"
        "COMPONENT Rendering:2\n"
        "COMPONENT Shape : 1\n"
        "COMPONENT Lighting: 2\n"
        "META \"title\" \"two squares\"\n"
        "META \"author\" \"someone\"\n"
        "UNIT length centimetre 0.01\n"
        "IMPORT house.Door AS FrontDoor\n"
        "IMPORT house.Window\n" +
        std::string("DEF Floor Transform { children [") + kSquare +
        "] }\n"
        "EXPORT Floor AS TheFloor\n"
        "DEF Wall Transform { translation 0 0 2 children [" +
        kSquare +
        "] }\n"
        "EXPORT Wall\n";
    Read r = readX3dv("statements", text);
    INFO(r.messages());
    REQUIRE(r.ok);
    CHECK(r.triangles() == 4);
    CHECK(r.area() == doctest::Approx(2.0));
    CHECK(r.diagnostics.warningCount() == 6);
    CHECK(r.has("scene.x3dv:2:1: warning: X3D PROFILE statement(s) skipped (X3D classic files are read as VRML97)"));
    CHECK(r.has("scene.x3dv:3:1: warning: X3D COMPONENT statement(s) skipped"));
    CHECK(r.has("scene.x3dv:6:1: warning: X3D META statement(s) skipped"));
    CHECK(r.has("scene.x3dv:8:1: warning: X3D UNIT statement(s) skipped (X3D classic files are read as VRML97); "
                "lengths are read unscaled: give --unit-scale for a length unit"));
    CHECK(r.has("scene.x3dv:9:1: warning: X3D IMPORT statement(s) skipped"));
    CHECK(r.has("scene.x3dv:14:1: warning: X3D EXPORT statement(s) skipped"));
    for (const char* kind : {"PROFILE", "COMPONENT", "META", "UNIT", "IMPORT", "EXPORT"})
        CHECK(warningsWith(r, std::string("X3D ") + kind + " ") == 1);
}

TEST_CASE("x3dv: unknown X3D nodes follow the unknown-node rule") {
    const std::string text = std::string("#X3D V3.2 utf8\nPROFILE Immersive\n") +
                             "MetadataString { name \"a\" value [\"b\"] }\n"
                             "Environment { shadows TRUE }\n" +
                             kSquare;
    Read lenient = readX3dv("unknown", text);
    CHECK(lenient.ok);
    CHECK(lenient.triangles() == 2);
    CHECK(lenient.has("scene.x3dv:3:1: warning: unknown node type 'MetadataString' skipped"));
    CHECK(lenient.has("scene.x3dv:4:1: warning: unknown node type 'Environment' skipped"));
    Read strict = readX3dv("unknown_strict", text, true);
    CHECK_FALSE(strict.ok);
    CHECK(strict.diagnostics.errorCount() == 2);
    CHECK(strict.has("scene.x3dv:3:1: error: unknown node type 'MetadataString' skipped"));
    CHECK(strict.has("scene.x3dv:2:1: warning: X3D PROFILE statement(s) skipped"));  // valid X3D: never an error
}

TEST_CASE("x3dv: a statement keyword followed by '{' is still a node (here a PROTO named EXPORT)") {
    const std::string text = std::string("#X3D V3.0 utf8\nPROTO EXPORT [] { ") + kSquare + "}\nEXPORT { }\nEXPORT {}\n";
    Read r = readX3dv("proto_named_export", text);
    INFO(r.messages());
    CHECK(r.ok);
    CHECK(r.triangles() == 4);
    CHECK(r.diagnostics.warningCount() == 0);
}

TEST_CASE("x3dv: a malformed X3D statement is a located error") {
    struct Case {
        const char* body;
        const char* message;
    };
    const Case cases[] = {
        {"META \"title\"\nShape {}\n", "scene.x3dv:3:1: error: expected a value string after the META key, found 'Shape'"},
        {"COMPONENT Rendering:\n[", "scene.x3dv:3:1: error: expected a component level after ':', found '['"},
        {"UNIT length metre\n", "scene.x3dv:3:1: error: expected a conversion factor after the UNIT name, found end of file"},
        {"EXPORT Floor AS\n", "scene.x3dv:3:1: error: expected a name after AS, found end of file"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.body);
        Read r = readX3dv("malformed", std::string("#X3D V3.2 utf8\n") + c.body);
        CHECK_FALSE(r.ok);
        CHECK(r.diagnostics.errorCount() == 1);
        CHECK(r.has(c.message));
    }
}

TEST_CASE("x3dv: importScene reads an .x3dv that inlines a VRML97 file, with its lights") {
    const auto dir = tempDir("import");
    writeFile(dir / "room.wrl", std::string("#VRML V2.0 utf8\n") + kSquare);
    const std::string path = writeFile(dir / "lit_final.x3dv",
                                       "#X3D V3.2 utf8\nPROFILE Interchange\n"
                                       "NavigationInfo { headlight FALSE }\n"
                                       "PointLight { location 0.5 0.5 2 intensity 0.7 }\n"
                                       "Inline { url \"room.wrl\" }\n");
    radbake::Diagnostics diagnostics;
    const auto scene = radbake::importScene(path, {}, diagnostics);
    REQUIRE(scene);
    CHECK(scene->name == "lit_final");
    CHECK(radbake::summarize(*scene).triangles == 2);
    REQUIRE(scene->lights.size() == 1);
    CHECK(scene->lights[0].intensity == doctest::Approx(0.7f));
    CHECK(scene->lights[0].position.z == doctest::Approx(2.0f));
    CHECK(diagnostics.warningCount() == 1);  // PROFILE
}
