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

// Every file under `dir` but timings.json, by relative path.
std::vector<std::pair<std::string, std::string>> outputsOf(const fs::path& dir) {
    std::vector<std::pair<std::string, std::string>> files;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(dir))
        if (entry.is_regular_file() && entry.path().filename() != "timings.json")
            files.emplace_back(fs::relative(entry.path(), dir).string(), readBytes(entry.path()));
    std::sort(files.begin(), files.end());
    return files;
}

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
