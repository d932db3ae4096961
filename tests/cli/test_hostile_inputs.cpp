// Hostile scene files (issue 32): bytes that crashed or hung Assimp, and paths that are not
// regular files (FIFOs, sockets, directories, all made in a temporary folder). Every run has
// a time limit, so a hang fails its test instead of stopping the suite.
#include <doctest/doctest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "cli_support.h"

using namespace clitest;

namespace {

constexpr int kSeconds = 120;  // a tiny scene bakes in a second; only a hang takes this long

void makeFifo(const fs::path& path) { REQUIRE_MESSAGE(::mkfifo(path.c_str(), 0600) == 0, std::strerror(errno)); }

// A UNIX socket bound at `path`; the file stays after the socket is closed.
void makeSocket(const fs::path& path) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    REQUIRE(path.string().size() < sizeof address.sun_path);
    std::strcpy(address.sun_path, path.c_str());
    const int bound = ::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address);
    ::close(fd);
    REQUIRE_MESSAGE(bound == 0, std::strerror(errno));
}

// A lamp over a floor whose material takes its colour from `texture` (map_Kd).
void writeTexturedObj(const fs::path& dir, const std::string& texture) {
    writeText(dir / "room.mtl", "newmtl light\nKd 0 0 0\nKe 2 2 2\nnewmtl floor\nKd 0.8 0.8 0.8\nmap_Kd " + texture + "\n");
    writeText(dir / "room.obj",
              "mtllib room.mtl\n"
              "v -0.5 1 -0.5\nv 0.5 1 -0.5\nv 0.5 1 0.5\nv -0.5 1 0.5\n"
              "v -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\n"
              "vt 0 0\nvt 0 1\nvt 1 1\nvt 1 0\n"
              "o lamp\nusemtl light\nf 1 2 3 4\n"
              "o floor\nusemtl floor\nf 5/1 6/2 7/3 8/4\n");
}

// The same in VRML97, the floor's ImageTexture naming `texture`.
void writeTexturedWrl(const fs::path& dir, const std::string& texture) {
    writeText(dir / "room.wrl",
              "#VRML V2.0 utf8\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 2 2 2 } }\n"
              "  geometry IndexedFaceSet { coord Coordinate { point [-0.5 1 -0.5, 0.5 1 -0.5, 0.5 1 0.5, -0.5 1 0.5] }\n"
              "    coordIndex [0 1 2 3 -1] } }\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0.8 0.8 0.8 }\n"
              "    texture ImageTexture { url \"" +
                  texture +
                  "\" } }\n"
                  "  geometry IndexedFaceSet { coord Coordinate { point [-2 0 -2, -2 0 2, 2 0 2, 2 0 -2] }\n"
                  "    coordIndex [0 1 2 3 -1] } }\n");
}

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
    for (const std::string& after : {std::string("\v"), std::string("\f"), std::string(1, '\0')}) {
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

TEST_CASE("a texture that is a FIFO, a socket or a directory is a located warning, and the bake goes on") {
    TempDir tmp;
    makeFifo(tmp.path / "fifo.png");
    makeSocket(tmp.path / "socket.png");
    fs::create_directory(tmp.path / "folder.png");
    const std::pair<const char*, const char*> kinds[] = {
        {"fifo.png", "a FIFO"}, {"socket.png", "a socket"}, {"folder.png", "a directory"}};
    for (const auto& [name, kind] : kinds) {
        for (const char* scene : {"room.obj", "room.wrl"}) {
            writeTexturedObj(tmp.path, name);
            writeTexturedWrl(tmp.path, name);
            const fs::path texture = tmp.path / name;
            const std::string expected =
                "warning: cannot read texture '" + texture.string() + "' (not a regular file (" + kind + "))";
            CAPTURE(scene);
            const RunResult info = runRadbake("info " + quote(tmp.path / scene), kSeconds);
            INFO(info.output);
            CHECK(info.exit_code == 0);
            CHECK(info.output.find(expected) != std::string::npos);

            const fs::path out = tmp.path / "out", dep = tmp.path / "room.d";
            const RunResult bake = runRadbake("bake " + quote(tmp.path / scene) + " -o " + quote(out) + " --depfile " +
                                                  quote(dep) + " --quality draft --no-lightmaps",
                                              kSeconds);
            INFO(bake.output);
            CHECK(bake.exit_code == 0);
            CHECK(bake.output.find(expected) != std::string::npos);
            CHECK(fs::is_regular_file(out / "room.glb"));
            // Named in the depfile like a missing texture: replacing it with an image rebuilds.
            CHECK(readBytes(dep).find(texture.string()) != std::string::npos);
            fs::remove_all(out);
        }
    }
    CHECK(fs::is_fifo(tmp.path / "fifo.png"));
    CHECK(fs::is_socket(tmp.path / "socket.png"));
}

TEST_CASE("--probes, --lightmap-scales and an Inline naming a FIFO: refused by name, never a hang") {
    TempDir tmp;
    writeTexturedObj(tmp.path, "absent.png");
    const fs::path fifo = tmp.path / "fifo.txt";
    makeFifo(fifo);
    const std::string bake = "bake " + quote(tmp.path / "room.obj") + " -o " + quote(tmp.path / "out") +
                             " --quality draft --no-lightmaps ";
    for (const std::string option : {"--probes", "--lightmap-scales"}) {
        const RunResult run = runRadbake(bake + option + " " + quote(fifo), kSeconds);
        CAPTURE(option);
        INFO(run.output);
        CHECK((run.exit_code == 1 || run.exit_code == 2));
        CHECK(run.output.find(fifo.string()) != std::string::npos);
        CHECK(run.output.find("not a regular file") != std::string::npos);
    }
    CHECK_FALSE(fs::exists(tmp.path / "out"));

    writeText(tmp.path / "top.wrl", "#VRML V2.0 utf8\nInline { url \"fifo.txt\" }\n"
                                    "Shape { appearance Appearance { material Material { emissiveColor 1 1 1 } }\n"
                                    "  geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 1 0 0, 1 0 1] }\n"
                                    "    coordIndex [0 1 2 -1] } }\n");
    const RunResult inlined = runRadbake("info " + quote(tmp.path / "top.wrl"), kSeconds);
    INFO(inlined.output);
    CHECK(inlined.exit_code == 0);
    CHECK(inlined.output.find(fifo.string()) != std::string::npos);
    CHECK(fs::is_fifo(fifo));
}

TEST_CASE("--depfile or --solution naming a directory or a FIFO: exit 1 naming it, before any output, and it is kept") {
    TempDir tmp;
    writeTexturedObj(tmp.path, "absent.png");
    const fs::path folder = tmp.path / "folder", fifo = tmp.path / "fifo";
    fs::create_directory(folder);
    makeFifo(fifo);
    const fs::path out = tmp.path / "out";
    const std::string bake =
        "bake " + quote(tmp.path / "room.obj") + " -o " + quote(out) + " --quality draft --no-lightmaps ";
    for (const std::string option : {"--depfile", "--solution"}) {
        for (const auto& [path, kind] : {std::pair{folder, "a directory"}, std::pair{fifo, "a FIFO"}}) {
            const RunResult run = runRadbake(bake + option + " " + quote(path), kSeconds);
            CAPTURE(option);
            INFO(run.output);
            CHECK(run.exit_code == 1);
            CHECK(run.output.find(path.string() + ": error: ") != std::string::npos);
            CHECK(run.output.find(std::string("not a regular file (") + kind + ")") != std::string::npos);
            CHECK(run.output.find("Success") == std::string::npos);
            CHECK_FALSE(fs::exists(out));
        }
    }
    CHECK(fs::is_directory(folder));
    CHECK(fs::is_empty(folder));
    CHECK(fs::is_fifo(fifo));
    CHECK_FALSE(fs::exists(tmp.path / "folder.radbake-tmp"));
    CHECK_FALSE(fs::exists(tmp.path / "fifo.radbake-tmp"));
}
