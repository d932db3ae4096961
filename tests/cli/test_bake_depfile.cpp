// radbake bake in a content build: a depfile naming every input (an Inline'd file, an MTL,
// the probes), provenance that changes when only an Inline'd file does, and outputs that keep
// their time when a re-bake leaves their bytes alone.
#include <doctest/doctest.h>

#include <chrono>
#include <string>

#include "cli_support.h"
#include "core/exr_io.h"

using namespace clitest;

namespace {

// A floor lit by an emitter defined in an Inline'd file.
void writeInlinedScene(const fs::path& dir, float emission) {
    writeText(dir / "top.wrl", "#VRML V2.0 utf8\n"
                               "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
                               "  geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 0 0 1, 1 0 1, 1 0 0] }\n"
                               "    coordIndex [0 1 2 3 -1] } }\n"
                               "Inline { url \"lamp part.wrl\" }\n");
    writeText(dir / "lamp part.wrl",
              "#VRML V2.0 utf8\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor " +
                  std::to_string(emission) + " " + std::to_string(emission) + " " + std::to_string(emission) +
                  " } }\n"
                  "  geometry IndexedFaceSet { coord Coordinate { point [0 1 0, 1 1 0, 1 1 1, 0 1 1] }\n"
                  "    coordIndex [0 1 2 3 -1] } }\n");
}

std::string attribute(const radbake::RgbImage& image, const std::string& name) {
    for (const auto& [key, value] : image.attributes)
        if (key == name) return value;
    return "";
}

}  // namespace

TEST_CASE("--depfile names every output and every input read: the scene, its Inline, the probes") {
    const TempDir tmp;
    writeInlinedScene(tmp.path, 1.0f);
    writeText(tmp.path / "probes.txt", "0.5 0.01 0.5 0 1 0\n");
    const fs::path out = tmp.path / "out";
    const fs::path dep = tmp.path / "bake.d";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "top.wrl") + " -o " + quote(out) + " --depfile " +
                                     quote(dep) + " --probes " + quote(tmp.path / "probes.txt") +
                                     " --quality draft -q");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const std::string text = readBytes(dep);
    const std::string targets = text.substr(0, text.find(": "));
    CHECK(targets.find((out / "top.glb").string()) == 0);
    CHECK(targets.find((out / "lightmaps" / "top_0.exr").string()) != std::string::npos);
    CHECK(targets.find((out / "manifest.json").string()) != std::string::npos);
    const std::string inputs = text.substr(text.find(": "));
    CHECK(inputs.find((tmp.path / "top.wrl").string()) != std::string::npos);
    CHECK(inputs.find((tmp.path / "lamp\\ part.wrl").string()) != std::string::npos);  // space escaped
    CHECK(inputs.find((tmp.path / "probes.txt").string()) != std::string::npos);
    CHECK(text.back() == '\n');
}

TEST_CASE("--sky FILE.exr: the depfile names the environment map, the provenance its name and bytes") {
    const TempDir tmp;
    writeInlinedScene(tmp.path, 0.0f);
    radbake::RgbImage sky;
    sky.width = 8, sky.height = 4;
    sky.rgb.assign(8 * 4 * 3, 0.5f);
    radbake::Diagnostics diagnostics;
    REQUIRE(radbake::writeExr(tmp.path / "sky map.exr", sky, {}, diagnostics));
    const fs::path out = tmp.path / "out", dep = tmp.path / "bake.d";
    const std::string bake = "bake " + quote(tmp.path / "top.wrl") + " -o " + quote(out) + " --depfile " + quote(dep) +
                             " --sky " + quote(tmp.path / "sky map.exr") + " --quality draft -q";
    RunResult run = runRadbake(bake);
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const std::string text = readBytes(dep);
    CHECK(text.substr(text.find(": ")).find((tmp.path / "sky\\ map.exr").string()) != std::string::npos);
    std::optional<radbake::RgbImage> lightmap = radbake::readExr(out / "lightmaps" / "top_0.exr", diagnostics);
    REQUIRE(lightmap);
    CHECK(attribute(*lightmap, "radbake:daylight").find("sky=sky map.exr ") == 0);
    CHECK(attribute(*lightmap, "radbake:inputs") == "3");
    const std::string inputs = attribute(*lightmap, "radbake:inputs_sha256");
    // Another sky, the same name: the provenance changes, and the light doubles with the sky.
    const auto total = [](const radbake::RgbImage& image) {
        double sum = 0.0;
        for (const float v : image.rgb) sum += v;
        return sum;
    };
    const double before = total(*lightmap);
    REQUIRE(before > 0.0);
    sky.rgb.assign(8 * 4 * 3, 1.0f);
    REQUIRE(radbake::writeExr(tmp.path / "sky map.exr", sky, {}, diagnostics));
    run = runRadbake(bake);
    REQUIRE(run.exit_code == 0);
    lightmap = radbake::readExr(out / "lightmaps" / "top_0.exr", diagnostics);
    REQUIRE(lightmap);
    CHECK(attribute(*lightmap, "radbake:inputs_sha256") != inputs);
    CHECK(attribute(*lightmap, "radbake:daylight").find("sky=sky map.exr ") == 0);
    CHECK(total(*lightmap) == doctest::Approx(2.0 * before).epsilon(0.01));
    // Not an EXR: refused before anything is read.
    run = runRadbake("bake " + quote(tmp.path / "top.wrl") + " -o " + quote(tmp.path / "other") + " --sky sky.png -q");
    CHECK(run.exit_code != 0);
    CHECK(run.output.find("sky.png") != std::string::npos);
    CHECK(!fs::exists(tmp.path / "other"));
}

TEST_CASE("--depfile names an OBJ's MTL file") {
    const TempDir tmp;
    writeText(tmp.path / "lamp.mtl", "newmtl light\nKd 0 0 0\nKe 1 1 1\nnewmtl grey\nKd 0.5 0.5 0.5\n");
    writeText(tmp.path / "lamp.obj", "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
                                     "v 0 1 0\nv 0 1 1\nv 1 1 1\nv 1 1 0\n"
                                     "usemtl grey\nf 1 4 3 2\nusemtl light\nf 5 8 7 6\n");
    const fs::path dep = tmp.path / "bake.d";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "lamp.obj") + " -o " + quote(tmp.path / "out") +
                                     " --depfile " + quote(dep) + " --quality draft --no-lightmaps -q");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    CHECK(readBytes(dep).find((tmp.path / "lamp.mtl").string()) != std::string::npos);
}

TEST_CASE("provenance covers an Inline'd file; an unchanged re-bake rewrites no output but its timings") {
    const TempDir tmp;
    const fs::path out = tmp.path / "out";
    const std::string bake =
        "bake " + quote(tmp.path / "top.wrl") + " -o " + quote(out) + " --quality draft --threads 1 -q";
    const auto provenance = [&] {
        radbake::Diagnostics diagnostics;
        const std::optional<radbake::RgbImage> atlas = radbake::readExr(out / "lightmaps" / "top_0.exr", diagnostics);
        REQUIRE(atlas);
        return std::make_pair(attribute(*atlas, "radbake:scene_sha256"), attribute(*atlas, "radbake:inputs_sha256"));
    };
    writeInlinedScene(tmp.path, 1.0f);
    REQUIRE(runRadbake(bake).exit_code == 0);
    const auto first = provenance();
    CHECK(first.second.size() == 64);

    // Unchanged inputs: the glb keeps its old time.
    const auto old_time = fs::file_time_type::clock::now() - std::chrono::hours(24);
    fs::last_write_time(out / "top.glb", old_time);
    const RunResult again = runRadbake(bake);
    REQUIRE(again.exit_code == 0);
    CHECK(fs::last_write_time(out / "top.glb") == old_time);
    CHECK(again.output.find("files changed") != std::string::npos);

    // Only the Inline'd file changes: the scene file's hash stays, the inputs' hash moves.
    writeInlinedScene(tmp.path, 2.0f);
    REQUIRE(runRadbake(bake).exit_code == 0);
    const auto second = provenance();
    CHECK(second.first == first.first);
    CHECK(second.second != first.second);
    CHECK(fs::last_write_time(out / "top.glb") != old_time);
}
