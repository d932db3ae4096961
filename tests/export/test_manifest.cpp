// manifest.json parsed back: every file once, sorted, with its true size and SHA-256.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "export/hash.h"
#include "export/manifest.h"
#include "export/output_transaction.h"
#include "temp_files.h"

using namespace radbake;
namespace fs = std::filesystem;
using testfs::readBytes;
using testfs::TempDir;

namespace {

}  // namespace

TEST_CASE("the manifest lists each output once, sorted, with its size and SHA-256") {
    TempDir tmp;
    fs::create_directories(tmp.path / "lightmaps");
    const std::map<std::string, std::string> files = {
        {"room.glb", "glTF bytes"},
        {"lightmaps/room_0.exr", std::string(100000, 'x')},
        {"lightmaps/room_1.exr", "abc"},
        {"stats.json", ""},
    };
    Diagnostics diagnostics;
    for (const auto& [name, content] : files) REQUIRE(writeFileBytes(tmp.path / name, content, diagnostics));
    const fs::path manifest_path = tmp.path / "manifest.json";
    // Unsorted, one repeated, and the manifest itself listed as OutputTransaction::staged() may.
    REQUIRE(writeManifest(manifest_path, tmp.path,
                          {"stats.json", "room.glb", "manifest.json", "lightmaps/room_1.exr", "lightmaps/room_0.exr",
                           "room.glb"},
                          "radbake 9.9 \"test\"", "room", diagnostics));
    CHECK(diagnostics.all().empty());

    const nlohmann::json manifest = nlohmann::json::parse(readBytes(manifest_path));
    CHECK(manifest.at("generator").get<std::string>() == "radbake 9.9 \"test\"");
    CHECK(manifest.at("scene").get<std::string>() == "room");
    const nlohmann::json& listed = manifest.at("files");
    REQUIRE(listed.size() == 4);
    const char* const expected_order[] = {"lightmaps/room_0.exr", "lightmaps/room_1.exr", "room.glb", "stats.json"};
    for (size_t i = 0; i < 4; ++i) {
        CAPTURE(i);
        const std::string path = listed.at(i).at("path").get<std::string>();
        CHECK(path == expected_order[i]);
        CHECK(listed.at(i).at("bytes").get<size_t>() == files.at(path).size());
        CHECK(listed.at(i).at("sha256").get<std::string>() == sha256Hex(files.at(path)));
        CHECK(listed.at(i).size() == 3);
    }
    CHECK(listed.at(1).at("sha256").get<std::string>() == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    CHECK(listed.at(3).at("sha256").get<std::string>() == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST_CASE("the manifest leaves timings.json out, says so, and does not change with it") {
    TempDir tmp;
    Diagnostics diagnostics;
    fs::create_directories(tmp.path / "sub");
    REQUIRE(writeFileBytes(tmp.path / "stats.json", "{}", diagnostics));
    REQUIRE(writeFileBytes(tmp.path / "timings.json", "{\"seconds\": 1}", diagnostics));
    REQUIRE(writeFileBytes(tmp.path / "sub" / "timings.json", "not the bake's", diagnostics));
    const std::vector<std::string> outputs = {"timings.json", "stats.json", "./timings.json", "sub/timings.json"};
    REQUIRE(writeManifest(tmp.path / "manifest.json", tmp.path, outputs, "radbake", "room", diagnostics));
    const std::string first = readBytes(tmp.path / "manifest.json");
    const nlohmann::json manifest = nlohmann::json::parse(first);
    CHECK(manifest.at("excluded") == nlohmann::json::array({"timings.json"}));
    REQUIRE(manifest.at("files").size() == 2);  // only the top-level timings.json is the bake's
    CHECK(manifest.at("files").at(0).at("path").get<std::string>() == "stats.json");
    CHECK(manifest.at("files").at(1).at("path").get<std::string>() == "sub/timings.json");

    REQUIRE(writeFileBytes(tmp.path / "timings.json", "{\"seconds\": 2.5}", diagnostics));
    REQUIRE(writeManifest(tmp.path / "manifest.json", tmp.path, outputs, "radbake", "room", diagnostics));
    CHECK(readBytes(tmp.path / "manifest.json") == first);
    CHECK(diagnostics.all().empty());
}

TEST_CASE("a manifest of nothing is valid JSON, and a missing output is reported at its path") {
    TempDir tmp;
    Diagnostics diagnostics;
    const fs::path manifest_path = tmp.path / "manifest.json";
    REQUIRE(writeManifest(manifest_path, tmp.path, {}, "radbake", "room", diagnostics));
    const nlohmann::json manifest = nlohmann::json::parse(readBytes(manifest_path));
    CHECK(manifest.at("files").size() == 0);
    CHECK(manifest.at("files").is_array());

    fs::remove(manifest_path);
    CHECK_FALSE(writeManifest(manifest_path, tmp.path, {"lightmaps/absent.exr"}, "radbake", "room", diagnostics));
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].location.file == (tmp.path / "lightmaps/absent.exr").string());
    CHECK_FALSE(fs::exists(manifest_path));
}

TEST_CASE("a manifest written through a transaction describes the committed files") {
    TempDir tmp;
    const fs::path out = tmp.path / "room";
    Diagnostics diagnostics;
    {
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        REQUIRE(writeFileBytes(transaction.stage("room.glb"), "glb", diagnostics));
        REQUIRE(writeFileBytes(transaction.stage("lightmaps/room_0.exr"), "exr", diagnostics));
        REQUIRE(writeManifest(transaction.stage("manifest.json"), transaction.stagingDir(), transaction.staged(),
                              "radbake", "room", diagnostics));
        REQUIRE(transaction.commit(diagnostics));
    }
    const nlohmann::json manifest = nlohmann::json::parse(readBytes(out / "manifest.json"));
    REQUIRE(manifest.at("files").size() == 2);
    for (size_t i = 0; i < 2; ++i) {
        const std::string path = manifest.at("files").at(i).at("path").get<std::string>();
        CHECK(manifest.at("files").at(i).at("sha256").get<std::string>() == sha256Hex(readBytes(out / path)));
    }
}
