// splitHardEdges on tiny literal meshes: which vertices split, what the copies carry.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <set>

#include "scene/creases.h"

using namespace radbake;

namespace {

// A unit cube with its 8 corners shared by its 6 quads (each two triangles of one polygon),
// counter-clockwise seen from outside.
Mesh sharedCube(float crease_angle) {
    Mesh mesh;
    for (int c = 0; c < 8; ++c) mesh.positions.push_back(Vec3(c & 1 ? 1.0f : 0.0f, c & 2 ? 1.0f : 0.0f, c & 4 ? 1.0f : 0.0f));
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        mesh.triangles.push_back(UVec3(q[0], q[1], q[2]));
        mesh.triangles.push_back(UVec3(q[0], q[2], q[3]));
        mesh.triangle_polygon.push_back(mesh.polygon_count);
        mesh.triangle_polygon.push_back(mesh.polygon_count);
        ++mesh.polygon_count;
    }
    mesh.crease_angle = crease_angle;
    return mesh;
}

DVec3 faceNormal(const Mesh& mesh, size_t t) {
    const UVec3& tri = mesh.triangles[t];
    const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
    return glm::normalize(glm::cross(b - a, c - a));
}

// The distinct face normals around each vertex, as a count per vertex.
std::vector<size_t> normalsPerVertex(const Mesh& mesh) {
    std::vector<std::vector<DVec3>> around(mesh.positions.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const DVec3 n = faceNormal(mesh, t);
        for (int k = 0; k < 3; ++k) {
            auto& list = around[mesh.triangles[t][k]];
            bool seen = false;
            for (const DVec3& m : list) seen = seen || glm::dot(m, n) > 1.0 - 1e-9;
            if (!seen) list.push_back(n);
        }
    }
    std::vector<size_t> counts;
    for (const auto& list : around) counts.push_back(list.size());
    return counts;
}

// A strip of two quads folded along x = 0 by `degrees` (0: flat), one polygon each.
Mesh foldedStrip(double degrees, float crease_angle) {
    Mesh mesh;
    const double a = degrees * kPi / 180.0;
    const float x = static_cast<float>(std::cos(a)), z = static_cast<float>(std::sin(a));
    mesh.positions = {{-1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {x, 0, z}, {x, 1, z}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
    mesh.triangle_polygon = {0, 0, 1, 1};
    mesh.polygon_count = 2;
    mesh.crease_angle = crease_angle;
    return mesh;
}

size_t added(Mesh mesh) { return splitHardEdges(mesh); }

}  // namespace

TEST_CASE("creases: a cube with shared corners splits into 24 vertices, one face normal each") {
    Mesh cube = sharedCube(0.0f);
    size_t split = 0;
    CHECK(splitHardEdges(cube, &split) == 16);
    CHECK(split == 8);
    REQUIRE(cube.positions.size() == 24);
    for (size_t count : normalsPerVertex(cube)) CHECK(count == 1);
    // Each face's four corners are its own: no vertex is used by two polygons.
    std::vector<std::set<uint32_t>> polygons(cube.positions.size());
    for (size_t t = 0; t < cube.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) polygons[cube.triangles[t][k]].insert(cube.triangle_polygon[t]);
    for (const auto& p : polygons) CHECK(p.size() == 1);
    // The copies sit where their originals were.
    std::set<std::array<float, 3>> corners;
    for (const Vec3& p : cube.positions) corners.insert({p.x, p.y, p.z});
    CHECK(corners.size() == 8);
}

TEST_CASE("creases: a crease angle above the cube's 90 degrees keeps it smooth, and splitting twice changes nothing") {
    Mesh smooth = sharedCube(1.6f);
    CHECK(splitHardEdges(smooth) == 0);
    CHECK(smooth.positions.size() == 8);
    Mesh hard = sharedCube(1.5f);  // 86 degrees: every edge is hard
    CHECK(splitHardEdges(hard) == 16);
    const std::vector<UVec3> once = hard.triangles;
    CHECK(splitHardEdges(hard) == 0);
    CHECK(hard.triangles == once);
}

TEST_CASE("creases: an edge splits only when sharper than the crease angle; flat edges never split") {
    CHECK(added(foldedStrip(0.0, 0.0f)) == 0);    // two coplanar polygons
    CHECK(added(foldedStrip(0.5, 0.0f)) == 0);    // bent by 0.5 degree: coplanar
    CHECK(added(foldedStrip(20.0, 0.0f)) == 2);   // VRML97's default 0
    CHECK(added(foldedStrip(20.0, 0.5f)) == 0);   // 20 < 28.6 degrees
    CHECK(added(foldedStrip(40.0, 0.5f)) == 2);   // 40 > 28.6 degrees
    // One polygon's triangles stay together however bent (a non-planar quad).
    Mesh bent = foldedStrip(40.0, 0.0f);
    bent.triangle_polygon = {0, 0, 0, 0};
    bent.polygon_count = 1;
    CHECK(splitHardEdges(bent) == 0);
}

TEST_CASE("creases: copies carry the vertex's colour and uv0; a mesh with its own normals is left alone") {
    Mesh strip = foldedStrip(90.0, 0.0f);
    for (size_t v = 0; v < strip.positions.size(); ++v) {
        strip.uv0.push_back(Vec2(float(v), 0.5f));
        strip.vertex_colors.push_back(Vec3(float(v) / 10.0f));
    }
    REQUIRE(splitHardEdges(strip) == 2);
    REQUIRE(strip.positions.size() == 8);
    REQUIRE(strip.uv0.size() == 8);
    REQUIRE(strip.vertex_colors.size() == 8);
    // Vertices 1 and 2 (on the fold) are copied as 6 and 7, used by the second polygon.
    CHECK(strip.positions[6] == strip.positions[1]);
    CHECK(strip.positions[7] == strip.positions[2]);
    CHECK(strip.uv0[6] == strip.uv0[1]);
    CHECK(strip.uv0[7] == strip.uv0[2]);
    CHECK(strip.vertex_colors[7] == strip.vertex_colors[2]);
    CHECK(strip.triangles[2] == UVec3(6, 4, 5));
    CHECK(strip.triangles[3] == UVec3(6, 5, 7));
    CHECK(strip.triangles[0] == UVec3(0, 1, 2));

    Mesh given = sharedCube(0.0f);
    given.normals.assign(8, Vec3(0.0f, 0.0f, 1.0f));
    CHECK(splitHardEdges(given) == 0);
    CHECK(given.positions.size() == 8);
}

TEST_CASE("creases: the scene counts what it split") {
    Scene scene;
    scene.meshes = {sharedCube(0.0f), sharedCube(1.6f), foldedStrip(90.0, 0.0f)};
    splitHardEdges(scene);
    CHECK(scene.crease_split.meshes == 2);
    CHECK(scene.crease_split.vertices == 8 + 2);
    CHECK(scene.crease_split.added == 16 + 2);
    splitHardEdges(scene);
    CHECK(scene.crease_split.added == 18);
}
