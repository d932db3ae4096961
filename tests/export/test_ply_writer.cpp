// The PLY writer: exact header text, and the binary body decoded back to the same floats
// and indices (meshes merged, later meshes' indices offset by the earlier vertex counts).
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <string>

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
