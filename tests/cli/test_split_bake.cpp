// A bake split into steps with files between them (issue 29): `radbake solve` writes the
// solution alone, and a later step reads it.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "cli_support.h"

using namespace clitest;

namespace {

// A floor under an emissive panel: small, lit, with lightmaps.
const char* const kLitRoom =
    "#VRML V2.0 utf8\n"
    "Shape { appearance Appearance { material Material { diffuseColor 0.6 0.6 0.6 } }\n"
    "  geometry IndexedFaceSet { coord Coordinate { point [-1 0 -1, -1 0 1, 1 0 1, 1 0 -1] }\n"
    "    coordIndex [0 1 2 3 -1] } }\n"
    "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
    "  geometry IndexedFaceSet { coord Coordinate { point [-1 0 -1, 1 0 -1, 1 2 -1, -1 2 -1] }\n"
    "    coordIndex [0 1 2 3 -1] } }\n"
    "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 5 5 5 } }\n"
    "  geometry IndexedFaceSet { coord Coordinate { point [-0.3 1.5 -0.3, 0.3 1.5 -0.3, 0.3 1.5 0.3, -0.3 1.5 0.3] }\n"
    "    coordIndex [0 1 2 3 -1] } }\n";

}  // namespace

TEST_CASE("radbake solve: the solution alone, kept when it matches, and a bake from it writes one bake's bytes") {
    TempDir tmp;
    writeText(tmp.path / "lit.wrl", kLitRoom);
    const fs::path solution = tmp.path / "lit.sol";
    const std::string scene = quote(tmp.path / "lit.wrl");
    const RunResult solved = runRadbake("solve " + scene + " -q --quality draft --solution " + quote(solution) +
                                        " --depfile " + quote(tmp.path / "lit.d"));
    INFO(solved.output);
    REQUIRE(solved.exit_code == 0);
    CHECK(solved.output.find("radbake: solved") != std::string::npos);
    REQUIRE(fs::is_regular_file(solution));
    const std::string depfile = readBytes(tmp.path / "lit.d");
    CHECK(depfile.find(solution.string() + ":") == 0);
    CHECK(depfile.find((tmp.path / "lit.wrl").string()) != std::string::npos);

    // The same solver settings, other read-out and lightmap options: the file is kept, untouched.
    const std::string bytes = readBytes(solution);
    const fs::file_time_type written = fs::last_write_time(solution);
    const RunResult again = runRadbake("solve " + scene + " -q --quality draft --solution " + quote(solution) +
                                       " --texel-density 32 --edge-correction off --no-lightmaps");
    CHECK(again.exit_code == 0);
    CHECK(again.output.find("radbake: kept") != std::string::npos);
    CHECK(fs::last_write_time(solution) == written);

    // A bake reading it writes what a bake from scratch writes, without solving.
    const RunResult from_file = runRadbake("bake " + scene + " -q --quality draft --solution " + quote(solution) +
                                           " -o " + quote(tmp.path / "a"));
    const RunResult whole = runRadbake("bake " + scene + " -q --quality draft -o " + quote(tmp.path / "b"));
    REQUIRE(from_file.exit_code == 0);
    REQUIRE(whole.exit_code == 0);
    CHECK(readBytes(solution) == bytes);
    CHECK(readBytes(tmp.path / "a" / "timings.json").find("\"links\"") == std::string::npos);
    CHECK(readBytes(tmp.path / "b" / "timings.json").find("\"links\"") != std::string::npos);
    const auto a = outputsOf(tmp.path / "a"), b = outputsOf(tmp.path / "b");
    REQUIRE(a.size() == b.size());
    for (size_t i = 0; i < a.size(); ++i) {
        CAPTURE(a[i].first);
        CHECK(a[i].first == b[i].first);
        CHECK(a[i].second == b[i].second);
    }

    // Other solver settings: solved again and rewritten.
    const RunResult other = runRadbake("solve " + scene + " -q --quality medium --solution " + quote(solution));
    CHECK(other.exit_code == 0);
    CHECK(other.output.find("radbake: solved") != std::string::npos);
    CHECK(readBytes(solution) != bytes);
}

TEST_CASE("radbake solve: --solution is required, and one naming a directory is refused before the solve") {
    TempDir tmp;
    writeText(tmp.path / "lit.wrl", kLitRoom);
    const std::string scene = quote(tmp.path / "lit.wrl");
    CHECK(runRadbake("solve " + scene + " -q").exit_code == 2);
    fs::create_directory(tmp.path / "dir.sol");
    const RunResult refused = runRadbake("solve " + scene + " -q --solution " + quote(tmp.path / "dir.sol"));
    CHECK(refused.exit_code == 1);
    CHECK(refused.output.find((tmp.path / "dir.sol").string() + ": error: cannot write the solution file") !=
          std::string::npos);
    CHECK(refused.output.find("radbake: solved") == std::string::npos);
    CHECK(fs::is_directory(tmp.path / "dir.sol"));
}

namespace {

// `radbake solve`, N `radbake gather` shards and `radbake merge` of a shipped scene against one
// `radbake bake` with the same options: every output but timings.json the same bytes.
void checkShardsMergeToOneBake(const std::string& scene_name, const std::string& options) {
    CAPTURE(scene_name);
    TempDir tmp;
    const fs::path root = fs::path(RADBAKE_SOURCE_DIR) / "scenes";
    const std::string scene = quote(root / (scene_name + ".wrl"));
    const std::string common = " -q " + options + " --probes " + quote(root / (scene_name + ".probes"));
    const fs::path solution = tmp.path / "scene.sol";
    REQUIRE(runRadbake("solve " + scene + common + " --solution " + quote(solution)).exit_code == 0);
    REQUIRE(runRadbake("bake " + scene + common + " -o " + quote(tmp.path / "whole")).exit_code == 0);
    const auto whole = outputsOf(tmp.path / "whole");
    for (const int shards : {1, 3, 7}) {
        CAPTURE(shards);
        std::string parts;
        for (int k = shards; k >= 1; --k) {  // any order
            const fs::path part = tmp.path / ("part" + std::to_string(shards) + "_" + std::to_string(k));
            const RunResult gathered = runRadbake("gather " + scene + common + " --solution " + quote(solution) +
                                                  " --shard " + std::to_string(k) + "/" + std::to_string(shards) +
                                                  " --threads 1 -o " + quote(part));
            INFO(gathered.output);
            REQUIRE(gathered.exit_code == 0);
            parts += " " + quote(part);
        }
        const fs::path merged = tmp.path / ("merged" + std::to_string(shards));
        const RunResult run = runRadbake("merge" + parts + " -q -o " + quote(merged));
        INFO(run.output);
        REQUIRE(run.exit_code == 0);
        checkSameOutputs(merged, whole);
    }
}

}  // namespace

TEST_CASE("solve, gather 1, 3 or 7 shards and merge: the bytes of one bake (vertices, lightmaps, directions, shadowmasks, probes, previews)") {
    checkShardsMergeToOneBake("cornell_box", "--quality draft --preview");
    checkShardsMergeToOneBake("paper/duplex", "--quality draft --texel-density 24");
    checkShardsMergeToOneBake("cornell_box", "--quality medium --no-lightmaps");
    // Directional lightmaps and the shadowmask of the lamp, drawn in real time.
    TempDir side;
    writeText(side.path / "realtime.txt", "Light\n");
    checkShardsMergeToOneBake("cornell_box", "--quality draft --texel-density 32 --directional --realtime-lights " +
                                                 quote(side.path / "realtime.txt"));
}

TEST_CASE("a shard fed another solution, a merge missing a part or given a foreign one: refused by name, nothing written") {
    TempDir tmp;
    writeText(tmp.path / "lit.wrl", kLitRoom);
    const std::string scene = quote(tmp.path / "lit.wrl");
    const std::string draft = " -q --quality draft --no-lightmaps";
    const fs::path solution = tmp.path / "lit.sol";
    REQUIRE(runRadbake("solve " + scene + draft + " --solution " + quote(solution)).exit_code == 0);
    const auto gather = [&](const std::string& options, const std::string& shard, const std::string& part) {
        return runRadbake("gather " + scene + options + " --solution " + quote(solution) + " --shard " + shard + " -o " +
                          quote(tmp.path / part));
    };

    // Other solver settings than the solution's: a located error, no part folder.
    const RunResult wrong = gather(" -q --quality medium --no-lightmaps", "1/2", "wrong");
    CHECK(wrong.exit_code == 1);
    CHECK(wrong.output.find(solution.string() + ": error: does not hold the solution of") != std::string::npos);
    CHECK_FALSE(fs::exists(tmp.path / "wrong"));
    // Not K/N: a bad command line.
    CHECK(gather(draft, "3/2", "bad").exit_code == 2);
    CHECK(gather(draft, "0/2", "bad").exit_code == 2);

    REQUIRE(gather(draft, "1/2", "p1").exit_code == 0);
    REQUIRE(gather(draft, "2/2", "p2").exit_code == 0);
    REQUIRE(runRadbake("solve " + scene + " -q --quality draft --error-threshold 0.5 --solution " + quote(tmp.path / "other.sol")).exit_code == 0);
    REQUIRE(runRadbake("gather " + scene + " -q --quality draft --error-threshold 0.5 --no-lightmaps --solution " +
                       quote(tmp.path / "other.sol") + " --shard 2/2 -o " + quote(tmp.path / "foreign"))
                .exit_code == 0);
    const std::string out = " -o " + quote(tmp.path / "out");
    const RunResult missing = runRadbake("merge " + quote(tmp.path / "p1") + out);
    CHECK(missing.exit_code == 1);
    CHECK(missing.output.find("shard 2 of 2 is missing") != std::string::npos);
    const RunResult foreign = runRadbake("merge " + quote(tmp.path / "p1") + " " + quote(tmp.path / "foreign") + out);
    CHECK(foreign.exit_code == 1);
    CHECK(foreign.output.find((tmp.path / "foreign").string() + ": error: was gathered with another scene or other options") !=
          std::string::npos);
    const RunResult twice = runRadbake("merge " + quote(tmp.path / "p1") + " " + quote(tmp.path / "p1") + out);
    CHECK(twice.exit_code == 1);
    CHECK(twice.output.find("more than one part of shard 1 of 2") != std::string::npos);
    const RunResult not_a_part = runRadbake("merge " + quote(tmp.path / "p1") + " " + quote(tmp.path) + out);
    CHECK(not_a_part.exit_code == 1);
    CHECK(not_a_part.output.find(tmp.path.string() + ": error: is not a read-out part") != std::string::npos);
    CHECK_FALSE(fs::exists(tmp.path / "out"));
    const RunResult merged = runRadbake("merge " + quote(tmp.path / "p2") + " " + quote(tmp.path / "p1") + out);
    INFO(merged.output);
    CHECK(merged.exit_code == 0);
    CHECK(fs::exists(tmp.path / "out" / "lit.glb"));
    // The scene edited since the shards read it: refused, naming the part.
    writeText(tmp.path / "lit.wrl", std::string(kLitRoom) + "# edited\n");
    const RunResult edited = runRadbake("merge " + quote(tmp.path / "p2") + " " + quote(tmp.path / "p1") + " -o " +
                                        quote(tmp.path / "out2"));
    CHECK(edited.exit_code == 1);
    CHECK(edited.output.find((tmp.path / "p1").string() + ": error: was read from other scene files") != std::string::npos);
    CHECK_FALSE(fs::exists(tmp.path / "out2"));
}
