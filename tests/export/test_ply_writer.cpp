// The PLY writer: exact header text, and the binary body decoded back to the same floats
// and indices (meshes merged, later meshes' indices offset by the earlier vertex counts).
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "export/hash.h"
#include "export/ply_writer.h"

using namespace radbake;

namespace {
Scene twoMeshScene() {
    Scene scene;
    scene.name = "two";
    scene.materials.resize(1);
    Mesh a;
    a.name = "a";
    a.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};  // faces +Z
    a.triangles = {{0, 1, 2}};
    a.triangle_polygon = {0};
    a.polygon_count = 1;
    Mesh b;
    b.name = "b";
    b.positions = {{0, 0, 1}, {0, 0, 2}, {0, 3, 1}, {0, 3, 2}};  // faces -X
    b.triangles = {{0, 1, 2}, {2, 1, 3}};
    b.triangle_polygon = {0, 0};
    b.polygon_count = 1;
    scene.meshes = {a, b};
    return scene;
}

template <typename T>
T readAt(const std::string& bytes, size_t& offset) {
    T value;
    std::memcpy(&value, bytes.data() + offset, sizeof(T));
    offset += sizeof(T);
    return value;
}
}  // namespace

TEST_CASE("PLY header and body decode back to the same numbers") {
    const Scene scene = twoMeshScene();
    VertexBake bake;
    bake.values = {{{0.5f, 1.25f, 7.0f}, {0, 0, 0}, {1e-6f, 2, 3}},
                   {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {100, 200, 300}}};
    Diagnostics diagnostics;
    const std::string bytes = encodePly(scene, bake, {"radbake test"}, diagnostics);
    CHECK_FALSE(diagnostics.hasErrors());

    const std::string expected_header =
        "ply\n"
        "format binary_little_endian 1.0\n"
        "comment generator radbake test\n"
        "comment scene two\n"
        "comment red green blue: baked irradiance H/pi per vertex, linear float, unclamped\n"
        "element vertex 7\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "property float red\nproperty float green\nproperty float blue\n"
        "element face 3\n"
        "property list uchar int vertex_indices\n"
        "end_header\n";
    REQUIRE(bytes.size() == expected_header.size() + 7 * 36 + 3 * 13);
    CHECK(bytes.substr(0, expected_header.size()) == expected_header);

    size_t offset = expected_header.size();
    for (size_t m = 0; m < 2; ++m) {
        const Vec3 normal = m == 0 ? Vec3(0, 0, 1) : Vec3(-1, 0, 0);
        for (size_t v = 0; v < scene.meshes[m].positions.size(); ++v) {
            for (int k = 0; k < 3; ++k) CHECK(readAt<float>(bytes, offset) == scene.meshes[m].positions[v][k]);
            for (int k = 0; k < 3; ++k) CHECK(readAt<float>(bytes, offset) == normal[k]);
            for (int k = 0; k < 3; ++k) CHECK(readAt<float>(bytes, offset) == bake.values[m][v][k]);
        }
    }
    const int32_t expected_faces[3][3] = {{0, 1, 2}, {3, 4, 5}, {5, 4, 6}};
    for (const auto& face : expected_faces) {
        CHECK(readAt<uint8_t>(bytes, offset) == 3);
        for (int k = 0; k < 3; ++k) CHECK(readAt<int32_t>(bytes, offset) == face[k]);
    }
    CHECK(offset == bytes.size());
}

TEST_CASE("PLY writer refuses a bake with the wrong mesh count") {
    VertexBake bake;
    bake.values = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    Diagnostics diagnostics;
    CHECK(encodePly(twoMeshScene(), bake, {}, diagnostics).empty());
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].message == "internal: baked values for 1 meshes, scene has 2");
}

TEST_CASE("without lightmaps the PLY is byte-identical to the writer before lightmaps") {
    VertexBake bake;
    bake.values = {{{0.5f, 1.25f, 7.0f}, {0, 0, 0}, {1e-6f, 2, 3}}, {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {100, 200, 300}}};
    Diagnostics diagnostics;
    // SHA-256 of this file as written before PlyOptions::lightmaps existed.
    CHECK(sha256Hex(encodePly(twoMeshScene(), bake, {"radbake test"}, diagnostics)) == "d13b3e69853d1fc71305b29fb273bdf49a8617b7f3c201411c78ecea584d80eb");
}

TEST_CASE("PLY with lightmaps: lightmap vertices with u1 v1 and the atlas, 255 for a mesh without charts") {
    const Scene scene = twoMeshScene();
    VertexBake bake;
    bake.values = {{{0, 0, 0}, {3, 6, 9}, {30, 60, 90}}, {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {100, 200, 300}}};
    // Mesh a in one chart on atlas 1, fanned around a vertex at the middle of its edge 1-2.
    LightmapFiles lightmaps;
    lightmaps.atlas_files = {"lightmaps/two_0.exr", "lightmaps/two_1.exr"};
    LightmapMesh a;
    const std::vector<Vec3>& p = scene.meshes[0].positions;
    a.positions = {p[0], p[1], 0.5f * (p[1] + p[2]), p[2]};
    a.uv = {{0.5f, 0.5f}, {1.0f, 0.5f}, {0.75f, 0.75f}, {0.5f, 1.0f}};
    a.atlas = {1, 1, 1, 1};
    a.source_corners = {{0, 1, 2}, {0, 1, 2}, {0, 1, 2}, {0, 1, 2}};
    a.barycentric = {{1, 0, 0}, {0, 1, 0}, {0, 0.5f, 0.5f}, {0, 0, 1}};
    a.triangles = {{0, 1, 2}, {0, 2, 3}};
    a.source_triangle = {0, 0};
    lightmaps.meshes = {a, LightmapMesh{}};
    PlyOptions options{"radbake test"};
    options.lightmaps = &lightmaps;
    Diagnostics diagnostics;
    const std::string bytes = encodePly(scene, bake, options, diagnostics);
    CHECK(diagnostics.all().empty());

    const std::string expected_header =
        "ply\n"
        "format binary_little_endian 1.0\n"
        "comment generator radbake test\n"
        "comment scene two\n"
        "comment red green blue: baked irradiance H/pi per vertex, linear float, unclamped\n"
        "comment u1 v1: lightmap UV (u right, v down from the image's top row) in the atlas named by lightmap\n"
        "comment lightmap: atlas index, 255 where the mesh has no lightmap\n"
        "comment lightmap 0 lightmaps/two_0.exr\n"
        "comment lightmap 1 lightmaps/two_1.exr\n"
        "element vertex 8\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "property float red\nproperty float green\nproperty float blue\n"
        "property float u1\nproperty float v1\nproperty uchar lightmap\n"
        "element face 4\n"
        "property list uchar int vertex_indices\n"
        "end_header\n";
    REQUIRE(bytes.size() == expected_header.size() + 8 * 45 + 4 * 13);
    CHECK(bytes.substr(0, expected_header.size()) == expected_header);

    size_t offset = expected_header.size();
    const Vec3 a_values[4] = {{0, 0, 0}, {3, 6, 9}, {16.5f, 33, 49.5f}, {30, 60, 90}};  // the cut vertex: mean of 1 and 2
    for (size_t v = 0; v < 4; ++v) {
        for (int k = 0; k < 3; ++k) CHECK(readAt<float>(bytes, offset) == a.positions[v][k]);
        for (int k = 0; k < 3; ++k) CHECK(readAt<float>(bytes, offset) == Vec3(0, 0, 1)[k]);  // face normal
        for (int k = 0; k < 3; ++k) CHECK(readAt<float>(bytes, offset) == doctest::Approx(a_values[v][k]));
        CHECK(readAt<float>(bytes, offset) == a.uv[v].x);
        CHECK(readAt<float>(bytes, offset) == a.uv[v].y);
        CHECK(readAt<uint8_t>(bytes, offset) == 1);
    }
    for (size_t v = 0; v < 4; ++v) {
        for (int k = 0; k < 3; ++k) CHECK(readAt<float>(bytes, offset) == scene.meshes[1].positions[v][k]);
        for (int k = 0; k < 3; ++k) CHECK(readAt<float>(bytes, offset) == Vec3(-1, 0, 0)[k]);
        for (int k = 0; k < 3; ++k) CHECK(readAt<float>(bytes, offset) == bake.values[1][v][k]);
        CHECK(readAt<float>(bytes, offset) == 0.0f);
        CHECK(readAt<float>(bytes, offset) == 0.0f);
        CHECK(readAt<uint8_t>(bytes, offset) == 255);
    }
    const int32_t expected_faces[4][3] = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {6, 5, 7}};
    for (const auto& face : expected_faces) {
        CHECK(readAt<uint8_t>(bytes, offset) == 3);
        for (int k = 0; k < 3; ++k) CHECK(readAt<int32_t>(bytes, offset) == face[k]);
    }
    CHECK(offset == bytes.size());
}
