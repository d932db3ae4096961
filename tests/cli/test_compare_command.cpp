// `radbake compare` end to end: two bakes of one scene pass, a one-vertex change in the PLY
// and a one-probe change in probes.csv are named with exit 1, a missing file gives 2.
#include <doctest/doctest.h>

#include <cstring>
#include <optional>
#include <string>

#include "cli_support.h"
#include "core/exr_io.h"

using namespace clitest;

namespace {

// A unit square lamp over a grey floor, with two probes: quick to bake.
void writeLampOverFloor(const fs::path& dir) {
    writeText(dir / "lamp.mtl", "newmtl light\nKd 0 0 0\nKe 2 2 2\nnewmtl floor\nKd 0.5 0.5 0.5\n");
    writeText(dir / "lamp.obj",
              "mtllib lamp.mtl\n"
              "v -0.5 1 -0.5\nv 0.5 1 -0.5\nv 0.5 1 0.5\nv -0.5 1 0.5\n"
              "v -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\n"
              "o lamp\nusemtl light\nf 1 2 3 4\no floor\nusemtl floor\nf 5 6 7 8\n");
    writeText(dir / "probes.txt", "0 0 0 0 1 0\n1 0 1 0 1 0\n");
}

void bakeInto(const fs::path& dir, const fs::path& out) {
    const RunResult run = runRadbake("bake " + quote(dir / "lamp.obj") + " --probes " + quote(dir / "probes.txt") +
                                     " --quality draft -q -o " + quote(out));
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
}

}  // namespace

TEST_CASE("compare: two bakes of one scene agree; one changed vertex or probe is named") {
    TempDir tmp;
    writeLampOverFloor(tmp.path);
    bakeInto(tmp.path, tmp.path / "a");
    bakeInto(tmp.path, tmp.path / "b");

    const RunResult same = runRadbake("compare " + quote(tmp.path / "a") + " " + quote(tmp.path / "b"));
    INFO(same.output);
    CHECK(same.exit_code == 0);
    CHECK(same.output.find("within tolerance") != std::string::npos);
    CHECK(same.output.find("lamp.ply") != std::string::npos);
    CHECK(runRadbake("compare --quiet " + quote(tmp.path / "a") + " " + quote(tmp.path / "b")).output.empty());

    // Vertex 5 (floor, second vertex) red: with lightmaps a PLY vertex is 9 floats (position,
    // normal, colour), u1 v1 and a uchar atlas index: 45 bytes; red is the 7th float.
    std::string ply = readBytes(tmp.path / "b" / "lamp.ply");
    REQUIRE(ply.find("property float u1") != std::string::npos);
    const size_t body = ply.find("end_header\n") + std::strlen("end_header\n");
    const size_t at = body + 5 * 45 + 24;
    float red;
    std::memcpy(&red, ply.data() + at, 4);
    red = red * 1.5f + 0.01f;
    std::memcpy(ply.data() + at, &red, 4);
    writeText(tmp.path / "b" / "lamp.ply", ply);
    const RunResult vertex = runRadbake("compare " + quote(tmp.path / "a") + " " + quote(tmp.path / "b"));
    INFO(vertex.output);
    CHECK(vertex.exit_code == 1);
    CHECK(vertex.output.find("DIFFERS lamp.ply: vertex 5 red") != std::string::npos);
    // Loose enough tolerances accept it.
    CHECK(runRadbake("compare --rel-tol 0.9 " + quote(tmp.path / "a") + " " + quote(tmp.path / "b")).exit_code == 0);

    // probes.csv: x,y,z,nx,ny,nz,r,g,b; set r of the second probe (the last line) to 1000.
    std::string csv = readBytes(tmp.path / "a" / "probes.csv");
    const size_t last_line = csv.rfind('\n', csv.size() - 2) + 1;
    size_t r_start = last_line;
    for (int comma = 0; comma < 6; ++comma) r_start = csv.find(',', r_start) + 1;
    csv.replace(r_start, csv.find(',', r_start) - r_start, "1000");
    writeText(tmp.path / "c.csv", csv);
    fs::create_directories(tmp.path / "c");
    fs::copy_file(tmp.path / "c.csv", tmp.path / "c" / "probes.csv");
    const RunResult probe = runRadbake("compare " + quote(tmp.path / "a" / "probes.csv") + " " +
                                       quote(tmp.path / "c" / "probes.csv"));
    INFO(probe.output);
    CHECK(probe.exit_code == 1);
    CHECK(probe.output.find("DIFFERS probes.csv: probe 1 r is") != std::string::npos);
    CHECK(probe.output.find(" vs 1000 ") != std::string::npos);

    // One texel of the lightmap, in a copy of A: named with its place, exit 1.
    fs::copy(tmp.path / "a", tmp.path / "d", fs::copy_options::recursive);
    radbake::Diagnostics diagnostics;
    std::optional<radbake::RgbImage> atlas = radbake::readExr(tmp.path / "d" / "lightmaps" / "lamp_0.exr", diagnostics);
    REQUIRE(atlas);
    const int x = atlas->width / 2, y = atlas->height / 2;
    atlas->rgb[3 * (static_cast<size_t>(y) * atlas->width + x) + 1] += 0.25f;
    REQUIRE(radbake::writeExr(tmp.path / "d" / "lightmaps" / "lamp_0.exr", *atlas, {}, diagnostics));
    const RunResult texel = runRadbake("compare " + quote(tmp.path / "a") + " " + quote(tmp.path / "d"));
    INFO(texel.output);
    CHECK(texel.exit_code == 1);
    CHECK(texel.output.find("DIFFERS lightmaps/lamp_0.exr: texel (" + std::to_string(x) + ", " + std::to_string(y) +
                            ") G") != std::string::npos);

    fs::remove(tmp.path / "b" / "lamp.glb");
    const RunResult missing = runRadbake("compare " + quote(tmp.path / "a") + " " + quote(tmp.path / "b"));
    INFO(missing.output);
    CHECK(missing.exit_code == 2);
    CHECK(missing.output.find("lamp.glb is missing from") != std::string::npos);
}

TEST_CASE("compare: usage") {
    CHECK(runRadbake("compare onlyone").exit_code == 2);
    CHECK(runRadbake("compare a b --rel-tol -1").exit_code == 2);
    const RunResult help = runRadbake("compare --help");
    CHECK(help.exit_code == 0);
    CHECK(help.output.find("--rel-tol") != std::string::npos);
    CHECK(help.output.find("0.001") != std::string::npos);
    CHECK(help.output.find("1e-06") != std::string::npos);
}
