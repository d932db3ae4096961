#include <doctest/doctest.h>

#include <cmath>

#include "io/vrml/vrml97_parser.h"
#include "test_vrml97_support.h"

using namespace radbake;
using namespace vrml_test;

namespace {
const char* kQuad = "Shape { geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0] } coordIndex [0 1 2 3] } }\n";

bool near(const Vec3& a, const Vec3& b, float tolerance = 1e-5f) { return glm::length(a - b) <= tolerance; }
}  // namespace

TEST_CASE("vrml97: an IndexedFaceSet quad becomes one polygon of two triangles") {
    Read r = readVrml97("quad", kQuad);
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 1);
    const Mesh& mesh = r.scene.meshes[0];
    CHECK(mesh.polygon_count == 1);
    CHECK(mesh.triangles.size() == 2);
    CHECK(mesh.triangle_polygon == std::vector<uint32_t>{0, 0});
    CHECK(r.area() == doctest::Approx(1.0));
    CHECK(mesh.solid);
    REQUIRE(r.scene.materials.size() == 1);
    CHECK(r.scene.materials[0].name == "default");
    CHECK(r.scene.materials[0].reflectance == Vec3(0.8f));
    CHECK_FALSE(r.scene.materials[0].isEmitter());
    CHECK(mesh.location.line == 2);
    CHECK(mesh.location.column == 18);
}

TEST_CASE("vrml97: every field type, comments anywhere, commas, single MF values, NULL and empty fields") {
    Read r = readVrml97("fields", R"(
PROTO All [ field SFBool b TRUE field SFInt32 i 0x1F field SFFloat f -1.5e2 field SFTime t 0
  field SFVec2f v2 1 2 field SFVec3f v3 1,2,3 field SFRotation r 0 1 0 3.14 field SFColor c 1 0 0
  field SFString s "a \"quoted\"
two-line string" field SFImage img 2 1 3 0xFF0000 0x00FF00 field SFNode n NULL
  field MFInt32 mi [1, 2, -3] field MFFloat mf 7 field MFTime mt [] field MFVec2f m2 [1 2, 3 4]
  field MFVec3f m3 1 2 3 field MFRotation mr [0 0 1 0] field MFColor mc [] field MFString ms "one"
  field MFNode mn [ ] eventIn SFBool set_b eventOut SFBool b_changed ]
{ Group {} }
Group { # a comment after a brace
  children [ # and inside a list
    All { i 12 mi 5 ms [ "x" "y" ] n Group { } }
    NULL
    Shape { geometry IndexedFaceSet { coord Coordinate { point 0 0 0 } coordIndex [] } }
  ] # end
}
Transform { children Shape { geometry Box { size 1 2 3 } } }  # single node where MFNode expected
)");
    CHECK(r.ok);
    CHECK(r.diagnostics.errorCount() == 0);
    CHECK(r.diagnostics.warningCount() == 0);
    REQUIRE(r.scene.meshes.size() == 1);  // the empty IndexedFaceSet adds nothing
    CHECK(r.area() == doctest::Approx(2 * (1 * 2 + 2 * 3 + 1 * 3)));
}

TEST_CASE("vrml97: DEF/USE shares nodes and a USE takes the most recent DEF") {
    Read r = readVrml97("defuse", R"(
DEF A Shape { geometry Box { size 1 1 1 } }
Transform { translation 10 0 0 children USE A }
DEF A Shape { geometry Box { size 2 2 2 } }
Transform { translation 20 0 0 children USE A }
ROUTE A.geometry TO A.set_geometry
ROUTE A . geometry TO A . set_geometry
)");
    CHECK(r.ok);
    REQUIRE(r.scene.meshes.size() == 4);
    CHECK(r.area() == doctest::Approx(6 + 6 + 24 + 24));
    // the second box is the first shape moved by 10, the fourth is the second moved by 20
    CHECK(r.scene.meshes[1].positions[0].x == doctest::Approx(r.scene.meshes[0].positions[0].x + 10));
    CHECK(r.scene.meshes[3].positions[0].x == doctest::Approx(r.scene.meshes[2].positions[0].x + 20));
    CHECK(std::abs(r.scene.meshes[2].positions[0].x) == doctest::Approx(1.0));
}

TEST_CASE("vrml97: Transform applies T C R SR S -SR -C in that order") {
    Read r = readVrml97("transform", R"(
Transform { translation 1 2 3 center 1 0 0 rotation 0 0 1 1.5707963 scale 2 3 1 scaleOrientation 0 0 1 0.7853982
  children Shape { geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 2 0 0, 2 1 0] } coordIndex [0 1 2 -1] } } }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 1);
    // Brute force: apply the chain by hand to (2, 0, 0).
    auto apply = [](Vec3 p) {
        DVec3 q(p);
        q -= DVec3(1, 0, 0);                                            // -C
        auto rotz = [](DVec3 v, double a) { return DVec3(v.x * std::cos(a) - v.y * std::sin(a), v.x * std::sin(a) + v.y * std::cos(a), v.z); };
        q = rotz(q, -kPi / 4);                                          // -SR
        q *= DVec3(2, 3, 1);                                            // S
        q = rotz(q, kPi / 4);                                           // SR
        q = rotz(q, kPi / 2);                                           // R
        q += DVec3(1, 0, 0) + DVec3(1, 2, 3);                           // C, T
        return Vec3(q);
    };
    const Mesh& mesh = r.scene.meshes[0];
    REQUIRE(mesh.positions.size() == 3);
    CHECK(near(mesh.positions[0], apply(Vec3(0, 0, 0))));
    CHECK(near(mesh.positions[1], apply(Vec3(2, 0, 0))));
    CHECK(near(mesh.positions[2], apply(Vec3(2, 1, 0))));
}

TEST_CASE("vrml97: a mirroring Transform keeps triangles counter-clockwise from the front") {
    Read r = readVrml97("mirror", std::string("Transform { scale -1 1 1 children ") + kQuad + "}");
    REQUIRE(r.ok);
    const Mesh& mesh = r.scene.meshes.at(0);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const UVec3& tri = mesh.triangles[t];
        const Vec3 n = glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x], mesh.positions[tri.z] - mesh.positions[tri.x]);
        CHECK(n.z > 0.0f);  // the quad faced +Z and still does after mirroring X
    }
}

TEST_CASE("vrml97: grouping nodes: Group, Switch, LOD, Collision, Billboard, Anchor") {
    Read r = readVrml97("groups", R"(
Group { children Shape { geometry Box { size 1 1 1 } } }
Switch { whichChoice 1 choice [ Shape { geometry Box { size 5 5 5 } } Shape { geometry Box { size 2 2 2 } } ] }
Switch { choice Shape { geometry Box { size 5 5 5 } } }
LOD { range [10] level [ Shape { geometry Box { size 1 1 1 } } Shape { geometry Box { size 9 9 9 } } ] }
Collision { collide FALSE children Shape { geometry Box { size 1 1 1 } } }
Billboard { axisOfRotation 0 1 0 children Shape { geometry Box { size 1 1 1 } } }
Anchor { url "x.wrl" description "d" children Shape { geometry Box { size 1 1 1 } } }
)");
    CHECK(r.ok);
    CHECK(r.scene.meshes.size() == 6);
    CHECK(r.area() == doctest::Approx(6 * 5 + 24));
}

TEST_CASE("vrml97: PROTO instances expand with IS bindings and defaults") {
    Read r = readVrml97("proto", R"(
PROTO Tile [ field SFColor tint 1 0 0 field SFVec3f where 0 0 0 exposedField SFFloat side 1 eventIn SFBool set_on ] {
  Transform { translation IS where set_translation IS set_on
    children Shape { appearance Appearance { material Material { diffuseColor IS tint } }
                     geometry Box { size 1 1 1 } } }
}
PROTO Pair [ field SFColor c 0 0 1 ] { Group { children [ Tile { tint IS c } Tile { tint IS c where 5 0 0 } ] } }
Tile { }
Tile { tint 0 1 0 where 0 3 0 }
Pair { }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 4);
    auto color = [&](size_t m) { return r.scene.materials.at(r.scene.meshes[m].material).reflectance; };
    CHECK(color(0) == Vec3(1, 0, 0));
    CHECK(color(1) == Vec3(0, 1, 0));
    CHECK(color(2) == Vec3(0, 0, 1));
    CHECK(color(3) == Vec3(0, 0, 1));
    auto centre = [&](size_t m) {
        Vec3 sum(0.0f);
        for (const Vec3& p : r.scene.meshes[m].positions) sum += p;
        return sum / float(r.scene.meshes[m].positions.size());
    };
    CHECK(near(centre(0), Vec3(0, 0, 0)));
    CHECK(near(centre(1), Vec3(0, 3, 0)));
    CHECK(near(centre(3), Vec3(5, 0, 0)));
}

TEST_CASE("vrml97: EXTERNPROTO from a local file is used; a remote one is skipped with a warning") {
    const auto dir = tempDir("externproto");
    writeFile(dir / "lib" / "protos.wrl", "#VRML V2.0 utf8\nPROTO Slab [ field SFVec3f size 4 1 4 ] { Shape { geometry Box { size IS size } } }\n");
    const std::string path = writeFile(dir / "scene.wrl", R"(#VRML V2.0 utf8
EXTERNPROTO Slab [ field SFVec3f size ] "lib/protos.wrl#Slab"
EXTERNPROTO Far [ field SFFloat x ] [ "http://example.com/far.wrl#Far" "urn:web3d:far" ]
Slab { }
Slab { size 1 1 1 }
Far { x 2 }
)");
    Read r = readPath(path);
    CHECK(r.ok);
    CHECK(r.scene.meshes.size() == 2);
    CHECK(r.area() == doctest::Approx(2 * (16 + 4 + 4) + 6));
    CHECK(r.has("scene.wrl:3:13: warning: EXTERNPROTO Far is not a local file"));
}

TEST_CASE("vrml97: EXTERNPROTO from an X3D classic (.x3dv) file is used") {
    const auto dir = tempDir("externproto_x3dv");
    writeFile(dir / "protos.x3dv", "#X3D V3.3 utf8\nPROFILE Interchange\n"
                                   "PROTO Slab [ field SFVec3f size 4 1 4 ] { Shape { geometry Box { size IS size } } }\n");
    const std::string path = writeFile(dir / "scene.wrl", "#VRML V2.0 utf8\n"
                                                          "EXTERNPROTO Slab [ field SFVec3f size ] \"protos.x3dv#Slab\"\n"
                                                          "Slab { size 1 2 3 }\n");
    Read r = readPath(path);
    INFO(r.messages());
    CHECK(r.ok);
    REQUIRE(r.scene.meshes.size() == 1);
    CHECK(r.area() == doctest::Approx(2 * (2 + 6 + 3)));
    CHECK_FALSE(r.has("not a VRML97 file"));
}

TEST_CASE("vrml97: Inline with a relative URL is placed by the current matrix") {
    const auto dir = tempDir("inline");
    writeFile(dir / "Parts" / "Quad.WRL", std::string("#VRML V2.0 utf8\n") + kQuad + "PointLight { location 1 0 0 }\n");
    const std::string path = writeFile(dir / "scene.wrl", R"(#VRML V2.0 utf8
Transform { translation 0 0 7 scale 2 2 2 children Inline { url "parts/quad.wrl" } }
Inline { url [ "http://example.com/x.wrl" "missing.wrl" ] }
)");
    Read r = readPath(path);
    CHECK(r.ok);
    REQUIRE(r.scene.meshes.size() == 1);
    CHECK(r.area() == doctest::Approx(4.0));
    CHECK(near(r.scene.meshes[0].positions[2], Vec3(2, 2, 7)));
    REQUIRE(r.scene.lights.size() == 1);
    CHECK(near(r.scene.lights[0].position, Vec3(2, 0, 7)));
    CHECK(r.scene.lights[0].radius == doctest::Approx(200.0f));
    CHECK(r.has("scene.wrl:3:1: warning: Inline file"));
    CHECK(r.has("missing.wrl' not found"));
}

TEST_CASE("vrml97: an Inline cycle is cut by the recursion guard") {
    const auto dir = tempDir("inline_cycle");
    writeFile(dir / "b.wrl", std::string("#VRML V2.0 utf8\n") + kQuad + "Inline { url \"a.wrl\" }\n");
    const std::string path = writeFile(dir / "a.wrl", "#VRML V2.0 utf8\nInline { url \"b.wrl\" }\nInline { url \"./a.wrl\" }\n");
    Read r = readPath(path);
    CHECK(r.ok);
    CHECK(r.scene.meshes.size() == 1);  // b's quad once; b -> a and a -> a are cut
    CHECK(r.diagnostics.warningCount() == 2);
    CHECK(r.has("includes a file already being read"));
}

TEST_CASE("vrml97: IndexedFaceSet ccw FALSE reverses winding; convex FALSE triangulates an L") {
    Read r = readVrml97("ifs", R"(
Shape { geometry IndexedFaceSet { ccw FALSE solid FALSE creaseAngle 0.5
  coord Coordinate { point [0 0 0, 1 0 0, 1 1 0] } coordIndex [0 1 2 -1] } }
Shape { geometry IndexedFaceSet { convex FALSE
  coord Coordinate { point [0 0 0, 2 0 0, 2 1 0, 1 1 0, 1 2 0, 0 2 0] } coordIndex [0 1 2 3 4 5 -1] } }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 2);
    const Mesh& tri = r.scene.meshes[0];
    CHECK_FALSE(tri.solid);
    CHECK(tri.crease_angle == doctest::Approx(0.5f));
    const Vec3 n = glm::cross(tri.positions[tri.triangles[0].y] - tri.positions[tri.triangles[0].x],
                              tri.positions[tri.triangles[0].z] - tri.positions[tri.triangles[0].x]);
    CHECK(n.z < 0.0f);
    const Mesh& l = r.scene.meshes[1];
    CHECK(l.polygon_count == 1);
    CHECK(l.triangles.size() == 4);
    double area = 0.0;
    for (size_t t = 0; t < l.triangles.size(); ++t) area += triangleArea(l, t);
    CHECK(area == doctest::Approx(3.0));
}

TEST_CASE("vrml97: IndexedFaceSet colours per vertex and per face are kept; bad faces are counted") {
    Read r = readVrml97("colors", R"(
Shape { geometry IndexedFaceSet { coord DEF C Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0, 9 9 9] }
  color Color { color [1 0 0, 0 1 0, 0 0 1, 1 1 1] } coordIndex [0 1 2 -1 0 2 3 -1] } }
Shape { geometry IndexedFaceSet { coord USE C colorPerVertex FALSE
  color Color { color [1 0 0, 0 1 0] } colorIndex [1 0] coordIndex [0 1 2 -1 0 2 3 -1 0 1 -1 0 1 7 -1] } }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 2);
    const Mesh& a = r.scene.meshes[0];
    CHECK(a.positions.size() == 4);  // the unused fifth point is not copied
    REQUIRE(a.vertex_colors.size() == 4);
    CHECK(a.vertex_colors[1] == Vec3(0, 1, 0));
    const Mesh& b = r.scene.meshes[1];
    CHECK(b.polygon_count == 2);
    REQUIRE(b.polygon_colors.size() == 2);
    CHECK(b.polygon_colors[0] == Vec3(0, 1, 0));
    CHECK(b.polygon_colors[1] == Vec3(1, 0, 0));
    CHECK(r.has("scene.wrl:5:18: warning: IndexedFaceSet: dropped 1 faces with fewer than 3 points and 1 faces with indices beyond its 5 points"));
}

TEST_CASE("vrml97: primitives Box, Sphere, Cylinder, Cone are closed convex solids") {
    Read r = readVrml97("prims", R"(
Shape { geometry Box { size 1 2 3 } }
Shape { geometry Sphere { radius 2 } }
Shape { geometry Cylinder { radius 1 height 2 } }
Shape { geometry Cone { bottomRadius 1 height 2 } }
Shape { geometry Cylinder { top FALSE } }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 5);
    CHECK(r.scene.meshes[0].polygon_count == 6);
    for (int m = 0; m < 4; ++m) CHECK(r.scene.meshes[size_t(m)].convex_solid);
    CHECK_FALSE(r.scene.meshes[4].convex_solid);
    double box = 0.0, sphere = 0.0;
    for (size_t t = 0; t < r.scene.meshes[0].triangles.size(); ++t) box += triangleArea(r.scene.meshes[0], t);
    for (size_t t = 0; t < r.scene.meshes[1].triangles.size(); ++t) sphere += triangleArea(r.scene.meshes[1], t);
    CHECK(box == doctest::Approx(22.0));
    CHECK(sphere == doctest::Approx(4 * kPi * 4).epsilon(0.02));  // tessellated sphere within 2%
}

TEST_CASE("vrml97: ElevationGrid vertices, quads and area") {
    Read r = readVrml97("grid", R"(
Shape { geometry ElevationGrid { xDimension 3 zDimension 2 xSpacing 2 zSpacing 1 height [0 0 0, 0 0 0]
  colorPerVertex FALSE color Color { color [1 0 0, 0 0 1] } } }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 1);
    const Mesh& mesh = r.scene.meshes[0];
    CHECK(mesh.positions.size() == 6);
    CHECK(mesh.polygon_count == 2);
    CHECK(near(mesh.positions[5], Vec3(4, 0, 1)));
    CHECK(r.area() == doctest::Approx(4.0));
    REQUIRE(mesh.polygon_colors.size() == 2);
    CHECK(mesh.polygon_colors[1] == Vec3(0, 0, 1));
    // counter-clockwise seen from +Y
    const UVec3 t = mesh.triangles[0];
    CHECK(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]).y > 0.0f);
}

TEST_CASE("vrml97: Extrusion defaults make a closed 2 x 1 x 2 box with outward faces") {
    Read r = readVrml97("extrusion", "Shape { geometry Extrusion { } }\n"
                                     "Shape { geometry Extrusion { crossSection [1 0, 0 1, -1 0, 0 -1, 1 0] spine [0 0 0, 0 0 3] } }\n");
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 2);
    const Mesh& box = r.scene.meshes[0];
    CHECK(box.polygon_count == 6);
    double area = 0.0;
    DVec3 centre(0.0);
    for (const Vec3& p : box.positions) centre += DVec3(p) / double(box.positions.size());
    for (size_t t = 0; t < box.triangles.size(); ++t) {
        area += triangleArea(box, t);
        const UVec3 tri = box.triangles[t];
        const DVec3 a(box.positions[tri.x]), b(box.positions[tri.y]), c(box.positions[tri.z]);
        CHECK(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0 - centre) > 0.0);  // outward
    }
    CHECK(area == doctest::Approx(16.0));
    // a diamond section along +Z: 4 sides of sqrt(2) x 3 plus two caps of area 2
    const Mesh& bar = r.scene.meshes[1];
    double bar_area = 0.0;
    for (size_t t = 0; t < bar.triangles.size(); ++t) bar_area += triangleArea(bar, t);
    CHECK(bar_area == doctest::Approx(4 * std::sqrt(2.0) * 3 + 2 * 2));
    float max_z = 0.0f;
    for (const Vec3& p : bar.positions) max_z = std::max(max_z, p.z);
    CHECK(max_z == doctest::Approx(3.0f));
}

TEST_CASE("vrml97: lines, points and text are ignored with one warning per kind") {
    Read r = readVrml97("lines", R"(
Shape { geometry IndexedLineSet { coord Coordinate { point [0 0 0, 1 0 0] } coordIndex [0 1] } }
Shape { geometry IndexedLineSet { } }
Shape { geometry PointSet { } }
Shape { geometry Text { string "hello {" } }
Shape { geometry Text { } }
)");
    CHECK(r.ok);
    CHECK(r.scene.meshes.empty());
    CHECK(r.diagnostics.warningCount() == 3);
    CHECK(r.has("scene.wrl:3:18: warning: IndexedLineSet nodes are ignored"));
    CHECK(r.has("scene.wrl:5:18: warning: PointSet nodes are ignored"));
    CHECK(r.has("scene.wrl:6:18: warning: Text nodes are ignored"));
}

TEST_CASE("vrml97: Material fields become the scene material") {
    Read r = readVrml97("material", R"(
Shape { appearance Appearance { material DEF Lamp Material { diffuseColor 0.2 0.3 0.4 emissiveColor 5 5 4
  ambientIntensity 0.5 transparency 0.25 } texture ImageTexture { url "wood.png" } } geometry Box { } }
Shape { appearance Appearance { material USE Lamp texture ImageTexture { url "wood.png" } } geometry Box { } }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.materials.size() == 1);  // shared through USE
    const Material& m = r.scene.materials[0];
    CHECK(m.name == "Lamp");
    CHECK(m.reflectance == Vec3(0.2f, 0.3f, 0.4f));
    CHECK(m.emission == Vec3(5, 5, 4));
    CHECK(m.ambient_intensity == 0.5f);
    CHECK(m.transparency == 0.25f);
    CHECK(m.base_color_texture.path.ends_with("wood.png"));  // resolved against the file
    CHECK(m.base_color_texture.rgb_replaces);                // VRML97: an RGB texture replaces diffuseColor
    CHECK(m.base_color_texture.location.line == 4);  // the ImageTexture node
    CHECK(m.location.line == 3);
}

TEST_CASE("vrml97: a material without a DEF name takes its Appearance's, else its place") {
    Read r = readVrml97("names", R"(
Shape { appearance DEF White Appearance { material Material { diffuseColor 0.7 0.7 0.7 } } geometry Box { } }
Shape { appearance Appearance { material Material { } } geometry Box { } }
Shape { appearance DEF Outer Appearance { material DEF Inner Material { } } geometry Box { } }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.materials.size() == 3);
    CHECK(r.scene.materials[0].name == "White");
    CHECK(r.scene.materials[1].name == "Material@4:42");
    CHECK(r.scene.materials[2].name == "Inner");  // the Material's own name first
}

TEST_CASE("vrml97: lights and viewpoints are kept in world space") {
    Read r = readVrml97("lights", R"(
Transform { translation 0 10 0 rotation 0 1 0 1.5707963 children [
  PointLight { location 1 0 0 intensity 0.5 color 1 0.5 0 attenuation 0 0 1 radius 7 }
  SpotLight { location 0 0 0 direction 0 0 -1 beamWidth 0.2 cutOffAngle 0.3 on FALSE }
  DirectionalLight { direction 0 -1 0 }
  Viewpoint { position 0 0 5 fieldOfView 0.5 description "front" }
] }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.lights.size() == 3);
    const Light& point = r.scene.lights[0];
    CHECK(point.type == LightType::Point);
    CHECK(near(point.position, Vec3(0, 10, -1)));  // +X turned by +90 deg about Y is -Z
    CHECK(point.intensity == 0.5f);
    CHECK(point.color == Vec3(1, 0.5f, 0));
    CHECK(point.attenuation == Vec3(0, 0, 1));
    CHECK(point.radius == doctest::Approx(7.0f));
    const Light& spot = r.scene.lights[1];
    CHECK(spot.type == LightType::Spot);
    CHECK(near(spot.direction, Vec3(-1, 0, 0)));
    CHECK(spot.beam_width == 0.2f);
    CHECK(spot.cut_off_angle == 0.3f);
    CHECK_FALSE(spot.on);
    CHECK(r.scene.lights[2].type == LightType::Directional);
    CHECK(near(r.scene.lights[2].direction, Vec3(0, -1, 0)));
    REQUIRE(r.scene.cameras.size() == 1);
    const Camera& camera = r.scene.cameras[0];
    CHECK(camera.name == "front");
    CHECK(near(camera.position, Vec3(5, 10, 0)));
    CHECK(near(camera.orientation * Vec3(0, 0, -1), Vec3(-1, 0, 0)));  // looks toward the origin's axis
    CHECK(camera.field_of_view == 0.5f);
}

TEST_CASE("vrml97: PROTO and ROUTE inside a node body") {
    Read r = readVrml97("proto_in_body", R"(
Group { PROTO Red [ ] { Material { diffuseColor 1 0 0 } }
  children Shape { appearance Appearance { material Red { } } geometry Box { } }
  ROUTE a.b TO c.d }
Shape { appearance Appearance { material Red { } } geometry Box { } }
)");
    CHECK(r.ok);
    REQUIRE(r.scene.meshes.size() == 2);
    CHECK(r.scene.materials.at(r.scene.meshes[0].material).reflectance == Vec3(1, 0, 0));
    CHECK(r.scene.materials.at(r.scene.meshes[1].material).reflectance == Vec3(1, 0, 0));
}

namespace {

// The texture coordinate of the mesh's vertex at `p` on a triangle whose face normal is
// nearest `normal` (a corner belongs to several faces), or NaN when none.
Vec2 uvAt(const Mesh& mesh, Vec3 p, Vec3 normal) {
    Vec2 best(std::numeric_limits<float>::quiet_NaN());
    double best_dot = -2.0;
    for (const UVec3& t : mesh.triangles) {
        const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
        const DVec3 n = glm::normalize(glm::cross(b - a, c - a));
        for (int k = 0; k < 3; ++k)
            if (glm::distance(mesh.positions[t[k]], p) < 1e-5f && glm::dot(n, DVec3(normal)) > best_dot) {
                best_dot = glm::dot(n, DVec3(normal));
                best = mesh.uv0[t[k]];
            }
    }
    return best;
}

void checkUv(Vec2 got, Vec2 want) {
    CHECK(got.x == doctest::Approx(want.x).epsilon(1e-5));
    CHECK(got.y == doctest::Approx(want.y).epsilon(1e-5));
}

}  // namespace

TEST_CASE("vrml97: textured Box, Sphere, Cylinder and Cone carry the standard's texture coordinates") {
    Read r = readVrml97("primitive_uvs", R"(
Shape { appearance Appearance { texture ImageTexture { url "wood.png" } } geometry Box { size 2 4 6 } }
Shape { appearance Appearance { texture ImageTexture { url "wood.png" } } geometry Sphere { radius 2 } }
Shape { appearance Appearance { texture ImageTexture { url "wood.png" } } geometry Cylinder { radius 1 height 4 } }
Shape { appearance Appearance { texture ImageTexture { url "wood.png" } } geometry Cone { bottomRadius 1 height 2 } }
Shape { geometry Box { } }
)");
    REQUIRE(r.ok);
    REQUIRE(r.scene.meshes.size() == 5);
    for (size_t m = 0; m < 4; ++m) {
        CAPTURE(m);
        CHECK(r.scene.materials[r.scene.meshes[m].material].base_color_texture.path.ends_with("wood.png"));
        CHECK(r.scene.meshes[m].uv0.size() == r.scene.meshes[m].positions.size());
    }
    CHECK(r.scene.meshes[4].uv0.empty());  // untextured: no coordinates, vertices shared as before
    CHECK(r.scene.meshes[4].positions.size() == 8);

    // ISO/IEC 14772-1 6.4: each face the whole image, upright as seen from outside (top: -Z up,
    // bottom: +Z up). The corner (1, 2, 3) on each of its three faces, and the opposite corner.
    const Mesh& box = r.scene.meshes[0];
    CHECK(box.positions.size() > 8);  // corners split where their faces differ
    checkUv(uvAt(box, Vec3(1, 2, 3), Vec3(0, 0, 1)), Vec2(1, 1));   // front: top right
    checkUv(uvAt(box, Vec3(1, 2, 3), Vec3(1, 0, 0)), Vec2(0, 1));   // right, seen from +X: top left
    checkUv(uvAt(box, Vec3(1, 2, 3), Vec3(0, 1, 0)), Vec2(1, 0));   // top: near right is bottom right
    checkUv(uvAt(box, Vec3(-1, -2, -3), Vec3(0, 0, -1)), Vec2(1, 0));  // back, seen from -Z: bottom right
    checkUv(uvAt(box, Vec3(-1, -2, -3), Vec3(-1, 0, 0)), Vec2(0, 0));  // left, seen from -X: bottom left
    checkUv(uvAt(box, Vec3(-1, -2, -3), Vec3(0, -1, 0)), Vec2(0, 0));  // bottom, +Z up: far left

    // 6.43: s from 0 at -Z counter-clockwise seen from above (-X 0.25, +Z 0.5, +X 0.75), t
    // by latitude from the bottom; the seam at -Z holds both 0 and 1.
    const Mesh& sphere = r.scene.meshes[1];
    checkUv(uvAt(sphere, Vec3(0, 0, 2), Vec3(0, 0, 1)), Vec2(0.5f, 0.5f));
    checkUv(uvAt(sphere, Vec3(2, 0, 0), Vec3(1, 0, 0)), Vec2(0.75f, 0.5f));
    checkUv(uvAt(sphere, Vec3(-2, 0, 0), Vec3(-1, 0, 0)), Vec2(0.25f, 0.5f));
    checkUv(uvAt(sphere, Vec3(0, 0, -2), Vec3(-0.2f, 0, -1)), Vec2(0.0f, 0.5f));  // the seam's -X side
    checkUv(uvAt(sphere, Vec3(0, 0, -2), Vec3(0.2f, 0, -1)), Vec2(1.0f, 0.5f));   // its +X side
    const float ring = 2.0f * std::sin(static_cast<float>(kPi) / 16.0f);  // the first ring below the north pole
    checkUv(uvAt(sphere, Vec3(0, 2.0f * std::cos(static_cast<float>(kPi) / 16.0f), ring), Vec3(0, 1, 1)),
            Vec2(0.5f, 15.0f / 16.0f));

    // 6.17: the side as the sphere's, t linear in height; caps upright with the top tilted
    // towards +Z (top: -Z up) or towards -Z (bottom: +Z up).
    const Mesh& cylinder = r.scene.meshes[2];
    checkUv(uvAt(cylinder, Vec3(1, 2, 0), Vec3(1, 0, 0)), Vec2(0.75f, 1.0f));
    checkUv(uvAt(cylinder, Vec3(-1, -2, 0), Vec3(-1, 0, 0)), Vec2(0.25f, 0.0f));
    checkUv(uvAt(cylinder, Vec3(0, 2, 1), Vec3(0, 1, 0)), Vec2(0.5f, 0.0f));   // top cap, +Z edge at the bottom
    checkUv(uvAt(cylinder, Vec3(1, 2, 0), Vec3(0, 1, 0)), Vec2(1.0f, 0.5f));
    checkUv(uvAt(cylinder, Vec3(0, -2, 1), Vec3(0, -1, 0)), Vec2(0.5f, 1.0f));  // bottom cap, +Z edge at the top

    // 6.14: the side as the cylinder's, the apex at t = 1 (each side triangle's own s), the
    // bottom as the cylinder's.
    const Mesh& cone = r.scene.meshes[3];
    checkUv(uvAt(cone, Vec3(0, -1, 1), Vec3(0, 0.5f, 1)), Vec2(0.5f, 0.0f));
    checkUv(uvAt(cone, Vec3(0, -1, 1), Vec3(0, -1, 0)), Vec2(0.5f, 1.0f));
    CHECK(uvAt(cone, Vec3(0, 1, 0), Vec3(0, 0.5f, 1)).y == doctest::Approx(1.0f));
}
