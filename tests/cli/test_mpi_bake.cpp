// One bake shared between MPI ranks (issue 29): `mpirun -np N radbake bake` writes exactly the
// bytes of one process's bake, and a rank that fails ends the run with a located error and
// nothing written. Built where CMake found MPI (radbake then shares bakes between ranks).
#include <doctest/doctest.h>

#include <string>

#include "cli_support.h"

#ifdef RADBAKE_MPIEXEC

using namespace clitest;

namespace {

// `mpirun -np N radbake ARGS` (oversubscribed: CI machines have fewer cores than ranks; as
// root where CI runs as root), killed after five minutes rather than hanging the suite.
RunResult runRanks(int ranks, const std::string& args) {
    return runShell("timeout -s KILL 300 '" RADBAKE_MPIEXEC "' --oversubscribe --allow-run-as-root -np " +
                    std::to_string(ranks) + " '" + RADBAKE_EXE + "' " + args + " 2>&1");
}

void checkRanksBakeOneBake(const std::string& scene_name, const std::string& options) {
    CAPTURE(scene_name);
    CAPTURE(options);
    TempDir tmp;
    const fs::path root = fs::path(RADBAKE_SOURCE_DIR) / "scenes";
    const std::string common = quote(root / (scene_name + ".wrl")) + " -q " + options;
    REQUIRE(runRadbake("bake " + common + " -o " + quote(tmp.path / "one")).exit_code == 0);
    const auto one = outputsOf(tmp.path / "one");
    for (const int ranks : {1, 2, 3}) {
        CAPTURE(ranks);
        const fs::path out = tmp.path / ("ranks" + std::to_string(ranks));
        const RunResult run = runRanks(ranks, "bake " + common + " --threads 1 -o " + quote(out));
        INFO(run.output);
        REQUIRE(run.exit_code == 0);
        checkSameOutputs(out, one);
        // The work was shared, not repeated by each rank alone (which gives the same bytes).
        const std::string timings = readBytes(out / "timings.json");
        if (ranks > 1) CHECK(timings.find("\"ranks\": " + std::to_string(ranks)) != std::string::npos);
        else CHECK(timings.find("\"ranks\"") == std::string::npos);
    }
}

}  // namespace

TEST_CASE("mpirun -np 1, 2 or 3 radbake bake: the bytes of one bake (vertices, lightmaps, directions, shadowmasks, probes, previews)") {
    const fs::path root = fs::path(RADBAKE_SOURCE_DIR) / "scenes";
    checkRanksBakeOneBake("cornell_box", "--quality draft --preview --probes " + quote(root / "cornell_box.probes"));
    checkRanksBakeOneBake("paper/duplex", "--quality draft --texel-density 24");
    checkRanksBakeOneBake("cornell_box", "--quality medium --no-lightmaps");
    TempDir side;
    writeText(side.path / "realtime.txt", "Light\n");
    checkRanksBakeOneBake("cornell_box", "--quality draft --texel-density 32 --directional --realtime-lights " +
                                             quote(side.path / "realtime.txt"));
}

TEST_CASE("mpirun radbake solve writes one process's solution; a bake on ranks reads it back") {
    TempDir tmp;
    const std::string scene = quote(fs::path(RADBAKE_SOURCE_DIR) / "scenes" / "paper" / "duplex.wrl");
    const std::string common = " -q --quality draft --texel-density 16";
    REQUIRE(runRadbake("solve " + scene + common + " --solution " + quote(tmp.path / "one.sol")).exit_code == 0);
    const RunResult solved = runRanks(2, "solve " + scene + common + " --solution " + quote(tmp.path / "two.sol"));
    INFO(solved.output);
    REQUIRE(solved.exit_code == 0);
    CHECK(readBytes(tmp.path / "two.sol") == readBytes(tmp.path / "one.sol"));
    REQUIRE(runRadbake("bake " + scene + common + " -o " + quote(tmp.path / "one")).exit_code == 0);
    const RunResult baked =
        runRanks(3, "bake " + scene + common + " --solution " + quote(tmp.path / "two.sol") + " -o " + quote(tmp.path / "three"));
    INFO(baked.output);
    REQUIRE(baked.exit_code == 0);
    checkSameOutputs(tmp.path / "three", outputsOf(tmp.path / "one"));
}

TEST_CASE("on ranks, a broken scene or an unusable solution file fails with a located error and writes nothing") {
    TempDir tmp;
    writeText(tmp.path / "broken.wrl", "#VRML V2.0 utf8\nShape { geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 1 0 0] }\n");
    const RunResult broken = runRanks(2, "bake " + quote(tmp.path / "broken.wrl") + " -q -o " + quote(tmp.path / "out"));
    CHECK(broken.exit_code != 0);
    CHECK(broken.output.find((tmp.path / "broken.wrl").string() + ":") != std::string::npos);
    CHECK(!fs::exists(tmp.path / "out"));

    // A directory where the solution file should be: the lead refuses it, every rank stops.
    fs::create_directory(tmp.path / "dir.sol");
    const std::string scene = quote(fs::path(RADBAKE_SOURCE_DIR) / "scenes" / "cornell_box.wrl");
    const RunResult refused = runRanks(2, "bake " + scene + " -q --quality draft --solution " +
                                              quote(tmp.path / "dir.sol") + " -o " + quote(tmp.path / "out"));
    CHECK(refused.exit_code != 0);
    CHECK(refused.output.find((tmp.path / "dir.sol").string() + ": error: cannot use the solution file") !=
          std::string::npos);
    CHECK(!fs::exists(tmp.path / "out"));
    CHECK(fs::is_directory(tmp.path / "dir.sol"));
}

TEST_CASE("a read-out shard or a merge on more than one rank is refused: they are separate jobs") {
    TempDir tmp;
    const std::string scene = quote(fs::path(RADBAKE_SOURCE_DIR) / "scenes" / "cornell_box.wrl");
    const RunResult run = runRanks(2, "gather " + scene + " -q --solution " + quote(tmp.path / "s.sol") +
                                          " --shard 1/2 -o " + quote(tmp.path / "part"));
    CHECK(run.exit_code != 0);
    CHECK(run.output.find("radbake gather runs as one process") != std::string::npos);
    CHECK(!fs::exists(tmp.path / "part"));
}

#endif
