// One test per hazard of the VRML97 reader: files from the wild, broken and hostile input.
#include <doctest/doctest.h>

#include <cstdint>

#include "io/import.h"
#include "io/vrml/vrml97_parser.h"
#include "test_vrml97_support.h"

using namespace radbake;
using namespace vrml_test;

namespace {

const char* kQuad = "Shape { geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0] } coordIndex [0 1 2 3] } }\n";

uint32_t crc32(const std::string& bytes) {
    uint32_t crc = 0xffffffffu;
    for (unsigned char b : bytes) {
        crc ^= b;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

// A gzip stream with one stored (uncompressed) deflate block: enough to test detection
// without a compressor in the tests.
std::string gzipStored(const std::string& data) {
    std::string out("\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\xff", 10);
    out.push_back('\x01');  // final stored block
    const uint16_t len = static_cast<uint16_t>(data.size()), nlen = static_cast<uint16_t>(~len);
    for (uint16_t v : {len, nlen}) {
        out.push_back(char(v & 0xff));
        out.push_back(char(v >> 8));
    }
    out += data;
    for (uint32_t v : {crc32(data), uint32_t(data.size())})
        for (int k = 0; k < 4; ++k) out.push_back(char((v >> (8 * k)) & 0xff));
    return out;
}

}  // namespace

TEST_CASE("hazard: .wrl.gz and gzip bytes inside a .wrl are read transparently") {
    const auto dir = tempDir("gzip");
    const std::string text = std::string("#VRML V2.0 utf8\n") + kQuad;
    Read a = readPath(writeFile(dir / "a.wrl.gz", gzipStored(text)));
    CHECK(a.ok);
    CHECK(a.area() == doctest::Approx(1.0));
    Read b = readPath(writeFile(dir / "b.wrl", gzipStored(text)));  // gzip despite the name
    CHECK(b.ok);
    CHECK(b.area() == doctest::Approx(1.0));
    std::string truncated = gzipStored(text);
    truncated.resize(truncated.size() - 30);
    Read c = readPath(writeFile(dir / "c.wrl.gz", truncated));
    CHECK_FALSE(c.ok);
    CHECK(c.has("c.wrl.gz: error: '"));
    CHECK(c.has("gzip data is truncated"));
}

TEST_CASE("hazard: Windows line endings and non-UTF-8 bytes in comments") {
    Read r = readVrml97("crlf", "# caf\xe9 \xff\xfe comment\r\nShape {\r\n geometry Box { size 1 1 1 } # \x80\x81\r\n}\r\nShape { geometry Bogus { } }\r\n");
    CHECK(r.ok);
    CHECK(r.area() == doctest::Approx(6.0));
    CHECK(r.has("scene.wrl:6:18: warning: unknown node type 'Bogus' skipped"));
}

TEST_CASE("hazard: unknown nodes and fields are located warnings, errors with strict") {
    const std::string body = R"(
Shape { geometry Box { size 1 1 1 frobnicate [1 2 { 3 }] } }
Shape { geometry NurbsSurface { controlPoint [0 0 0] inner Group { children [] } } }
Group { children [ Shape { geometry Box { size 2 2 2 } } ] bogus "x" }
)";
    Read lax = readVrml97("unknown", body);
    CHECK(lax.ok);
    CHECK(lax.scene.meshes.size() == 2);
    CHECK(lax.has("scene.wrl:3:35: warning: unknown field 'frobnicate' in Box skipped"));
    CHECK(lax.has("scene.wrl:4:18: warning: unknown node type 'NurbsSurface' skipped"));
    CHECK(lax.has("scene.wrl:5:60: warning: unknown field 'bogus' in Group skipped"));
    Read strict = readVrml97("unknown_strict", body, true);
    CHECK_FALSE(strict.ok);
    CHECK(strict.diagnostics.errorCount() == 3);
    CHECK(strict.has("scene.wrl:4:18: error: unknown node type 'NurbsSurface' skipped"));
}

TEST_CASE("hazard: syntax errors are located errors and the reader returns false") {
    struct Case {
        const char* body;
        const char* message;
    } cases[] = {
        {"Shape { geometry Box { size 1 x 1 } }", "scene.wrl:2:31: error: expected a number for field 'size', found 'x'"},
        {"Shape { geometry Box { size 1 1 1 }", "scene.wrl:2:36: error: unexpected end of file inside Shape (opened at line 2, column 1)"},
        {"Group { children [ Shape { } ", "scene.wrl:2:30: error: unexpected end of file in field 'children'"},
        {"Transform { translation 1 2 3 ] }", "scene.wrl:2:31: error: expected a field name or '}' in Transform, found ']'"},
        {"Shape { appearance Appearance { material Material { diffuseColor 1 0 \"oops } } }", "scene.wrl:2:70: error: expected a number for field 'diffuseColor', found an unterminated string"},
        {"Switch { whichChoice 2147483648 }", "scene.wrl:2:22: error: expected an integer for field 'whichChoice'"},
        {"Box", "scene.wrl:2:4: error: expected '{' after node type 'Box', found end of file"},
        {"PROTO P [ field SFFloat x 1 ] { Box { size IS y } } P { }", "scene.wrl:2:47: error: IS refers to 'y', which PROTO P does not declare"},
        {"Box { size IS y }", "scene.wrl:2:12: error: IS outside a PROTO body"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.body);
        // an IS to an undeclared field is an error only with strict (a warning otherwise)
        const bool strict = std::string(c.body).starts_with("PROTO P");
        Read r = readVrml97("syntax", c.body, strict);
        CHECK_FALSE(r.ok);
        CHECK(r.diagnostics.errorCount() == 1);
        CHECK(r.has(c.message));
    }
}

TEST_CASE("hazard: a file that is not VRML reports where and why") {
    const auto dir = tempDir("header");
    Read r = readPath(writeFile(dir / "x.wrl", "#VRML V3.0 utf8\nShape {}\n"));
    CHECK_FALSE(r.ok);
    CHECK(r.has("x.wrl:1:1: error: not a VRML file: the first line must start with \"#VRML V2.0\" or \"#VRML V1.0\" (found \"#VRML V3.0 utf8\")"));
}

TEST_CASE("hazard: deep nesting is a located error, not a stack overflow") {
    std::string body;
    for (int i = 0; i < 5000; ++i) body += "Group { children ";
    Read r = readVrml97("deep", body);
    CHECK_FALSE(r.ok);
    CHECK(r.has("scene.wrl:2:3401: error: nodes nested deeper than 200 levels"));
}

TEST_CASE("hazard: DEF/USE fan-out and PROTO expansion bombs stop at their limits") {
    vrml::Vrml97Limits saved = vrml::vrml97Limits();
    vrml::vrml97Limits().max_node_visits = 100'000;
    vrml::vrml97Limits().max_expanded_nodes = 10'000;
    std::string fan = "DEF L0 Shape { geometry Box { } }\n";
    for (int i = 1; i <= 40; ++i)
        fan += "DEF L" + std::to_string(i) + " Group { children [ USE L" + std::to_string(i - 1) + " USE L" +
               std::to_string(i - 1) + " ] }\n";
    Read a = readVrml97("fanout", fan);
    CHECK_FALSE(a.ok);
    CHECK(a.has("error: the scene graph expands to more than 100000 node instances"));

    std::string protos = "PROTO P0 [ field SFVec3f s 1 1 1 ] { Shape { geometry Box { size IS s } } }\n";
    for (int i = 1; i <= 30; ++i)
        protos += "PROTO P" + std::to_string(i) + " [ field SFVec3f s 1 1 1 ] { Group { children [ P" + std::to_string(i - 1) +
                  " { s IS s } P" + std::to_string(i - 1) + " { s IS s } ] } }\n";
    protos += "P30 { s 2 2 2 }\n";
    Read b = readVrml97("protobomb", protos);
    vrml::vrml97Limits() = saved;
    CHECK_FALSE(b.ok);
    CHECK(b.has("error: PROTO expansion makes more than 10000 nodes"));
}

TEST_CASE("hazard: USE of an undefined name is a located warning") {
    Read r = readVrml97("undefined_use", std::string("Group { children [ USE Nowhere ") + kQuad + "] }");
    CHECK(r.ok);
    CHECK(r.scene.meshes.size() == 1);
    CHECK(r.has("scene.wrl:2:24: warning: USE of undefined node name 'Nowhere' ignored"));
}

TEST_CASE("hazard: resolveUrl keeps local files and refuses remote ones") {
    const auto dir = tempDir("urls");
    writeFile(dir / "Models" / "Chair.wrl", "#VRML V2.0 utf8\n");
    const std::string base = (dir / "scene.wrl").string();
    CHECK_FALSE(vrml::resolveUrl(base, "http://example.com/a.wrl").has_value());
    CHECK_FALSE(vrml::resolveUrl(base, "urn:web3d:media:a").has_value());
    CHECK(vrml::resolveUrl(base, "models/chair.WRL") == (dir / "Models" / "Chair.wrl").string());
    CHECK(vrml::resolveUrl(base, "Models\\Chair.wrl#Top") == (dir / "Models" / "Chair.wrl").string());
    CHECK(vrml::resolveUrl(base, "Models/My%20Chair.wrl") == (dir / "Models" / "My Chair.wrl").string());
    CHECK(vrml::resolveUrl(base, "file://" + (dir / "Models" / "Chair.wrl").string()) == (dir / "Models" / "Chair.wrl").string());
}

TEST_CASE("hazard: importScene reads VRML97 and applies the unit scale") {
    const auto dir = tempDir("import");
    const std::string path = writeFile(dir / "room.wrl", std::string("#VRML V2.0 utf8\n") + kQuad);
    Diagnostics diagnostics;
    ImportOptions options;
    options.unit_scale = 0.01f;
    const auto scene = importScene(path, options, diagnostics);
    REQUIRE(scene.has_value());
    CHECK(scene->name == "room");
    const SceneSummary summary = summarize(*scene);
    CHECK(summary.area == doctest::Approx(1e-4));
    CHECK(summary.polygons == 1);
}

// Regression (found by fuzz_vrml, heap-use-after-free): a PROTO redefined inside the body of an
// instance of the same name freed the definition the instance was being parsed with, and the
// instance was then bound to the new definition.
TEST_CASE("hazard: a PROTO redefined inside its own instance's body keeps the instance's definition") {
    Read r = readVrml97("proto_redefined_in_body.wrl",
                        "PROTO X [ field SFVec3f size 1 1 1 ] { Shape { geometry Box { size IS size } } }\n"
                        "X { size 2 2 2\n"
                        "    PROTO X [ field SFFloat radius 1 ] { Shape { geometry Sphere { radius IS radius } } }\n"
                        "    size 2 2 2 }\n"
                        "X { radius 3 }\n");
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 2);
    CHECK(r.scene.meshes[0].polygon_count == 6);  // the first instance is still the box
    double box_area = 0.0;
    for (size_t t = 0; t < r.scene.meshes[0].triangles.size(); ++t) box_area += triangleArea(r.scene.meshes[0], t);
    CHECK(box_area == doctest::Approx(24.0));
    CHECK(r.scene.meshes[1].polygon_count > 6);   // the second uses the redefinition: the sphere
    CHECK_FALSE(r.has("unknown field"));
}
