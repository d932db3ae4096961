// Memory bounded before it is spent (issue 32): small hostile scenes that expand to gigabytes
// (a PNG header declaring 16383^2 pixels, an Extrusion's spine x cross-section, a DEF/USE
// fan-out, faces stacked a thousand deep for the overlap check) are refused from what they
// declare, under --max-memory or an address-space limit (ulimit -v), with a located message;
// an allocation that fails anyway is a located error and exit 1, never an abort. Every run
// has a time limit and an address-space cap, so none can take the machine's memory.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "cli_support.h"

using namespace clitest;

namespace {

constexpr int kSeconds = 60;
constexpr long kCapKib = 1000000;  // ulimit -v for runs that must not spend memory: about 1 GB

// `radbake ARGS` under `ulimit -v kib` (the shell fails, and so the test, when it cannot set it).
RunResult runUnder(long kib, const std::string& args) {
    return runShell("ulimit -v " + std::to_string(kib) + " && exec timeout -s KILL " + std::to_string(kSeconds) + " '" +
                    RADBAKE_EXE + "' " + args + " 2>&1");
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Exit 1 with an error located in `file`, and no sign of an abort or an escaped exception.
void checkLocatedFailure(const RunResult& run, const std::string& file) {
    INFO(run.output);
    CHECK(run.exit_code == 1);
    CHECK(contains(run.output, file));
    CHECK(contains(run.output, "error:"));
    CHECK_FALSE(contains(run.output, "terminate called"));
    CHECK_FALSE(contains(run.output, "std::bad_alloc"));
}

// `info` of dir/file under the address-space cap, with --max-memory 512 and without (the budget
// is then 3/4 of ulimit -v), and `bake` with `bake_options`, each end in a located error at
// `where` naming `what` (info) before the geometry is built; the bake writes nothing.
void checkExpansionRefused(const TempDir& dir, const std::string& file, const std::string& where,
                           const std::string& what, const std::string& bake_options) {
    const std::string scene = quote(dir.path / file);
    for (const std::string& budget : {std::string(" --max-memory 512"), std::string()}) {
        CAPTURE(budget);
        const RunResult info = runUnder(kCapKib, "info " + scene + budget);
        checkLocatedFailure(info, where);
        CHECK(contains(info.output, what));
        CHECK(contains(info.output, "--max-memory"));
    }
    const fs::path out = dir.path / "out";
    const RunResult baked = runUnder(4 * kCapKib, "bake " + scene + bake_options + " -q -o " + quote(out));
    checkLocatedFailure(baked, where);
    CHECK_FALSE(fs::exists(out));
}

uint32_t crc32(const std::string& bytes) {
    uint32_t crc = 0xffffffffu;
    for (unsigned char byte : bytes) {
        crc ^= byte;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

std::string bigEndian(uint32_t value) {
    return {char(value >> 24), char(value >> 16), char(value >> 8), char(value)};
}

std::string pngChunk(const std::string& type, const std::string& data) {
    return bigEndian(uint32_t(data.size())) + type + data + bigEndian(crc32(type + data));
}

// A valid PNG header declaring width x height 8-bit RGBA, with one stored (uncompressed)
// zlib block of two zero rows: a few hundred bytes that a decoder sizes for the whole image.
std::string hugePngHeader(uint32_t width, uint32_t height) {
    const std::string ihdr = bigEndian(width) + bigEndian(height) + std::string("\x08\x06\x00\x00\x00", 5);
    const std::string rows(64, '\0');
    const uint16_t length = uint16_t(rows.size());
    std::string zlib = "\x78\x01";
    zlib += '\x01';  // final block, stored
    zlib += char(length & 0xff);
    zlib += char(length >> 8);
    zlib += char(~length & 0xff);
    zlib += char((~length >> 8) & 0xff);
    zlib += rows + bigEndian(1u);  // the Adler-32 is never reached: the data ends first
    return std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr) + pngChunk("IDAT", zlib) + pngChunk("IEND", "");
}

// A lamp over a floor textured with `texture`.
void writeTexturedWrl(const fs::path& path, const std::string& texture) {
    writeText(path,
              "#VRML V2.0 utf8\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 2 2 2 } }\n"
              "  geometry IndexedFaceSet { coord Coordinate { point [-0.5 1 -0.5, 0.5 1 -0.5, 0.5 1 0.5, -0.5 1 0.5] }\n"
              "    coordIndex [0 1 2 3 -1] } }\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0.8 0.8 0.8 }\n"
              "    texture ImageTexture { url \"" + texture + "\" } }\n"
              "  geometry IndexedFaceSet { coord Coordinate { point [-2 0 -2, -2 0 2, 2 0 2, 2 0 -2] }\n"
              "    coordIndex [0 1 2 3 -1] } }\n");
}

// An emitting Extrusion whose spine runs up and down between y = 0 and 1 `spine` times around a
// circular cross-section of `section` points: every side quad is stacked spine/2 deep.
std::string stackedExtrusion(int spine, int section) {
    std::string text = "#VRML V2.0 utf8\nShape { appearance Appearance { material Material { emissiveColor 1 1 1 } }\n"
                       "  geometry Extrusion { spine [";
    for (int i = 0; i < spine; ++i) text += i % 2 ? " 0 1 0," : " 0 0 0,";
    text += "] crossSection [";
    for (int j = 0; j < section; ++j) {
        const double angle = 2.0 * 3.14159265358979 * j / (section - 1);
        char point[48];
        std::snprintf(point, sizeof point, " %.3f %.3f,", std::cos(angle), std::sin(angle));
        text += point;
    }
    return text + "] } }\n";
}

// A Sphere DEF'd once, then `levels` Groups each USing the previous one twice: 2^levels spheres.
std::string fanOut(int levels) {
    std::string text = "#VRML V2.0 utf8\n"
                       "DEF L0 Shape { appearance Appearance { material Material { emissiveColor 1 1 1 } } "
                       "geometry Sphere {} }\n";
    for (int k = 1; k <= levels; ++k)
        text += "DEF L" + std::to_string(k) + " Group { children [ USE L" + std::to_string(k - 1) + " USE L" +
                std::to_string(k - 1) + " ] }\n";
    return text;
}

}  // namespace

TEST_CASE("memory: a small PNG declaring 16383 x 16383 RGBA pixels is refused from its header, never decoded") {
    TempDir dir;
    writeText(dir.path / "huge.png", hugePngHeader(16383, 16383));
    REQUIRE(fs::file_size(dir.path / "huge.png") < 1024);
    writeTexturedWrl(dir.path / "room.wrl", "huge.png");
    const std::string scene = quote(dir.path / "room.wrl");

    // The default budget: more than 64 M pixels is refused unless --max-memory allows it.
    const RunResult info = runUnder(kCapKib, "info " + scene);
    INFO(info.output);
    CHECK(info.exit_code == 0);
    CHECK(contains(info.output, "room.wrl:6:"));
    CHECK(contains(info.output, "16383 x 16383"));
    CHECK(contains(info.output, "pixels"));
    // A budget given that cannot hold it.
    const RunResult budget = runUnder(kCapKib, "info " + scene + " --max-memory 512");
    INFO(budget.output);
    CHECK(budget.exit_code == 0);
    CHECK(contains(budget.output, "room.wrl:6:"));
    CHECK(contains(budget.output, "--max-memory"));

    // The bake goes on without it, as with a missing texture, and never embeds it.
    const fs::path out = dir.path / "out";
    const RunResult baked =
        runUnder(4 * kCapKib, "bake " + scene + " --quality draft --no-lightmaps --max-memory 512 -q -o " + quote(out));
    INFO(baked.output);
    REQUIRE(baked.exit_code == 0);
    const std::string glb = readBytes(out / "room.glb");
    REQUIRE_FALSE(glb.empty());
    CHECK_FALSE(contains(glb, bigEndian(16383) + bigEndian(16383)));
}

TEST_CASE("memory: an Extrusion whose spine x cross-section expands past the budget is a located error") {
    TempDir dir;
    // 2000 x 2000 points in about 40 KB: 8 million triangles.
    writeText(dir.path / "extrusion.wrl", stackedExtrusion(2000, 2000));
    REQUIRE(fs::file_size(dir.path / "extrusion.wrl") > 30000);
    checkExpansionRefused(dir, "extrusion.wrl", "extrusion.wrl:3:", "Extrusion expands to", " --max-memory 512");
}

TEST_CASE("memory: the coplanar overlap check of faces stacked a thousand deep is bounded") {
    TempDir dir;
    // 40 cross-section points, each side quad stacked 1000 deep: a million pairs per quad.
    writeText(dir.path / "stacked.wrl", stackedExtrusion(2000, 40));
    const RunResult info = runUnder(kCapKib, "info " + quote(dir.path / "stacked.wrl"));
    INFO(info.output);
    CHECK(info.exit_code == 0);
    CHECK(contains(info.output, "stacked.wrl:3:"));
    CHECK(contains(info.output, "overlap check stopped after"));
    CHECK(contains(info.output, "duplicate coplanar face(s)"));
}

TEST_CASE("memory: a 2 KB DEF/USE fan-out doubling at each level is a located error before it is built") {
    TempDir dir;
    writeText(dir.path / "fan.wrl", fanOut(30));  // 2^30 spheres
    REQUIRE(fs::file_size(dir.path / "fan.wrl") < 2500);
    checkExpansionRefused(dir, "fan.wrl", "fan.wrl:", "Group 'L", "");
}

TEST_CASE("memory: an allocation that fails below the budget is a located error and exit 1, never an abort") {
    TempDir dir;
    // 2 million triangles fit a budget the address space does not hold: reading succeeds,
    // a later phase (validation, hard edges, the summary) fails to allocate.
    writeText(dir.path / "extrusion.wrl", stackedExtrusion(1000, 1000));
    const std::string scene = quote(dir.path / "extrusion.wrl");
    const long cap_kib = 250000;
    const RunResult info = runUnder(cap_kib, "info " + scene + " --max-memory 100000");
    checkLocatedFailure(info, "extrusion.wrl: error:");
    CHECK(contains(info.output, "out of memory while"));
    const fs::path out = dir.path / "out";
    const RunResult baked = runUnder(cap_kib, "bake " + scene + " --max-memory 100000 -q -o " + quote(out));
    checkLocatedFailure(baked, "extrusion.wrl: error:");
    CHECK(contains(baked.output, "out of memory while"));
    CHECK_FALSE(fs::exists(out));
}
