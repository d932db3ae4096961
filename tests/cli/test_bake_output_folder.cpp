// `radbake bake` and its output folder (issue 32): locked before any work, so a second bake is
// refused at once; files it did not write kept, with --no-lightmaps too; another scene refused.
#include <chrono>
#include <filesystem>
#include <string>

#include "cli_support.h"
#include "export/output_transaction.h"

using namespace clitest;
using radbake::Diagnostics;
using radbake::OutputTransaction;

namespace {

void writeLamp(const fs::path& path) {
    writeText(path, "#VRML V2.0 utf8\n"
                    "Shape { appearance Appearance { material Material { diffuseColor 0.6 0.6 0.6 } }\n"
                    "  geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 1 0 0, 1 0 1, 0 0 1] }\n"
                    "    coordIndex [0 3 2 1 -1] } }\n"
                    "Shape { appearance Appearance { material Material { emissiveColor 5 5 5 } }\n"
                    "  geometry IndexedFaceSet { coord Coordinate { point [0.3 1 0.3, 0.7 1 0.3, 0.7 1 0.7, 0.3 1 0.7] }\n"
                    "    coordIndex [0 1 2 3 -1] } }\n");
    REQUIRE(fs::is_regular_file(path));
}

}  // namespace

TEST_CASE("radbake bake into a folder another bake holds exits 1 at once, before reading the scene") {
    const TempDir tmp;
    writeLamp(tmp.path / "lamp.wrl");
    for (const bool exists : {false, true}) {
        CAPTURE(exists);
        const fs::path out = tmp.path / (exists ? "old" : "new");
        if (exists) fs::create_directory(out);
        Diagnostics diagnostics;
        OutputTransaction holder(out);
        REQUIRE(holder.begin(diagnostics));
        const auto start = std::chrono::steady_clock::now();
        const RunResult run = runRadbake("bake " + quote(tmp.path / "lamp.wrl") + " -o " + quote(out) + " -q", 60);
        INFO(run.output);
        CHECK(run.exit_code == 1);
        CHECK(run.output.find("another bake is writing into this directory") != std::string::npos);
        CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(10));
        CHECK(fs::exists(out) == exists);
    }
    // Without -o: baked/<scene name>/ is the folder locked, also before the scene is read.
    Diagnostics diagnostics;
    OutputTransaction holder(tmp.path / "baked" / "lamp");
    REQUIRE(holder.begin(diagnostics));
    const std::string command = "cd " + quote(tmp.path) + " && '" + RADBAKE_EXE + "' bake lamp.wrl -q 2>&1";
    CHECK(std::system((command + " | grep -q 'another bake'").c_str()) == 0);
}

TEST_CASE("radbake bake keeps files it did not write, with --no-lightmaps too, and refuses another scene's folder") {
    const TempDir tmp;
    writeLamp(tmp.path / "lamp.wrl");
    writeLamp(tmp.path / "hall.wrl");
    const fs::path out = tmp.path / "out";
    fs::create_directories(out / "lightmaps");
    writeText(out / "lightmaps" / "README", "ours, not radbake's");
    writeText(out / "lightmaps" / "level2_0.exr", "another level's atlas");
    writeText(out / "probes.csv", "hand-made");
    for (const char* extra : {"", " --no-lightmaps", " --preview"}) {
        CAPTURE(extra);
        const RunResult run =
            runRadbake("bake " + quote(tmp.path / "lamp.wrl") + " -o " + quote(out) + " --quality draft -q" + extra, 120);
        INFO(run.output);
        REQUIRE(run.exit_code == 0);
        CHECK(readBytes(out / "lightmaps" / "README") == "ours, not radbake's");
        CHECK(readBytes(out / "lightmaps" / "level2_0.exr") == "another level's atlas");
        CHECK(readBytes(out / "probes.csv") == "hand-made");
        CHECK(fs::exists(out / "lightmaps" / "lamp_0.exr") == (std::string(extra) != " --no-lightmaps"));
    }
    const std::string manifest = readBytes(out / "manifest.json");
    const RunResult other = runRadbake("bake " + quote(tmp.path / "hall.wrl") + " -o " + quote(out) + " --quality draft -q", 120);
    INFO(other.output);
    CHECK(other.exit_code == 1);
    CHECK(other.output.find("another scene ('lamp')") != std::string::npos);
    CHECK(readBytes(out / "manifest.json") == manifest);
    CHECK(fs::exists(out / "lamp.glb"));
    CHECK_FALSE(fs::exists(out / "hall.glb"));
}
