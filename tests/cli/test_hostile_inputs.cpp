// Hostile scene files (issue 32): bytes that crashed or hung Assimp, and paths that are not
// regular files (FIFOs, sockets, directories, all made in a temporary folder). Every run has
// a time limit, so a hang fails its test instead of stopping the suite.
#include <doctest/doctest.h>

#include <cstdint>
#include <string>

#include "cli_support.h"

using namespace clitest;

namespace {

constexpr int kSeconds = 120;  // a tiny scene bakes in a second; only a hang takes this long

// A binary little-endian PLY triangle whose end_header is followed by `after`.
std::string binaryPly(const std::string& after) {
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header" +
                      after;
    const float corners[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    ply.append(reinterpret_cast<const char*>(corners), sizeof corners);
    const int32_t face[3] = {0, 1, 2};
    ply += '\3';
    ply.append(reinterpret_cast<const char*>(face), sizeof face);
    return ply;
}

}  // namespace

TEST_CASE("PLY: end_header followed by a vertical tab is a located error, never a hang or a crash") {
    TempDir tmp;
    // Assimp 5.2.5 does not take '\v' for white space: its header never ends. These 33 bytes
    // hung `info` and `bake`; with a face element and a binary body it was a SEGV.
    const std::string ascii("ply\nformat ascii 1.0\nend_header\v\n", 33);
    const fs::path hang = tmp.path / "hang.ply";
    writeText(hang, ascii);
    for (const std::string& command : {std::string("info "), "bake -o " + quote(tmp.path / "out") + " "}) {
        const RunResult run = runRadbake(command + quote(hang), kSeconds);
        CAPTURE(command);
        INFO(run.output);
        CHECK(run.exit_code == 1);
        CHECK(run.output.find(hang.string() + ":3:11: error: PLY end_header is followed by byte 0x0b") !=
              std::string::npos);
    }
    // Other white space Assimp misreads after end_header: a form feed, a NUL.
    const fs::path crash = tmp.path / "crash.ply";
    for (const std::string after : {std::string("\v"), std::string("\f"), std::string(1, '\0')}) {
        writeText(crash, binaryPly(after));
        const RunResult run = runRadbake("bake " + quote(crash) + " -o " + quote(tmp.path / "out"), kSeconds);
        CAPTURE(static_cast<int>(after[0]));
        INFO(run.output);
        CHECK(run.exit_code == 1);
        CHECK(run.output.find(crash.string() + ":9:11: error: PLY end_header is followed by byte 0x") != std::string::npos);
    }
    CHECK_FALSE(fs::exists(tmp.path / "out"));
    // A space, a tab or CRLF after end_header still reads.
    for (const std::string after : {" \n", "\t\n", "\r\n", "\n"}) {
        writeText(crash, binaryPly(after));
        const RunResult run = runRadbake("info " + quote(crash), kSeconds);
        INFO(run.output);
        CHECK(run.exit_code == 0);
        CHECK(run.output.find("triangles  1") != std::string::npos);
    }
}
