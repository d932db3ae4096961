// Hard edges from file to bake (issue 13): VRML97, VRML 1.0 and OBJ files whose faces meet
// at hard edges come out with each face's corners its own, carrying that face's normal and
// light; smooth surfaces keep their shared vertices.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "export/mesh_attributes.h"
#include "radbake.h"
#include "radiosity/form_factor.h"
#include "../export/temp_files.h"

using namespace radbake;
using testfs::TempDir;

namespace {

Scene import(const std::string& path) {
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(path, {}, diagnostics);
    for (const Diagnostic& d : diagnostics.all()) MESSAGE(formatDiagnostic(d));
    REQUIRE(scene);
    return std::move(*scene);
}

DVec3 faceNormal(const Mesh& mesh, size_t t) {
    const UVec3& tri = mesh.triangles[t];
    const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
    return glm::normalize(glm::cross(b - a, c - a));
}

// Every corner of every triangle has, as its exported normal, its triangle's face normal.
void checkFlatNormals(const Mesh& mesh) {
    const std::vector<Vec3> normals = vertexNormals(mesh);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k)
            CHECK(glm::dot(DVec3(normals[mesh.triangles[t][k]]), faceNormal(mesh, t)) == doctest::Approx(1.0).epsilon(1e-6));
}

constexpr const char* kCubeCoordinates =
    "coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0, 1 1 0, 0 0 1, 1 0 1, 0 1 1, 1 1 1 ] }\n"
    "coordIndex [ 0 2 3 1 -1, 4 5 7 6 -1, 0 1 5 4 -1, 2 6 7 3 -1, 0 4 6 2 -1, 1 3 7 5 -1 ]\n";

}  // namespace

TEST_CASE("hard edges: a VRML97 Box and an IndexedFaceSet cube with shared corners come out with 24 vertices") {
    TempDir dir;
    const Scene box = import(testfs::writeText(dir, "box.wrl", "#VRML V2.0 utf8\nShape { geometry Box { } }\n"));
    REQUIRE(box.meshes.size() == 1);
    CHECK(box.meshes[0].positions.size() == 24);
    checkFlatNormals(box.meshes[0]);
    CHECK(box.crease_split.vertices == 8);
    CHECK(box.crease_split.added == 16);

    const Scene cube = import(testfs::writeText(dir, "cube.wrl", std::string("#VRML V2.0 utf8\nShape { geometry IndexedFaceSet {\n") +
                                                         kCubeCoordinates + "} }\n"));
    REQUIRE(cube.meshes.size() == 1);
    CHECK(cube.meshes[0].crease_angle == 0.0f);  // VRML97's default
    CHECK(cube.meshes[0].positions.size() == 24);
    checkFlatNormals(cube.meshes[0]);

    // creaseAngle above 90 degrees: the file asks for a smooth cube, and gets one.
    const Scene smooth = import(testfs::writeText(dir, "smooth.wrl",
                                      std::string("#VRML V2.0 utf8\nShape { geometry IndexedFaceSet { creaseAngle 1.6\n") +
                                          kCubeCoordinates + "} }\n"));
    CHECK(smooth.meshes[0].positions.size() == 8);
    CHECK(smooth.crease_split.added == 0);
}

TEST_CASE("hard edges: round primitives keep their sides smooth and split only at the rims") {
    TempDir dir;
    const Scene scene = import(testfs::writeText(dir, "round.wrl",
                                     "#VRML V2.0 utf8\n"
                                     "Shape { geometry Sphere { } }\n"
                                     "Transform { translation 3 0 0 children Shape { geometry Cylinder { } } }\n"
                                     "Transform { translation 6 0 0 children Shape { geometry Cylinder { top FALSE bottom FALSE } } }\n"
                                     "Transform { translation 9 0 0 children Shape { geometry Cone { } } }\n"));
    REQUIRE(scene.meshes.size() == 4);
    // Sphere: the poles and 15 rings of 32, all smooth (11.25 degree facets, crease 0.5 rad).
    CHECK(scene.meshes[0].positions.size() == 2 + 15 * 32);
    // Cylinder: each rim vertex is one vertex of the side and one of its cap.
    CHECK(scene.meshes[1].positions.size() == 4 * 32);
    CHECK(scene.meshes[2].positions.size() == 2 * 32);
    // Cone: the apex stays one smooth vertex, the rim splits from the base.
    CHECK(scene.meshes[3].positions.size() == 1 + 2 * 32);
    // The cylinder side's normals are radial (smooth), its caps' are the axis.
    const Mesh& cylinder = scene.meshes[1];
    const std::vector<Vec3> normals = vertexNormals(cylinder);
    size_t radial = 0, axial = 0;
    for (size_t v = 0; v < normals.size(); ++v) {
        const Vec3 n = normals[v];
        if (std::abs(n.y) < 1e-6f) {
            const Vec3 r = glm::normalize(Vec3(cylinder.positions[v].x - 3.0f, 0.0f, cylinder.positions[v].z));
            CHECK(glm::dot(n, r) == doctest::Approx(1.0f).epsilon(1e-5));
            ++radial;
        } else if (std::abs(std::abs(n.y) - 1.0f) < 1e-6f) {
            ++axial;
        }
    }
    CHECK(radial == 64);
    CHECK(axial == 64);
}

TEST_CASE("hard edges: VRML 1.0 ShapeHints creaseAngle defaults to 0.5 rad") {
    TempDir dir;
    // Two quads folded by 20 degrees and two folded by 40 degrees along x = 0.
    const auto folded = [](double degrees) {
        const double a = degrees * kPi / 180.0;
        return "Coordinate3 { point [ -1 0 0, 0 0 0, 0 1 0, -1 1 0, " + std::to_string(std::cos(a)) + " 0 " +
               std::to_string(std::sin(a)) + ", " + std::to_string(std::cos(a)) + " 1 " + std::to_string(std::sin(a)) +
               " ] }\nIndexedFaceSet { coordIndex [ 0 1 2 3 -1, 1 4 5 2 -1 ] }\n";
    };
    const Scene scene = import(testfs::writeText(dir, "folds.wrl",
                                     "#VRML V1.0 ascii\nSeparator {\n Separator { " + folded(20.0) + " }\n Separator { Translation { translation 0 0 5 } " +
                                         folded(40.0) + " }\n Separator { Translation { translation 0 0 -5 } Cube { } }\n}\n"));
    REQUIRE(scene.meshes.size() == 3);
    CHECK(scene.meshes[0].crease_angle == doctest::Approx(0.5f));
    CHECK(scene.meshes[0].positions.size() == 6);  // 20 degrees < 28.6: smooth
    CHECK(scene.meshes[1].positions.size() == 8);  // 40 degrees: split along the fold
    CHECK(scene.meshes[2].positions.size() == 24);
    checkFlatNormals(scene.meshes[2]);
}

TEST_CASE("hard edges: an OBJ keeps its per-face normals apart; without normals its edges are hard") {
    TempDir dir;
    const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n";
    const std::string faced = v +
                              "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n"
                              "f 1//1 3//1 4//1 2//1\nf 5//2 6//2 8//2 7//2\nf 1//3 2//3 6//3 5//3\n"
                              "f 3//4 7//4 8//4 4//4\nf 1//5 5//5 7//5 3//5\nf 2//6 4//6 8//6 6//6\n";
    const Scene with_normals = import(testfs::writeText(dir, "faced.obj", faced));
    REQUIRE(with_normals.meshes.size() == 1);
    CHECK(with_normals.meshes[0].positions.size() == 24);
    CHECK(with_normals.meshes[0].normals.size() == 24);
    CHECK(with_normals.crease_split.added == 0);  // the file already kept them apart
    checkFlatNormals(with_normals.meshes[0]);

    const std::string bare = v + "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    const Scene without = import(testfs::writeText(dir, "bare.obj", bare));
    CHECK(without.meshes[0].positions.size() == 24);
    checkFlatNormals(without.meshes[0]);

    // Shared smooth normals: the file says the corners are smooth, so they stay shared.
    std::string smooth = v;
    for (int c = 0; c < 8; ++c)
        smooth += "vn " + std::string(c & 1 ? "1" : "-1") + (c & 2 ? " 1" : " -1") + (c & 4 ? " 1\n" : " -1\n");
    smooth += "f 1//1 3//3 4//4 2//2\nf 5//5 6//6 8//8 7//7\nf 1//1 2//2 6//6 5//5\n"
              "f 3//3 7//7 8//8 4//4\nf 1//1 5//5 7//7 3//3\nf 2//2 4//4 8//8 6//6\n";
    CHECK(import(testfs::writeText(dir, "smooth.obj", smooth)).meshes[0].positions.size() == 8);
}

TEST_CASE("hard edges: a black cube above an emitting floor bakes each face's own light at a shared corner") {
    // Floor: 20 x 20 at y = 0, emitting radiance 1, black; the cube: black, 1 m, 0.1 m above.
    TempDir dir;
    const std::string path = testfs::writeText(dir, "cube_on_floor.wrl",
                                   "#VRML V2.0 utf8\n"
                                   "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 1 1 1 } }\n"
                                   " geometry IndexedFaceSet { coord Coordinate { point [ -10 0 -10, -10 0 10, 10 0 10, 10 0 -10 ] }\n"
                                   "  coordIndex [ 0 1 2 3 -1 ] } }\n"
                                   "Transform { translation 0 0.6 0 children Shape {\n"
                                   " appearance Appearance { material Material { diffuseColor 0 0 0 } } geometry Box { size 1 1 1 } } }\n");
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.lightmaps.enabled = false;
    options.threading.threads = 2;
    Progress progress(false);
    Diagnostics diagnostics;
    const Bake baked = bake(path, options, progress, diagnostics);
    for (const Diagnostic& d : diagnostics.all()) MESSAGE(formatDiagnostic(d));
    REQUIRE(std::string(toString(baked.status)) == "ok");
    const Mesh& cube = baked.scene->meshes[1];
    REQUIRE(cube.positions.size() == 24);
    const std::vector<Vec3>& values = baked.vertices.values[1];
    const std::vector<DVec3> floor = {{-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}};
    const std::vector<Vec3> normals = vertexNormals(cube);
    size_t bottom = 0, side = 0, top = 0;
    for (size_t v = 0; v < cube.positions.size(); ++v) {
        if (normals[v].y > 0.5f) {  // the top face: nothing lights it
            CHECK(values[v].x == 0.0f);
            ++top;
            continue;
        }
        // H / pi = the unoccluded form factor to the floor in the face's own direction (the
        // cube is behind each of its faces): nearly 1 under it, nearly 1/2 on the sides' bottom
        // edges (the floor's far edges are 10 m away).
        const double expected = pointPolygonFormFactor(DVec3(cube.positions[v]), DVec3(normals[v]), floor, {0, 1, 0});
        CAPTURE(values[v].x);
        CAPTURE(expected);
        CHECK(std::abs(values[v].x / expected - 1.0) < 0.02);  // relative (Approx adds 1 to the scale)
        if (normals[v].y < -0.5f) {
            CHECK(expected > 0.95);
            ++bottom;
        } else {
            if (cube.positions[v].y < 0.6f) CHECK(std::abs(expected - 0.5) < 0.015);  // bottom edge
            ++side;
        }
    }
    CHECK(bottom == 4);
    CHECK(side == 16);
    CHECK(top == 4);
}
