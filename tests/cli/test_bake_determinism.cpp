// DESIGN.md section 4: the same scene and options give byte-identical outputs whatever the
// thread count, stats.json and manifest.json included; only timings.json (not in the
// manifest) may differ.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <set>
#include <string>

#include "cli_support.h"

using namespace clitest;

namespace {

std::set<std::string> filesUnder(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        if (entry.is_regular_file()) names.insert(fs::relative(entry.path(), dir).generic_string());
    return names;
}

// Bakes a shipped scene (draft, with its probes and previews) with 1 and 2 threads and checks
// that every output but timings.json is the same, byte for byte.
void checkIdenticalWithOneAndTwoThreads(const std::string& scene_name) {
    CAPTURE(scene_name);
    const fs::path scene = fs::path(RADBAKE_SOURCE_DIR) / "scenes" / (scene_name + ".wrl");
    const fs::path probes = fs::path(RADBAKE_SOURCE_DIR) / "scenes" / (scene_name + ".probes");
    REQUIRE(fs::exists(scene));
    REQUIRE(fs::exists(probes));
    TempDir tmp;
    // The scene path as given is in stats.json: the same for both bakes.
    const std::string common = quote(scene) + " --quality draft --preview -q --probes " + quote(probes);
    const RunResult one = runRadbake("bake " + common + " --threads 1 -o " + quote(tmp.path / "t1"));
    const RunResult two = runRadbake("bake " + common + " --threads 2 -o " + quote(tmp.path / "t2"));
    INFO(one.output, two.output);
    REQUIRE(one.exit_code == 0);
    REQUIRE(two.exit_code == 0);

    const std::set<std::string> files = filesUnder(tmp.path / "t1");
    REQUIRE(files == filesUnder(tmp.path / "t2"));
    for (const char* name : {"stats.json", "manifest.json", "timings.json", "probes.csv"})
        CHECK_MESSAGE(files.count(name) == 1, name);
    for (const std::string& name : files) {
        if (name == "timings.json") continue;
        const std::string a = readBytes(tmp.path / "t1" / name);
        CHECK_MESSAGE(!a.empty(), name);
        CHECK_MESSAGE(a == readBytes(tmp.path / "t2" / name), name);
    }

    // The read-out's work is counted where it was done (every vertex and texel read, its rays and
    // form factors): the same counts on either thread count, as the bytes above say.
    const nlohmann::json stats = nlohmann::json::parse(readBytes(tmp.path / "t1" / "stats.json"));
    CHECK(stats.at("vertex_reads").get<size_t>() >= stats.at("vertices").get<size_t>() / 4);
    CHECK(stats.at("texel_reads").get<size_t>() >=
          stats.at("covered_texels").get<size_t>() - stats.at("interpolated_texels").get<size_t>());
    CHECK(stats.at("texel_form_factors").get<size_t>() > stats.at("texel_reads").get<size_t>());

    // What does differ is in timings.json, which the manifest does not list.
    const nlohmann::json t1 = nlohmann::json::parse(readBytes(tmp.path / "t1" / "timings.json"));
    const nlohmann::json t2 = nlohmann::json::parse(readBytes(tmp.path / "t2" / "timings.json"));
    CHECK(t1.at("threads").get<int>() == 1);
    CHECK(t2.at("threads").get<int>() == 2);
    const nlohmann::json manifest = nlohmann::json::parse(readBytes(tmp.path / "t1" / "manifest.json"));
    CHECK(manifest.at("excluded") == nlohmann::json::array({"timings.json"}));
    std::set<std::string> listed;
    for (const nlohmann::json& entry : manifest.at("files")) listed.insert(entry.at("path").get<std::string>());
    std::set<std::string> expected = files;
    expected.erase("manifest.json");
    expected.erase("timings.json");
    CHECK(listed == expected);
}

}  // namespace

TEST_CASE("the Cornell Box bakes to identical stats.json and manifest.json with 1 and 2 threads") {
    checkIdenticalWithOneAndTwoThreads("cornell_box");
}

TEST_CASE("the paper's shadow scene (occlusion) bakes to identical stats.json and manifest.json with 1 and 2 threads") {
    checkIdenticalWithOneAndTwoThreads("paper/shadow");
}
