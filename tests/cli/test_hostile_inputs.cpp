// Hostile scene files (issue 32): bytes that crashed or hung Assimp, paths that are not
// regular files (FIFOs, sockets, directories, all made in a temporary folder), and paths that
// lead out of the scene's folder (the read policy, core/read_policy.h). Every run has
// a time limit, so a hang fails its test instead of stopping the suite.
#include <doctest/doctest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cli_support.h"
#include "radbake.h"

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

// ---- the read policy: a scene reads only regular files under its read roots -------------

namespace {

// A scene's folder and a folder beside it that it must not reach, holding a VRML scene of
// its own (a lit triangle, so reading it would change the bake), a text file, an image, an
// MTL and a glTF buffer, each marked "TOPSECRET" so a leak is found wherever it lands.
struct TwoFolders {
    TempDir tmp;
    fs::path scene, secret;
    TwoFolders() : scene(tmp.path / "scene"), secret(tmp.path / "secret") {
        fs::create_directory(scene);
        fs::create_directory(secret);
        writeText(secret / "secret.wrl", "#VRML V2.0 utf8\n# TOPSECRET\n" + litTriangle("TOPSECRET_MESH", 5));
        writeText(secret / "secret.txt", "TOPSECRET first line of a file nobody may read\n");
        writeText(secret / "protos.wrl", "#VRML V2.0 utf8\nPROTO Slab [] { Shape { geometry Box {} } } # TOPSECRET\n");
        writeText(secret / "tex.ppm", std::string("P6\n1 1\n255\n") + "TOP");  // one texel: 'T' 'O' 'P'
        // A value Assimp cannot parse: it quotes it in its error.
        writeText(secret / "secret.mtl", "newmtl TOPSECRET_MATERIAL\nKd 1 0 0\nNs TOPSECRET_LINE of the file\n");
        writeText(secret / "secret.bin", "TOPSECRET-TOPSECRET-TOPS");  // 24 bytes: 3 vec2 UVs
    }
    static std::string litTriangle(const std::string& name, int y) {
        return "DEF " + name + " Shape { appearance Appearance { material Material { emissiveColor 1 1 1 } }\n"
               "  geometry IndexedFaceSet { coord Coordinate { point [0 " + std::to_string(y) + " 0, 1 " +
               std::to_string(y) + " 0, 1 " + std::to_string(y) + " 1] } coordIndex [0 1 2 -1] } }\n";
    }
};

// Every byte of every file under `dir` (outputs, depfile), for leak checks.
std::string everyByteUnder(const fs::path& dir) {
    std::string all;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        if (entry.is_regular_file()) all += readBytes(entry.path());
    return all;
}

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST_CASE("read policy: Inline, EXTERNPROTO and ImageTexture out of the scene's folder are refused by name and "
          "counted; --read-root widens it") {
    TwoFolders f;
    const fs::path room = f.scene / "room.wrl";
    writeText(room, "#VRML V2.0 utf8\n"
                    "EXTERNPROTO Slab [] \"../secret/protos.wrl#Slab\"\n"
                    "Inline { url \"../secret/secret.wrl\" }\n"
                    "Inline { url \"" + (f.secret / "secret.txt").string() + "\" }\n"
                    "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 }\n"
                    "    texture ImageTexture { url \"../secret/tex.ppm\" } }\n"
                    "  geometry IndexedFaceSet { coord Coordinate { point [-2 0 -2, -2 0 2, 2 0 2, 2 0 -2] }\n"
                    "    texCoord TextureCoordinate { point [0 0, 0 1, 1 1, 1 0] } coordIndex [0 1 2 3 -1] } }\n" +
                        TwoFolders::litTriangle("lamp", 1));
    const fs::path out = f.tmp.path / "out", dep = f.tmp.path / "room.d";
    const RunResult run = runRadbake("bake " + quote(room) + " -o " + quote(out) + " --depfile " + quote(dep) +
                                         " --quality draft --no-lightmaps",
                                     kSeconds);
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    // Located at the node that named it, naming the path; never a byte of the file.
    CHECK(run.output.find(room.string() + ":2:13: warning: EXTERNPROTO Slab '" + (f.secret / "protos.wrl").string() +
                          "' refused: ") != std::string::npos);
    CHECK(run.output.find(room.string() + ":3:1: warning: Inline '" + (f.secret / "secret.wrl").string() +
                          "' refused: ") != std::string::npos);
    CHECK(run.output.find(room.string() + ":4:1: warning: Inline '" + (f.secret / "secret.txt").string() +
                          "' refused: ") != std::string::npos);
    CHECK(run.output.find(room.string() + ":6:13: warning: cannot read texture '" + (f.secret / "tex.ppm").string() +
                          "' (") != std::string::npos);
    CHECK(count(run.output, "outside the read root '" + f.scene.string() + "'") == 4);
    CHECK(run.output.find("TOPSECRET") == std::string::npos);
    const std::string stats = readBytes(out / "stats.json");
    CHECK(stats.find("\"refused_inputs\": 4") != std::string::npos);
    CHECK(stats.find("\"meshes\": 2") != std::string::npos);  // the floor and the lamp, nothing inlined
    const std::string outputs = everyByteUnder(out) + readBytes(dep);
    CHECK(outputs.find("TOPSECRET") == std::string::npos);
    CHECK(outputs.find("\"images\"") == std::string::npos);  // the image outside is not embedded
    CHECK(readBytes(dep).find(f.secret.string()) == std::string::npos);

    // --read-root widens the policy: the same scene reads all but the text file, which is no VRML.
    fs::remove(f.secret / "secret.txt");
    const RunResult widened = runRadbake("bake " + quote(room) + " -o " + quote(out) + " --depfile " + quote(dep) +
                                             " --read-root " + quote(f.secret) + " --quality draft --no-lightmaps",
                                         kSeconds);
    INFO(widened.output);
    REQUIRE(widened.exit_code == 0);
    CHECK(widened.output.find("refused") == std::string::npos);
    CHECK(readBytes(out / "stats.json").find("refused_inputs") == std::string::npos);
    CHECK(readBytes(out / "stats.json").find("\"meshes\": 3") != std::string::npos);  // and the Inline's
    CHECK(readBytes(dep).find((f.secret / "secret.wrl").string()) != std::string::npos);
    CHECK(readBytes(dep).find((f.secret / "tex.ppm").string()) != std::string::npos);
    const RunResult info = runRadbake("info --json " + quote(room) + " --read-root " + quote(f.secret), kSeconds);
    INFO(info.output);
    CHECK(info.exit_code == 0);
    CHECK(info.output.find("refused") == std::string::npos);
    CHECK(info.output.find((f.secret / "secret.wrl").string()) != std::string::npos);
}

TEST_CASE("read policy: a symbolic link in the scene's folder that leads out of it is refused") {
    TwoFolders f;
    const fs::path link = f.scene / "inlined.wrl", folder_link = f.scene / "textures";
    REQUIRE_MESSAGE(::symlink((f.secret / "secret.wrl").c_str(), link.c_str()) == 0, std::strerror(errno));
    REQUIRE_MESSAGE(::symlink(f.secret.c_str(), folder_link.c_str()) == 0, std::strerror(errno));
    const fs::path room = f.scene / "room.wrl";
    writeText(room, "#VRML V2.0 utf8\nInline { url \"inlined.wrl\" }\n"
                    "Shape { appearance Appearance { texture ImageTexture { url \"textures/tex.ppm\" } }\n"
                    "  geometry IndexedFaceSet { coord Coordinate { point [-2 0 -2, -2 0 2, 2 0 2] } coordIndex [0 1 2 -1] } }\n" +
                        TwoFolders::litTriangle("lamp", 1));
    const RunResult run = runRadbake("info " + quote(room), kSeconds);
    INFO(run.output);
    CHECK(run.exit_code == 0);
    CHECK(run.output.find(room.string() + ":2:1: warning: Inline '" + link.string() + "' refused: resolved to '" +
                          (f.secret / "secret.wrl").string() + "', outside the read root") != std::string::npos);
    CHECK(run.output.find("warning: cannot read texture '" + (folder_link / "tex.ppm").string() + "' (resolved to '" +
                          (f.secret / "tex.ppm").string() + "', outside the read root") != std::string::npos);
    CHECK(run.output.find("refused    2 files") != std::string::npos);
    CHECK(run.output.find("TOPSECRET") == std::string::npos);
}

TEST_CASE("read policy: an OBJ's mtllib out of the tree is refused, and no line of it appears anywhere") {
    TwoFolders f;
    const fs::path obj = f.scene / "room.obj";
    writeText(obj, "mtllib ../secret/secret.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 1\nusemtl TOPSECRET_MATERIAL\nf 1 2 3\n");
    const fs::path out = f.tmp.path / "out", dep = f.tmp.path / "room.d";
    const RunResult info = runRadbake("info " + quote(obj), kSeconds);
    const RunResult bake = runRadbake("bake " + quote(obj) + " -o " + quote(out) + " --depfile " + quote(dep) +
                                          " --quality draft --no-lightmaps",
                                      kSeconds);
    for (const RunResult* run : {&info, &bake}) {
        INFO(run->output);
        CHECK(run->output.find(obj.string() + ": warning: '" + (f.scene / "../secret/secret.mtl").string() +
                               "' not read: resolved to '" + (f.secret / "secret.mtl").string() +
                               "', outside the read root") != std::string::npos);
        CHECK(run->output.find("TOPSECRET_LINE") == std::string::npos);
        CHECK(run->output.find("Kd 1 0 0") == std::string::npos);
    }
    // Nothing lights the triangle, so the bake may fail; whatever it wrote holds no line of the MTL.
    if (fs::exists(out)) {
        const std::string outputs = everyByteUnder(out);
        CHECK(outputs.find("TOPSECRET_LINE") == std::string::npos);
        CHECK(readBytes(out / "stats.json").find("\"refused_inputs\": 1") != std::string::npos);
    }
}

TEST_CASE("read policy: a glTF buffer uri out of the tree is refused, never embedded in the output glb") {
    TwoFolders f;
    // Positions from a buffer beside the scene; UVs from the secret one.
    const float corners[9] = {0, 0, 0, 1, 0, 0, 0, 0, 1};
    writeText(f.scene / "mesh.bin", std::string(reinterpret_cast<const char*>(corners), sizeof corners));
    const fs::path gltf = f.scene / "room.gltf";
    writeText(gltf, R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "materials": [{"emissiveFactor": [1, 1, 1]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
  "buffers": [{"uri": "mesh.bin", "byteLength": 36}, {"uri": "../../../)" +
                        f.secret.relative_path().string() + R"(/secret.bin", "byteLength": 24}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 1, "byteLength": 24}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 0, 1]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}]})");
    const fs::path out = f.tmp.path / "out";
    const RunResult run = runRadbake("bake " + quote(gltf) + " -o " + quote(out) + " --quality draft --no-lightmaps",
                                     kSeconds);
    INFO(run.output);
    CHECK(run.output.find(gltf.string() + ": warning: '") != std::string::npos);
    CHECK(run.output.find("secret.bin' not read: resolved to '" + (f.secret / "secret.bin").string() +
                          "', outside the read root") != std::string::npos);
    CHECK(run.output.find("TOPSECRET") == std::string::npos);
    // Either the scene bakes without the buffer, or it fails with a located error: never with it.
    if (run.exit_code == 0) {
        CHECK(everyByteUnder(out).find("TOPSECRET") == std::string::npos);
    } else {
        CHECK(run.exit_code == 1);
        CHECK(run.output.find(gltf.string() + ": error: ") != std::string::npos);
        CHECK_FALSE(fs::exists(out / "room.glb"));
    }
}

TEST_CASE("read policy: a missing Inline, EXTERNPROTO or MTL is named in the depfile, so adding it rebuilds") {
    TempDir tmp;
    const fs::path room = tmp.path / "room.wrl";
    writeText(room, "#VRML V2.0 utf8\nEXTERNPROTO Slab [] \"lib/protos.wrl#Slab\"\nInline { url \"later.wrl\" }\n" +
                        TwoFolders::litTriangle("lamp", 1));
    writeTexturedObj(tmp.path, "absent.png");
    const fs::path obj = tmp.path / "room.obj";
    writeText(obj, "mtllib later.mtl\n" + readBytes(obj));
    for (const auto& [scene, missing] : {std::pair{room, std::vector<std::string>{"later.wrl", "lib/protos.wrl"}},
                                         std::pair{obj, std::vector<std::string>{"later.mtl"}}}) {
        const fs::path out = tmp.path / "out", dep = tmp.path / "room.d";
        const RunResult run = runRadbake("bake " + quote(scene) + " -o " + quote(out) + " --depfile " + quote(dep) +
                                             " --quality draft --no-lightmaps",
                                         kSeconds);
        INFO(run.output);
        CHECK(run.exit_code == 0);
        const std::string depfile = readBytes(dep);
        INFO(depfile);
        for (const std::string& name : missing) CHECK(depfile.find((tmp.path / name).string()) != std::string::npos);
        CHECK(run.output.find("refused") == std::string::npos);
        fs::remove_all(out);
    }
}

TEST_CASE("read policy: a small .wrl.gz that inflates beyond the cap is a located error") {
    TempDir tmp;
    // A VRML header, then a comment of zeros far beyond the cap: a few KiB compressed.
    const fs::path plain = tmp.path / "bomb.wrl";
    writeText(plain, "#VRML V2.0 utf8\n#" + std::string(size_t(8) << 20, '0') + "\n");
    REQUIRE(std::system(("gzip -9 " + quote(plain)).c_str()) == 0);
    const fs::path bomb = tmp.path / "bomb.wrl.gz";
    REQUIRE(fs::file_size(bomb) < 64 * 1024);
    const fs::path top = tmp.path / "top.wrl";
    writeText(top, "#VRML V2.0 utf8\nInline { url \"bomb.wrl.gz\" }\n");
    for (const fs::path& scene : {bomb, top}) {
        radbake::Diagnostics diagnostics;
        std::vector<std::string> lines;
        diagnostics.sink = [&](const radbake::Diagnostic& d) { lines.push_back(radbake::formatDiagnostic(d)); };
        radbake::ImportOptions options;
        options.max_input_bytes = size_t(1) << 20;
        CHECK_FALSE(radbake::importScene(scene.string(), options, diagnostics));
        std::string all;
        for (const std::string& line : lines) all += line + "\n";
        INFO(all);
        const std::string at = scene == top ? top.string() + ":2:1" : bomb.string();
        CHECK(all.find(at + ": error: '" + bomb.string() + "': decompressed data larger than 1048576 bytes") !=
              std::string::npos);
    }
}

TEST_CASE("an Inline of a file that is no VRML does not quote it") {
    TempDir tmp;
    writeText(tmp.path / "notes.txt", "TOPSECRET first line\n");
    const fs::path top = tmp.path / "top.wrl";
    writeText(top, "#VRML V2.0 utf8\nInline { url \"notes.txt\" }\n");
    const RunResult run = runRadbake("info " + quote(top), kSeconds);
    INFO(run.output);
    CHECK(run.output.find((tmp.path / "notes.txt").string() + ":1:1: error: not a VRML file") != std::string::npos);
    CHECK(run.output.find("TOPSECRET") == std::string::npos);
}
