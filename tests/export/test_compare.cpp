// Golden-file comparison: identical copies pass, a one-texel / one-vertex / one-probe change
// is found and named, a moved vertex, a turned normal or a shifted UV fails, values within
// tolerance pass, and layouts that differ give 2.
#include <doctest/doctest.h>

#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "export/compare.h"
#include "core/exr_io.h"
#include "export/gltf_writer.h"
#include "export/ply_writer.h"
#include "export/probes.h"
#include "temp_files.h"

using namespace radbake;
namespace fs = std::filesystem;
using testfs::readBytes;
using testfs::TempDir;

namespace {

Scene twoMeshScene() {
    Scene scene;
    scene.name = "room";
    scene.materials.resize(1);
    Mesh a;
    a.name = "a";
    a.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    a.triangles = {{0, 1, 2}};
    a.triangle_polygon = {0};
    a.polygon_count = 1;
    Mesh b;
    b.name = "b";
    b.positions = {{0, 0, 1}, {0, 0, 2}, {0, 3, 1}, {0, 3, 2}};
    b.triangles = {{0, 1, 2}, {2, 1, 3}};
    b.triangle_polygon = {0, 0};
    b.polygon_count = 1;
    scene.meshes = {a, b};
    return scene;
}

struct BakeFiles {
    Scene scene = twoMeshScene();
    VertexBake bake;
    std::vector<Probe> probes;
    std::vector<DVec3> irradiance;
    RgbImage image;
    LightmapFiles lightmaps;
    bool with_lightmaps = false;

    BakeFiles() {
        // Mesh a in one chart on atlas 1; mesh b's two triangles in charts on atlases 0 and 1.
        lightmaps.atlas_files = {"lightmaps/room_0.exr", "lightmaps/room_1.exr"};
        const auto chart = [](LightmapMesh& out, const Mesh& mesh, uint32_t t, int atlas, Vec2 uv0) {
            const uint32_t base = static_cast<uint32_t>(out.positions.size());
            for (int k = 0; k < 3; ++k) {
                out.positions.push_back(mesh.positions[mesh.triangles[t][k]]);
                out.uv.push_back(uv0 + Vec2(k == 1 ? 0.25f : 0.0f, k == 2 ? 0.25f : 0.0f));
                out.atlas.push_back(atlas);
                out.source_corners.push_back(mesh.triangles[t]);
                Vec3 w(0.0f);
                w[k] = 1.0f;
                out.barycentric.push_back(w);
            }
            out.triangles.push_back({base, base + 1, base + 2});
            out.source_triangle.push_back(t);
        };
        lightmaps.meshes.resize(2);
        chart(lightmaps.meshes[0], scene.meshes[0], 0, 1, {0.5f, 0.5f});
        chart(lightmaps.meshes[1], scene.meshes[1], 0, 0, {0.0f, 0.0f});
        chart(lightmaps.meshes[1], scene.meshes[1], 1, 1, {0.0f, 0.5f});
        bake.values = {{{0.1f, 0.2f, 0.3f}, {1.0f, 2.0f, 3.0f}, {0.0f, 0.5f, 0.25f}},
                       {{4.0f, 4.5f, 5.0f}, {0.7f, 0.8f, 0.9f}, {1.5f, 1.25f, 1.125f}, {2.0f, 0.0f, 0.0f}}};
        probes = {Probe{{0, 0, 0}, {0, 0, 1}, {}}, Probe{{1, 2, 3}, {0, 1, 0}, {}}};
        irradiance = {{1.0, 2.0, 3.0}, {10.0, 20.0, 30.0}};
        image.width = 6;
        image.height = 4;
        for (int i = 0; i < 6 * 4 * 3; ++i) image.rgb.push_back(0.25f * static_cast<float>(i % 7));
    }

    void write(const fs::path& dir) const {
        Diagnostics diagnostics;
        fs::create_directories(dir / "lightmaps");
        GltfOptions glb_options;
        PlyOptions ply_options;
        if (with_lightmaps) {
            glb_options.lightmaps = &lightmaps;
            ply_options.lightmaps = &lightmaps;
        }
        REQUIRE(writeGlb(dir / "room.glb", scene, bake, glb_options, diagnostics));
        REQUIRE(writePly(dir / "room.ply", scene, bake, ply_options, diagnostics));
        REQUIRE(writeProbesCsv(dir / "probes.csv", probes, irradiance, diagnostics));
        REQUIRE(writeExr(dir / "lightmaps" / "room_0.exr", image, ExrWriteOptions{}, diagnostics));
        std::ofstream(dir / "stats.json") << "{\"ignored\": true}\n";
    }
};

const FileDifference& fileNamed(const CompareResult& result, const std::string& name) {
    for (const FileDifference& file : result.files)
        if (file.file == name) return file;
    FAIL("no result for " << name);
    return result.files.front();
}

std::string channelNames(const FileDifference& file) {
    std::string names;
    for (const ChannelDifference& channel : file.channels) names += (names.empty() ? "" : " ") + channel.name;
    return names;
}

// The channel named `name`, which must be there.
const ChannelDifference& channelNamed(const FileDifference& file, const std::string& name) {
    for (const ChannelDifference& channel : file.channels)
        if (channel.name == name) return channel;
    FAIL("no channel " << name << " in " << file.file);
    return file.channels.front();
}

// The channel whose worst place fails, or nullptr.
const ChannelDifference* failingChannel(const FileDifference& file) {
    for (const ChannelDifference& channel : file.channels)
        if (channel.worst_excess > 1.0) return &channel;
    return nullptr;
}

}  // namespace

TEST_CASE("identical bake directories compare equal, file by file") {
    TempDir tmp;
    BakeFiles files;
    files.write(tmp.path / "a");
    files.write(tmp.path / "b");
    const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
    CHECK(result.exitCode() == 0);
    CHECK(result.problems.empty());
    REQUIRE(result.files.size() == 4);  // stats.json is not compared
    CHECK(result.files[0].file == "lightmaps/room_0.exr");
    CHECK(result.files[0].samples == 24);
    CHECK(fileNamed(result, "room.glb").samples == 7);
    CHECK(fileNamed(result, "room.ply").samples == 7);
    CHECK(fileNamed(result, "probes.csv").samples == 2);
    for (const FileDifference& file : result.files) {
        CHECK(file.comparable);
        // Light, plus x y z nx ny nz for the meshes (no lightmaps here: no UVs).
        CHECK(file.channels.size() == (file.kind == "glb" || file.kind == "ply" ? 9u : 3u));
        for (const ChannelDifference& channel : file.channels) CHECK(channel.max_abs == 0.0);
    }
    CHECK(channelNames(fileNamed(result, "room.glb")) == "R G B x y z nx ny nz");
    CHECK(channelNames(fileNamed(result, "room.ply")) == "red green blue x y z nx ny nz");
}

TEST_CASE("a one-texel change is found and named") {
    TempDir tmp;
    BakeFiles files;
    files.write(tmp.path / "a");
    files.image.rgb[(2 * 6 + 3) * 3 + 1] += 0.5f;  // texel x=3, y=2, green
    files.write(tmp.path / "b");
    const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
    CHECK(result.exitCode() == 1);
    const FileDifference& exr = fileNamed(result, "lightmaps/room_0.exr");
    CHECK_FALSE(exr.within);
    const ChannelDifference* channel = failingChannel(exr);
    REQUIRE(channel);
    CHECK(channel->name == "G");
    CHECK(channel->worst_place == "texel (3, 2)");
    CHECK(channel->max_abs == doctest::Approx(0.5));
    CHECK(channel->rmse == doctest::Approx(0.5 / std::sqrt(24.0)));
    CHECK(exr.channels[0].max_abs == 0.0);
    CHECK(fileNamed(result, "room.glb").within);
    CHECK(formatCompareResult(result).find("DIFFERS lightmaps/room_0.exr: texel (3, 2) G") != std::string::npos);
}

TEST_CASE("a one-vertex change is found in the glb and the ply, a probe change in probes.csv") {
    TempDir tmp;
    BakeFiles files;
    files.write(tmp.path / "a");
    files.bake.values[1][2].z = 1.2f;  // mesh b, vertex 2, blue: 1.125 -> 1.2
    files.irradiance[1].x = 10.5;
    files.write(tmp.path / "b");
    const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
    CHECK(result.exitCode() == 1);

    const ChannelDifference* glb = failingChannel(fileNamed(result, "room.glb"));
    REQUIRE(glb);
    CHECK(glb->name == "B");
    CHECK(glb->worst_place == "mesh 'b' vertex 2");
    CHECK(glb->worst_a == 1.125);
    CHECK(glb->worst_b == doctest::Approx(1.2));
    CHECK(glb->max_rel == doctest::Approx(0.075 / 1.2));

    const ChannelDifference* ply = failingChannel(fileNamed(result, "room.ply"));
    REQUIRE(ply);
    CHECK(ply->name == "blue");
    CHECK(ply->worst_place == "vertex 5");  // merged: mesh a has 3 vertices

    const ChannelDifference* csv = failingChannel(fileNamed(result, "probes.csv"));
    REQUIRE(csv);
    CHECK(csv->name == "r");
    CHECK(csv->worst_place == "probe 1");
    CHECK(csv->max_abs == doctest::Approx(0.5));
    CHECK(fileNamed(result, "lightmaps/room_0.exr").within);
}

TEST_CASE("differences within either tolerance pass; a NaN on one side never does") {
    TempDir tmp;
    BakeFiles files;
    files.write(tmp.path / "a");
    files.bake.values[0][1].x *= 1.0f + 2e-4f;  // relative 2e-4 < 1e-3
    files.bake.values[0][2].x = 5e-7f;           // absolute 5e-7 < 1e-6 (relative 1)
    files.write(tmp.path / "b");
    const CompareResult close = comparePaths(tmp.path / "a" / "room.glb", tmp.path / "b" / "room.glb", CompareOptions{});
    CHECK(close.exitCode() == 0);
    REQUIRE(close.files.size() == 1);
    CHECK(close.files[0].channels[0].max_rel == doctest::Approx(1.0));
    CHECK(close.files[0].channels[0].max_abs == doctest::Approx(2e-4).epsilon(0.01));

    CompareOptions strict;
    strict.rel_tol = 1e-4;
    const CompareResult tight = comparePaths(tmp.path / "a" / "room.glb", tmp.path / "b" / "room.glb", strict);
    CHECK(tight.exitCode() == 1);
    CHECK(failingChannel(tight.files[0])->worst_place == "mesh 'a' vertex 1");

    files.irradiance[0].y = std::numeric_limits<double>::quiet_NaN();
    files.write(tmp.path / "c");
    const CompareResult nan = comparePaths(tmp.path / "a" / "probes.csv", tmp.path / "c" / "probes.csv", CompareOptions{});
    CHECK(nan.exitCode() == 1);
    CHECK(failingChannel(nan.files[0])->worst_place == "probe 0");
}

TEST_CASE("different layouts, missing or extra files and mismatched kinds are not comparable") {
    TempDir tmp;
    BakeFiles files;
    files.write(tmp.path / "a");

    SUBCASE("image size") {
        files.image.width = 4;
        files.image.rgb.resize(4 * 4 * 3);
        files.write(tmp.path / "b");
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 2);
        CHECK_FALSE(fileNamed(result, "lightmaps/room_0.exr").comparable);
        CHECK(fileNamed(result, "lightmaps/room_0.exr").problem == "different layouts (6x4 image vs 4x4 image)");
    }
    SUBCASE("vertex count") {
        files.scene.meshes[1].positions.push_back({1, 1, 1});
        files.bake.values[1].push_back({0, 0, 0});
        files.write(tmp.path / "b");
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 2);
        CHECK_FALSE(fileNamed(result, "room.glb").comparable);
        CHECK_FALSE(fileNamed(result, "room.ply").comparable);
        CHECK(fileNamed(result, "room.ply").problem ==
              "different layouts (7 vertices: x y z nx ny nz vs 8 vertices: x y z nx ny nz)");
    }
    SUBCASE("probe positions") {
        files.probes[1].position.z = 3.5;
        files.write(tmp.path / "b");
        CHECK(comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{}).exitCode() == 2);
    }
    SUBCASE("a file missing from B, or only in B") {
        files.write(tmp.path / "b");
        fs::remove(tmp.path / "b" / "room.ply");
        const CompareResult missing = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(missing.exitCode() == 2);
        REQUIRE(missing.problems.size() == 1);
        CHECK(missing.problems[0] == "room.ply is missing from " + (tmp.path / "b").string());
        const CompareResult extra = comparePaths(tmp.path / "b", tmp.path / "a", CompareOptions{});
        CHECK(extra.exitCode() == 2);
        REQUIRE(extra.problems.size() == 1);
        CHECK(extra.problems[0] == "room.ply is only in " + (tmp.path / "a").string());
    }
    SUBCASE("kinds, a directory with a file, nothing there, garbage") {
        CHECK(comparePaths(tmp.path / "a" / "room.glb", tmp.path / "a" / "room.ply", CompareOptions{}).exitCode() == 2);
        CHECK(comparePaths(tmp.path / "a", tmp.path / "a" / "room.ply", CompareOptions{}).exitCode() == 2);
        const CompareResult none = comparePaths(tmp.path / "a", tmp.path / "nothing", CompareOptions{});
        CHECK(none.exitCode() == 2);
        REQUIRE(none.problems.size() == 1);
        CHECK(none.problems[0] == (tmp.path / "nothing").string() + " does not exist");
        fs::create_directories(tmp.path / "g");
        std::ofstream(tmp.path / "g" / "room.glb") << "glTF garbage";
        const CompareResult garbage = comparePaths(tmp.path / "a" / "room.glb", tmp.path / "g" / "room.glb", CompareOptions{});
        CHECK(garbage.exitCode() == 2);
        REQUIRE(garbage.files.size() == 1);
        CHECK(garbage.files[0].problem.find((tmp.path / "g" / "room.glb").string()) == 0);
    }
}

TEST_CASE("lightmap layouts: glb primitives per atlas and their files must match; lightmap UVs are compared") {
    TempDir tmp;
    BakeFiles files;
    files.with_lightmaps = true;
    files.write(tmp.path / "a");

    SUBCASE("identical copies pass, per primitive") {
        files.write(tmp.path / "b");
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 0);
        CHECK(fileNamed(result, "room.glb").samples == 9);  // 3 + 3 + 3 lightmap vertices
        CHECK(fileNamed(result, "room.ply").samples == 9);
    }
    SUBCASE("a COLOR_0 change is named by mesh and primitive") {
        files.bake.values[1][3].y = 0.5f;  // mesh b vertex 3: only in triangle 1, atlas 1, primitive 1
        files.write(tmp.path / "b");
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 1);
        const ChannelDifference* glb = failingChannel(fileNamed(result, "room.glb"));
        REQUIRE(glb);
        CHECK(glb->name == "G");
        CHECK(glb->worst_place == "mesh 'b' primitive 1 vertex 2");
        CHECK(glb->worst_a == 0.0);
        CHECK(glb->worst_b == 0.5);
        const ChannelDifference* ply = failingChannel(fileNamed(result, "room.ply"));
        REQUIRE(ply);
        CHECK(ply->worst_place == "vertex 8");
    }
    SUBCASE("a shifted lightmap UV differs, named by its vertex, in TEXCOORD_0, TEXCOORD_1 and u1") {
        files.lightmaps.meshes[1].uv[4].x = 0.3f;  // mesh b, chart on atlas 1, its second vertex
        files.write(tmp.path / "b");
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 1);
        const FileDifference& glb = fileNamed(result, "room.glb");
        CHECK(glb.comparable);
        CHECK(channelNames(glb) == "R G B x y z nx ny nz u0 v0 u1 v1");
        for (const char* name : {"u0", "u1"}) {
            const ChannelDifference& u = channelNamed(glb, name);
            CHECK(u.worst_excess > 1.0);
            CHECK(u.worst_place == "mesh 'b' primitive 1 vertex 1");
            CHECK(u.worst_a == 0.25);
            CHECK(u.worst_b == doctest::Approx(0.3));
        }
        CHECK(channelNamed(glb, "v1").max_abs == 0.0);
        CHECK(channelNamed(glb, "G").max_abs == 0.0);
        const ChannelDifference& ply_u = channelNamed(fileNamed(result, "room.ply"), "u1");
        CHECK(ply_u.worst_excess > 1.0);
        CHECK(ply_u.worst_place == "vertex 7");
        CHECK(fileNamed(result, "lightmaps/room_0.exr").within);
        CHECK(formatCompareResult(result).find("DIFFERS room.ply: vertex 7 u1 is 0.25 vs 0.300000012") !=
              std::string::npos);
    }
    SUBCASE("a UV moved by less than uv_tol passes") {
        files.lightmaps.meshes[1].uv[4].x = std::nextafter(0.25f, 1.0f);  // 3e-8 further
        files.write(tmp.path / "b");
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 0);
        CHECK(channelNamed(fileNamed(result, "room.glb"), "u1").max_abs > 0.0);
        CompareOptions exact;
        exact.uv_tol = 0.0;
        CHECK(comparePaths(tmp.path / "a", tmp.path / "b", exact).exitCode() == 1);
    }
    SUBCASE("a different atlas, or lightmaps on one side only, are not comparable") {
        files.lightmaps.atlas_files[1] = "lightmaps/room_9.exr";
        files.write(tmp.path / "b");
        CompareResult result = comparePaths(tmp.path / "a" / "room.glb", tmp.path / "b" / "room.glb", CompareOptions{});
        CHECK(result.exitCode() == 2);
        CHECK(result.files[0].problem ==
              "different layouts (mesh 'a': 3 vertices: POSITION NORMAL TEXCOORD_0 TEXCOORD_1, lightmap "
              "lightmaps/room_1.exr vs mesh 'a': 3 vertices: POSITION NORMAL TEXCOORD_0 TEXCOORD_1, lightmap "
              "lightmaps/room_9.exr)");

        files.with_lightmaps = false;
        files.write(tmp.path / "c");
        result = comparePaths(tmp.path / "a" / "room.ply", tmp.path / "c" / "room.ply", CompareOptions{});
        CHECK(result.exitCode() == 2);
        CHECK(result.files[0].problem ==
              "different layouts (9 vertices: x y z nx ny nz u1 v1 lightmap vs 7 vertices: x y z nx ny nz)");
    }
    SUBCASE("the lightmap index of a PLY vertex must match") {
        files.write(tmp.path / "b");
        // Flip the atlas byte of vertex 0 (the last byte of the first 45-byte vertex record).
        std::fstream ply(tmp.path / "b" / "room.ply", std::ios::in | std::ios::out | std::ios::binary);
        std::string text((std::istreambuf_iterator<char>(ply)), std::istreambuf_iterator<char>());
        const size_t body = text.find("end_header\n") + 11;
        REQUIRE(text[body + 44] == 1);
        ply.seekp(static_cast<std::streamoff>(body + 44));
        ply.put(0);
        ply.close();
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 2);
        CHECK(fileNamed(result, "room.ply").problem == "lightmap differs at vertex 0: 1 vs 0 (must match exactly)");
    }
}

TEST_CASE("compare recurses into lightmaps/ and ignores manifest.json and PNG previews") {
    TempDir tmp;
    BakeFiles files;
    files.write(tmp.path / "a");
    files.write(tmp.path / "b");
    Diagnostics diagnostics;
    RgbImage second = files.image;
    REQUIRE(writeExr(tmp.path / "a" / "lightmaps" / "room_1.exr", second, ExrWriteOptions{}, diagnostics));
    second.rgb[5] += 1.0f;  // texel (1, 0), blue
    REQUIRE(writeExr(tmp.path / "b" / "lightmaps" / "room_1.exr", second, ExrWriteOptions{}, diagnostics));
    std::ofstream(tmp.path / "a" / "manifest.json") << "{\"files\": []}\n";
    std::ofstream(tmp.path / "b" / "manifest.json") << "{\"files\": [\"different\"]}\n";
    std::ofstream(tmp.path / "a" / "lightmaps" / "room_0.png") << "only in a";
    std::ofstream(tmp.path / "b" / "preview.png") << "only in b";

    const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
    CHECK(result.problems.empty());
    REQUIRE(result.files.size() == 5);
    CHECK(result.files[0].file == "lightmaps/room_0.exr");
    CHECK(result.files[1].file == "lightmaps/room_1.exr");
    CHECK(result.exitCode() == 1);
    const ChannelDifference* channel = failingChannel(fileNamed(result, "lightmaps/room_1.exr"));
    REQUIRE(channel);
    CHECK(channel->worst_place == "texel (1, 0)");
    CHECK(fileNamed(result, "lightmaps/room_0.exr").within);

    fs::remove(tmp.path / "b" / "lightmaps" / "room_1.exr");  // fewer atlases in B
    const CompareResult fewer = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
    CHECK(fewer.exitCode() == 2);
    REQUIRE(fewer.problems.size() == 1);
    CHECK(fewer.problems[0] == "lightmaps/room_1.exr is missing from " + (tmp.path / "b").string());
}

TEST_CASE("geometry: a moved vertex or a turned normal fails, named by its vertex, with the vertex count kept") {
    TempDir tmp;
    BakeFiles files;
    files.scene.meshes[0].normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};  // given normals: not from the positions
    files.write(tmp.path / "a");

    SUBCASE("identical geometry passes") {
        files.write(tmp.path / "b");
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 0);
        for (const char* name : {"room.glb", "room.ply"})
            for (const char* channel : {"x", "y", "z", "nx", "ny", "nz"})
                CHECK(channelNamed(fileNamed(result, name), channel).max_abs == 0.0);
    }
    SUBCASE("a vertex moved by 1 mm fails; one float rounding passes") {
        files.scene.meshes[1].positions[2].y += 0.001f;  // mesh b vertex 2: (0, 3, 1), extent sqrt(14) ~ 3.7
        files.write(tmp.path / "b");
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 1);
        const FileDifference& glb = fileNamed(result, "room.glb");
        const ChannelDifference* moved = failingChannel(glb);
        REQUIRE(moved);
        CHECK(moved->name == "y");
        CHECK(moved->worst_place == "mesh 'b' vertex 2");
        CHECK(moved->worst_a == 3.0);
        CHECK(moved->worst_b == doctest::Approx(3.001));
        CHECK(channelNamed(glb, "B").max_abs == 0.0);  // the light is the same
        const ChannelDifference& ply = channelNamed(fileNamed(result, "room.ply"), "y");
        CHECK(ply.worst_excess > 1.0);
        CHECK(ply.worst_place == "vertex 5");
        CHECK(formatCompareResult(result).find("DIFFERS room.glb: mesh 'b' vertex 2 y is 3 vs 3.00099993") !=
              std::string::npos);

        files.scene.meshes[1].positions[2].y = std::nextafter(3.0f, 4.0f);  // 2.4e-7 < 1e-6 * 3.7
        files.write(tmp.path / "c");
        const CompareResult rounded = comparePaths(tmp.path / "a", tmp.path / "c", CompareOptions{});
        CHECK(rounded.exitCode() == 0);
        CHECK(channelNamed(fileNamed(rounded, "room.glb"), "y").max_abs > 0.0);
    }
    SUBCASE("a turned normal fails") {
        files.scene.meshes[0].normals[1] = glm::normalize(Vec3(0.0f, 0.01f, 1.0f));  // 0.57 degrees
        files.write(tmp.path / "b");
        const CompareResult result = comparePaths(tmp.path / "a", tmp.path / "b", CompareOptions{});
        CHECK(result.exitCode() == 1);
        const ChannelDifference* turned = failingChannel(fileNamed(result, "room.glb"));
        REQUIRE(turned);
        CHECK(turned->name == "ny");
        CHECK(turned->worst_place == "mesh 'a' vertex 1");
        CHECK(channelNamed(fileNamed(result, "room.glb"), "y").max_abs == 0.0);
        const ChannelDifference* ply = failingChannel(fileNamed(result, "room.ply"));
        REQUIRE(ply);
        CHECK(ply->name == "ny");
        CHECK(ply->worst_place == "vertex 1");
    }
}
