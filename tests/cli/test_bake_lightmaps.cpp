// `radbake bake` lightmap outputs end to end: EXR atlases with their provenance, TEXCOORD_1 in
// the glb, manifest.json that matches the files, stale lightmaps retired, previews.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string>

#include "cli_support.h"
#include "core/exr_io.h"
#include "export/hash.h"
#include "export/lightmap_png.h"
#include "scene/texture_image.h"

using namespace clitest;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A unit square lamp (L_e = 2) facing down at height 1 over a black 4 x 4 floor.
void writeLampScene(const fs::path& dir) {
    writeText(dir / "lamp.mtl", "newmtl light\nKd 0 0 0\nKe 2 2 2\nnewmtl floor\nKd 0 0 0\n");
    writeText(dir / "lamp.obj",
              "mtllib lamp.mtl\n"
              "v -0.5 1 -0.5\nv 0.5 1 -0.5\nv 0.5 1 0.5\nv -0.5 1 0.5\n"
              "v -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\n"
              "o lamp\nusemtl light\nf 1 2 3 4\n"
              "o floor\nusemtl floor\nf 5 6 7 8\n");
}

// Every file under `dir`, as paths relative to it with forward slashes.
std::set<std::string> filesUnder(const fs::path& dir) {
    std::set<std::string> names;
    if (!fs::exists(dir)) return names;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        if (entry.is_regular_file()) names.insert(fs::relative(entry.path(), dir).generic_string());
    return names;
}

// The JSON chunk of a .glb (header 12 bytes, then the chunk's length and type).
std::string glbJson(const fs::path& path) {
    const std::string bytes = readBytes(path);
    REQUIRE(bytes.size() > 20);
    uint32_t length = 0;
    std::copy_n(bytes.data() + 12, 4, reinterpret_cast<char*>(&length));
    return bytes.substr(20, length);
}

std::string attribute(const radbake::RgbImage& image, const std::string& name) {
    for (const auto& [key, value] : image.attributes)
        if (key == name) return value;
    return "";
}

}  // namespace

TEST_CASE("bake writes EXR lightmaps with provenance, TEXCOORD_1, and a manifest of every file") {
    TempDir tmp;
    writeLampScene(tmp.path);
    const fs::path out = tmp.path / "out";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "lamp.obj") + " -o " + quote(out) + " -q");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    CHECK(run.output.find("1 lightmap (") != std::string::npos);

    radbake::Diagnostics diagnostics;
    const std::optional<radbake::RgbImage> atlas = radbake::readExr(out / "lightmaps" / "lamp_0.exr", diagnostics);
    REQUIRE(atlas);
    CHECK(atlas->half);
    CHECK(attribute(*atlas, "radbake:scene") == "lamp.obj");
    CHECK(attribute(*atlas, "radbake:scene_sha256") == radbake::sha256File(tmp.path / "lamp.obj", diagnostics).value());
    CHECK(attribute(*atlas, "radbake:version").find("radbake ") == 0);
    CHECK(attribute(*atlas, "radbake:options").find("quality=medium visibility=aabb") == 0);
    CHECK(attribute(*atlas, "radbake:options").find("texel_density=16 atlas_size=1024 padding=2 texel_tolerance=0.02") !=
          std::string::npos);
    CHECK(attribute(*atlas, "radbake:atlas") == "0 of 1");

    // The brightest floor texel is near the centre below the lamp: H/pi there from the closed
    // form (4 corner rectangles of 0.5 x 0.5 at height 1), within a texel's offset and 1 %.
    const double centre = 4 * 2.0 * 0.5 * 2 * (0.5 / std::sqrt(1.25) * std::atan(0.5 / std::sqrt(1.25))) / kPi;
    const float brightest = *std::max_element(atlas->rgb.begin(), atlas->rgb.end());
    CHECK(brightest <= centre * 1.01);
    CHECK(brightest >= centre * 0.97);

    const std::string json = glbJson(out / "lamp.glb");
    CHECK(json.find("\"TEXCOORD_1\"") != std::string::npos);
    CHECK(json.find("lightmaps/lamp_0.exr") != std::string::npos);

    const std::set<std::string> files = filesUnder(out);
    CHECK(files == std::set<std::string>{"lamp.glb", "lamp.ply", "stats.json", "timings.json", "manifest.json",
                                         "lightmaps/lamp_0.exr", "lightmaps/lamp_0.png"});
    const nlohmann::json manifest = nlohmann::json::parse(readBytes(out / "manifest.json"));
    std::set<std::string> listed;
    for (size_t i = 0; i < manifest.at("files").size(); ++i) {
        const nlohmann::json& entry = manifest.at("files").at(i);
        const std::string path = entry.at("path").get<std::string>();
        listed.insert(path);
        CHECK_MESSAGE(entry.at("bytes").get<double>() == static_cast<double>(fs::file_size(out / path)), path);
        CHECK_MESSAGE(entry.at("sha256").get<std::string>() == radbake::sha256File(out / path, diagnostics).value(), path);
    }
    std::set<std::string> expected = files;
    expected.erase("manifest.json");
    expected.erase("timings.json");  // differs from run to run: never listed
    CHECK(listed == expected);

    const nlohmann::json stats = nlohmann::json::parse(readBytes(out / "stats.json"));
    CHECK(stats.at("lightmaps").get<bool>());
    CHECK(stats.at("atlases").get<double>() == 1);
    CHECK(stats.at("occupancy").get<double>() > 0.0);
    CHECK(stats.at("occupancy").get<double>() <= 1.0);
    CHECK(nlohmann::json::parse(readBytes(out / "timings.json")).at("phases").contains("lightmaps"));
    CHECK(stats.at("texel_tolerance").get<double>() == 0.02);  // medium's
    CHECK(stats.at("covered_texels").get<double>() > 0);
    CHECK(stats.at("interpolated_texels").get<double>() <= stats.at("covered_texels").get<double>());
}

TEST_CASE("a re-bake with fewer atlases, then --no-lightmaps, leaves no stale lightmaps") {
    TempDir tmp;
    writeLampScene(tmp.path);
    const fs::path out = tmp.path / "out";
    const std::string scene = "bake " + quote(tmp.path / "lamp.obj") + " -o " + quote(out) + " -q --quality draft";
    // 16-texel atlases hold one 12-texel chart each: the 64-texel floor alone needs many.
    const RunResult small = runRadbake(scene + " --atlas-size 16");
    INFO(small.output);
    REQUIRE(small.exit_code == 0);
    const size_t many = filesUnder(out / "lightmaps").size() / 2;  // an EXR and a PNG per atlas
    CHECK(many > 10);
    CHECK(fs::exists(out / "lightmaps" / ("lamp_" + std::to_string(many - 1) + ".exr")));

    const RunResult one = runRadbake(scene);
    INFO(one.output);
    REQUIRE(one.exit_code == 0);
    CHECK(filesUnder(out / "lightmaps") == std::set<std::string>{"lamp_0.exr", "lamp_0.png"});

    const RunResult none = runRadbake(scene + " --no-lightmaps");
    INFO(none.output);
    REQUIRE(none.exit_code == 0);
    CHECK_FALSE(fs::exists(out / "lightmaps" / "lamp_0.exr"));
    CHECK(filesUnder(out) == std::set<std::string>{"lamp.glb", "lamp.ply", "stats.json", "timings.json", "manifest.json"});
    CHECK(glbJson(out / "lamp.glb").find("TEXCOORD_1") == std::string::npos);
    CHECK_FALSE(nlohmann::json::parse(readBytes(out / "stats.json")).at("lightmaps").get<bool>());
}

TEST_CASE("--exr-float writes 32-bit lightmaps; --preview writes PNGs of the view and of each atlas") {
    TempDir tmp;
    writeLampScene(tmp.path);
    const fs::path out = tmp.path / "out";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "lamp.obj") + " -o " + quote(out) +
                                     " -q --quality draft --exr-float --preview");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    radbake::Diagnostics diagnostics;
    const std::optional<radbake::RgbImage> atlas = radbake::readExr(out / "lightmaps" / "lamp_0.exr", diagnostics);
    REQUIRE(atlas);
    CHECK_FALSE(atlas->half);
    CHECK(nlohmann::json::parse(readBytes(out / "stats.json")).at("texel_tolerance").get<double>() == 0.05);  // draft's
    for (const char* name : {"preview/lamp_view.png", "preview/lamp_atlas_0.png"}) {
        const std::string png = readBytes(out / name);
        REQUIRE_MESSAGE(png.size() > 24, name);
        CHECK_MESSAGE(png.substr(1, 3) == "PNG", name);
        // IHDR: big-endian width and height at bytes 16 and 20.
        const auto be32 = [&](size_t at) {
            return (uint32_t(uint8_t(png[at])) << 24) | (uint32_t(uint8_t(png[at + 1])) << 16) |
                   (uint32_t(uint8_t(png[at + 2])) << 8) | uint32_t(uint8_t(png[at + 3]));
        };
        if (std::string(name) == "preview/lamp_view.png") {
            CHECK(be32(16) == 800);
            CHECK(be32(20) == 600);
        } else {
            CHECK(be32(16) == static_cast<uint32_t>(atlas->width));
            CHECK(be32(20) == static_cast<uint32_t>(atlas->height));
        }
    }
}

TEST_CASE("--max-texels: the default density is lowered to fit, with a warning; a given density over it is an error") {
    TempDir tmp;
    writeLampScene(tmp.path);
    // At 16 texels per metre the 4 x 4 m floor alone has 64 x 64 texels.
    const std::string scene = "bake " + quote(tmp.path / "lamp.obj") + " -q --quality draft --max-texels 1000";
    const RunResult lowered = runRadbake(scene + " -o " + quote(tmp.path / "a"));
    INFO(lowered.output);
    REQUIRE(lowered.exit_code == 0);
    CHECK(lowered.output.find("warning: lightmaps at the default 16 texels per metre would need 4352 texels, above "
                              "--max-texels 1000") != std::string::npos);
    const nlohmann::json stats = nlohmann::json::parse(readBytes(tmp.path / "a" / "stats.json"));
    CHECK(stats.at("texel_density").get<double>() < 16.0 * std::sqrt(1000.0 / 4352.0));
    CHECK(stats.at("texel_density").get<double>() > 0.8 * 16.0 * std::sqrt(1000.0 / 4352.0));
    CHECK(stats.at("covered_texels").get<double>() <= 1000);

    const RunResult refused = runRadbake(scene + " --texel-density 16 -o " + quote(tmp.path / "b"));
    INFO(refused.output);
    CHECK(refused.exit_code == 1);
    CHECK(refused.output.find("error: lightmaps at --texel-density 16 need 4352 texels, above --max-texels 1000: give "
                              "a density of about 7.67 or less") != std::string::npos);
    CHECK_FALSE(fs::exists(tmp.path / "b"));
}

TEST_CASE("the glb embeds each atlas's PNG, the file beside the EXR, and decodes to the EXR within its step") {
    TempDir tmp;
    writeLampScene(tmp.path);
    const fs::path out = tmp.path / "out";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "lamp.obj") + " -o " + quote(out) + " -q --quality draft");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const std::string glb = readBytes(out / "lamp.glb");
    const nlohmann::json json = nlohmann::json::parse(glbJson(out / "lamp.glb"));
    const std::string png = readBytes(out / "lightmaps" / "lamp_0.png");
    REQUIRE(png.size() > 33);
    CHECK(glb.find(png) != std::string::npos);  // embedded byte for byte
    size_t lightmapped = 0;
    for (const nlohmann::json& material : json.at("materials")) {
        if (!material.contains("extensions")) continue;
        const nlohmann::json& extension = material.at("extensions").at("MOZ_lightmap");
        CHECK(extension.at("texCoord").get<int>() == 1);
        CHECK(material.at("extras").at("radbake_lightmap_png").get<std::string>() == "lightmaps/lamp_0.png");
        CHECK(material.at("extras").at("radbake_lightmap_encoding").get<std::string>() == "rgbe8");
        CHECK(extension.at("intensity").get<double>() == doctest::Approx(kPi));
        // The PNG's bytes decode to the EXR's texels: each within half a code of its texel's
        // shared exponent (the EXR holds halves of the same floats).
        radbake::Diagnostics diagnostics;
        const std::optional<radbake::RgbImage> atlas = radbake::readExr(out / "lightmaps" / "lamp_0.exr", diagnostics);
        REQUIRE(atlas);
        radbake::TextureRef ref;
        ref.path = "lamp_0.png";
        ref.embedded = std::make_shared<std::string>(png);
        int width = 0, height = 0;
        std::vector<uint8_t> rgba;
        std::string error;
        REQUIRE(radbake::readImageRgba8(ref, width, height, rgba, error));
        REQUIRE(static_cast<size_t>(width) * static_cast<size_t>(height) * 3 == atlas->rgb.size());
        size_t lit = 0;
        for (size_t t = 0; t < atlas->rgb.size() / 3; ++t) {
            const float* rgb = &atlas->rgb[3 * t];
            const float peak = std::max({rgb[0], rgb[1], rgb[2]});
            lit += peak > 0.0f;
            for (int c = 0; c < 3; ++c)
                CHECK(std::fabs(radbake::decodeRgbe(rgba[4 * t + c], rgba[4 * t + 3]) - rgb[c]) <= peak / 256.0f);
        }
        CHECK(lit > atlas->rgb.size() / 12);
        ++lightmapped;
    }
    CHECK(lightmapped == 2);  // the lamp's and the floor's materials, both on atlas 0
}

TEST_CASE("--export-lights writes KHR_lights_punctual marked as baked; without it the glb has no lights") {
    TempDir tmp;
    writeText(tmp.path / "lit.wrl",
              "#VRML V2.0 utf8\n"
              "PointLight { location 0 1 0 intensity 0.5 }\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
              "  geometry IndexedFaceSet { coord Coordinate { point [-1 0 -1, -1 0 1, 1 0 1, 1 0 -1] }\n"
              "    coordIndex [0 1 2 3 -1] } }\n");
    const std::string bake = "bake " + quote(tmp.path / "lit.wrl") + " -q --quality draft --no-lightmaps";
    const RunResult plain = runRadbake(bake + " -o " + quote(tmp.path / "plain"));
    INFO(plain.output);
    REQUIRE(plain.exit_code == 0);
    CHECK(glbJson(tmp.path / "plain" / "lit.glb").find("KHR_lights_punctual") == std::string::npos);

    const RunResult lit = runRadbake(bake + " --export-lights -o " + quote(tmp.path / "lit"));
    INFO(lit.output);
    REQUIRE(lit.exit_code == 0);
    const nlohmann::json json = nlohmann::json::parse(glbJson(tmp.path / "lit" / "lit.glb"));
    const nlohmann::json& lights = json.at("extensions").at("KHR_lights_punctual").at("lights");
    REQUIRE(lights.size() == 1);
    CHECK(lights.at(0).at("type") == "point");
    CHECK(lights.at(0).at("intensity").get<double>() == doctest::Approx(0.5));
    CHECK(lights.at(0).at("extras").at("radbake_baked").get<bool>());
}

TEST_CASE("--lightmap-scales: the named mesh gets scale^2 times the texels; the file is in the depfile") {
    TempDir tmp;
    writeLampScene(tmp.path);
    writeText(tmp.path / "scales.txt", "floor 0.5  # half the density\n");
    const std::string bake = "bake " + quote(tmp.path / "lamp.obj") + " -q --quality draft --texel-density 16";
    const RunResult even = runRadbake(bake + " -o " + quote(tmp.path / "even"));
    INFO(even.output);
    REQUIRE(even.exit_code == 0);
    const RunResult scaled = runRadbake(bake + " --lightmap-scales " + quote(tmp.path / "scales.txt") + " --depfile " +
                                        quote(tmp.path / "out.d") + " -o " + quote(tmp.path / "scaled"));
    INFO(scaled.output);
    REQUIRE(scaled.exit_code == 0);
    const double even_texels =
        nlohmann::json::parse(readBytes(tmp.path / "even" / "stats.json")).at("covered_texels").get<double>();
    const double scaled_texels =
        nlohmann::json::parse(readBytes(tmp.path / "scaled" / "stats.json")).at("covered_texels").get<double>();
    // The 4 x 4 m floor: 64 x 64 texels, then 32 x 32; the 1 x 1 m lamp keeps its 16 x 16.
    CHECK(even_texels == 64 * 64 + 16 * 16);
    CHECK(scaled_texels == 32 * 32 + 16 * 16);
    CHECK(readBytes(tmp.path / "out.d").find("scales.txt") != std::string::npos);
    // The atlas records the scales that shaped it; a bake without them records none.
    radbake::Diagnostics diagnostics;
    const auto scaled_atlas = radbake::readExr(tmp.path / "scaled" / "lightmaps" / "lamp_0.exr", diagnostics);
    const auto even_atlas = radbake::readExr(tmp.path / "even" / "lightmaps" / "lamp_0.exr", diagnostics);
    REQUIRE(scaled_atlas);
    REQUIRE(even_atlas);
    CHECK(attribute(*scaled_atlas, "radbake:lightmap_scales") == "floor = 0.5");
    CHECK(attribute(*even_atlas, "radbake:lightmap_scales").empty());

    writeText(tmp.path / "typo.txt", "flor 0.5\n");
    const RunResult typo = runRadbake(bake + " --lightmap-scales " + quote(tmp.path / "typo.txt") + " -o " +
                                      quote(tmp.path / "typo"));
    CHECK(typo.exit_code == 0);
    CHECK(typo.output.find("typo.txt:1:1: warning: no mesh takes the lightmap scale of 'flor'") != std::string::npos);
    writeText(tmp.path / "bad.txt", "floor -2\n");
    const RunResult bad = runRadbake(bake + " --lightmap-scales " + quote(tmp.path / "bad.txt") + " -o " +
                                     quote(tmp.path / "bad"));
    CHECK(bad.exit_code == 1);
    CHECK(bad.output.find("bad.txt:1:7: error:") != std::string::npos);
    CHECK_FALSE(fs::exists(tmp.path / "bad"));
}

TEST_CASE("--realtime-lights writes each atlas's shadowmask beside it, named in the glb with its lights' channels") {
    TempDir tmp;
    writeText(tmp.path / "lit.wrl",
              "#VRML V2.0 utf8\n"
              "DEF Lamp PointLight { location 0 1 0 }\n"
              "DEF Fill PointLight { location 0.5 1 0 intensity 0.5 }\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
              "  geometry DEF Floor IndexedFaceSet { coord Coordinate { point [-1 0 -1, -1 0 1, 1 0 1, 1 0 -1] }\n"
              "    coordIndex [0 1 2 3 -1] } }\n");
    writeText(tmp.path / "realtime.txt", "# drawn by the engine\nLamp\n");
    writeText(tmp.path / "dark.txt", "Floor\n");
    writeText(tmp.path / "wrong.txt", "Lamp\nLamp2\n");
    const fs::path out = tmp.path / "out";
    const std::string bake = "bake " + quote(tmp.path / "lit.wrl") + " -q --quality draft --realtime-lights ";
    const RunResult run = runRadbake(bake + quote(tmp.path / "realtime.txt") + " -o " + quote(out));
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    CHECK(fs::exists(out / "lightmaps" / "lit_0_shadowmask.png"));
    const nlohmann::json stats = nlohmann::json::parse(readBytes(out / "stats.json"));
    CHECK(stats.at("realtime_lights") == 1);
    CHECK(stats.at("shadowmask_lights_without_channel") == 0);
    const nlohmann::json json = nlohmann::json::parse(glbJson(out / "lit.glb"));
    CHECK(json.at("asset").at("extras").at("radbake_shadowmask_channels") == nlohmann::json({{"Lamp", 0}}));
    for (const nlohmann::json& material : json.at("materials"))
        if (material.contains("extensions"))
            CHECK(material.at("extras").at("radbake_shadowmask").get<std::string>() == "lightmaps/lit_0_shadowmask.png");
    const RunResult refused = runRadbake(bake + quote(tmp.path / "wrong.txt") + " -o " + quote(tmp.path / "b"));
    CHECK(refused.exit_code == 1);
    CHECK(refused.output.find("wrong.txt:2:1: error: no light or emissive mesh is named 'Lamp2' (named lights: 'Lamp', "
                              "'Fill')") != std::string::npos);
    CHECK_FALSE(fs::exists(tmp.path / "b"));
    const RunResult dark = runRadbake(bake + quote(tmp.path / "dark.txt") + " -o " + quote(tmp.path / "b"));
    CHECK(dark.exit_code == 1);
    CHECK(dark.output.find("dark.txt:1:1: error: 'Floor' is a mesh that emits no light") != std::string::npos);
    CHECK_FALSE(fs::exists(tmp.path / "b"));
    // Lightmap-only options without lightmaps say so.
    const RunResult plain = runRadbake("bake " + quote(tmp.path / "lit.wrl") + " -q --quality draft --no-lightmaps --directional " +
                                       "--lightmap-quantity radiance -o " + quote(tmp.path / "c"));
    CHECK(plain.exit_code == 0);
    CHECK(plain.output.find("warning: --directional has no effect: the bake has no lightmaps") != std::string::npos);
    CHECK(plain.output.find("warning: --lightmap-quantity has no effect: the bake has no lightmaps") != std::string::npos);
}
