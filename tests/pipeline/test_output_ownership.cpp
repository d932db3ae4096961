// A bake writes only what it owns (issue 32): files its folder's last bake did not write
// are kept, another scene's bake is refused whole, and a folder another bake holds is refused
// before any work.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "export/hash.h"
#include "radbake.h"
#include "../export/temp_files.h"
#include "../radiosity/test_scenes.h"

using namespace radbake;
using namespace radbake::test;
using testfs::readBytes;
using testfs::TempDir;
namespace fs = std::filesystem;

namespace {

// A lamp over a floor: a fast bake with a lightmap atlas.
Scene lampScene(const std::string& name) {
    Scene scene;
    scene.name = name;
    const uint32_t grey = addMaterial(scene, Vec3(0.6f), Vec3(0.0f));
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(5.0f));
    addQuad(scene, grey, {0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
    addQuad(scene, lamp, {0.3f, 0.3f, 1.0f}, {0.3f, 0.7f, 1.0f}, {0.7f, 0.7f, 1.0f}, {0.7f, 0.3f, 1.0f});
    return scene;
}

BakeOptions draft(bool lightmaps, bool probes, bool preview) {
    BakeOptions result = BakeOptions::forQuality(Quality::Draft);
    result.threading.threads = 1;
    result.lightmaps.enabled = lightmaps;
    result.preview = preview;
    if (probes) {
        Probe probe;
        probe.position = {0.5, 0.5, 0.01};
        probe.normal = {0.0, 0.0, 1.0};
        result.probes = std::vector<Probe>{probe};
    }
    return result;
}

// The same lamp over a floor as a VRML97 file, for the calls that read a scene.
std::string writeLampFile(const fs::path& path) {
    std::ofstream(path, std::ios::binary)
        << "#VRML V2.0 utf8\n"
           "Shape { appearance Appearance { material Material { diffuseColor 0.6 0.6 0.6 } }\n"
           "  geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 1 0 0, 1 0 1, 0 0 1] }\n"
           "    coordIndex [0 3 2 1 -1] } }\n"
           "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 5 5 5 } }\n"
           "  geometry IndexedFaceSet { coord Coordinate { point [0.3 1 0.3, 0.7 1 0.3, 0.7 1 0.7, 0.3 1 0.7] }\n"
           "    coordIndex [0 1 2 3 -1] } }\n";
    REQUIRE(fs::is_regular_file(path));
    return path.string();
}

// A progress sink that records every phase begun: a refused bake begins none.
struct PhaseLog {
    std::vector<std::string> begun;
    void attach(Progress& progress) {
        progress.setSink([this](const ProgressEvent& event) {
            if (!event.phase_done && (begun.empty() || begun.back() != event.phase)) begun.emplace_back(event.phase);
        });
    }
};

// A bake in memory: the scene's name is what its outputs are called.
Bake bakeScene(const std::string& name, const BakeOptions& bake_options) {
    Progress progress(false);
    Diagnostics diagnostics;
    Bake result = bake(lampScene(name), bake_options, progress, diagnostics);
    REQUIRE(result.ok());
    return result;
}

// name -> content of every regular file under `dir`.
std::map<std::string, std::string> files(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        if (entry.is_regular_file()) out[fs::relative(entry.path(), dir).generic_string()] = readBytes(entry.path());
    return out;
}

void put(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
    REQUIRE(fs::is_regular_file(path));
}

}  // namespace

TEST_CASE("files no bake of ours wrote survive in lightmaps/, preview/ and beside, with lightmaps or without") {
    const TempDir tmp;
    const fs::path out = tmp.path / "out";
    const std::map<std::string, std::string> users = {{"lightmaps/README", "how the atlases are made"},
                                                      {"lightmaps/level2_0.exr", "another level's atlas"},
                                                      {"preview/README", "screenshots go here"},
                                                      {"probes.csv", "the user's own probe list"}};
    for (const auto& [name, text] : users) put(out / name, text);
    const Bake with_all = bakeScene("room", draft(true, false, true));
    const Bake bare = bakeScene("room", draft(false, false, false));
    for (const Bake* bake : {&with_all, &bare, &with_all}) {
        CAPTURE(bake->options.lightmaps.enabled);
        Diagnostics diagnostics;
        REQUIRE(writeBake(*bake, out, diagnostics));
        const auto now = files(out);
        for (const auto& [name, text] : users) CHECK_MESSAGE((now.count(name) == 1 && now.at(name) == text), name);
        CHECK(now.count("lightmaps/room_0.exr") == (bake->options.lightmaps.enabled ? 1 : 0));
        CHECK(now.count("lightmaps/room_0.png") == (bake->options.lightmaps.enabled ? 1 : 0));
        CHECK(now.count("preview/room_view.png") == (bake->options.preview ? 1 : 0));
    }
}

TEST_CASE("probes.csv our last bake wrote goes with a bake without probes; one we did not write stays") {
    const TempDir tmp;
    const fs::path out = tmp.path / "out";
    Diagnostics diagnostics;
    REQUIRE(writeBake(bakeScene("room", draft(false, true, false)), out, diagnostics));
    REQUIRE(fs::is_regular_file(out / "probes.csv"));
    REQUIRE(writeBake(bakeScene("room", draft(false, false, false)), out, diagnostics));
    CHECK_FALSE(fs::exists(out / "probes.csv"));  // ours, and now stale
    put(out / "probes.csv", "the user's");
    REQUIRE(writeBake(bakeScene("room", draft(false, false, false)), out, diagnostics));
    CHECK(readBytes(out / "probes.csv") == "the user's");
    CHECK_FALSE(diagnostics.hasErrors());
}

TEST_CASE("a second scene baked into a folder is refused, the first's bake kept whole and its manifest true") {
    const TempDir tmp;
    const fs::path out = tmp.path / "out";
    Diagnostics diagnostics;
    REQUIRE(writeBake(bakeScene("room", draft(true, true, false)), out, diagnostics));
    const auto before = files(out);
    Diagnostics second;
    CHECK_FALSE(writeBake(bakeScene("hall", draft(false, false, false)), out, second));
    REQUIRE(second.errorCount() == 1);
    CHECK(second.all()[0].message.find("another scene ('room')") != std::string::npos);
    CHECK(files(out) == before);

    // Refused before the scene is read: a scene that does not exist is never opened.
    Progress progress(false);
    PhaseLog log;
    log.attach(progress);
    Diagnostics early;
    CHECK_FALSE(bakeInto((tmp.path / "hall.wrl").string(), out, draft(false, false, false), progress, early));
    REQUIRE(early.errorCount() == 1);
    CHECK(early.all()[0].message.find("another scene ('room')") != std::string::npos);
    CHECK(log.begun.empty());
    CHECK(files(out) == before);

    // The same scene again replaces its own bake (same name: the same scene as far as files go).
    REQUIRE(writeBake(bakeScene("room", draft(false, false, false)), out, diagnostics));
    CHECK(files(out).count("lightmaps/room_0.exr") == 0);
}

TEST_CASE("a folder whose manifest is not radbake's, or names another scene without saying so, is refused") {
    const TempDir tmp;
    const fs::path out = tmp.path / "out";
    const Bake room = bakeScene("room", draft(false, false, false));
    put(out / "manifest.json", "{\"name\": \"a web app's manifest\"}");
    Diagnostics diagnostics;
    CHECK_FALSE(writeBake(room, out, diagnostics));
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].message.find("cannot tell which files of this folder are radbake's") !=
          std::string::npos);
    CHECK(readBytes(out / "manifest.json") == "{\"name\": \"a web app's manifest\"}");

    // An older radbake's manifest has no "scene": its glb names the scene.
    put(out / "manifest.json", R"({"generator": "radbake 0.0.9", "excluded": ["timings.json"],
                                   "files": [{"path": "hall.glb", "bytes": 1, "sha256": ""}]})");
    put(out / "hall.glb", "x");
    Diagnostics older;
    CHECK_FALSE(writeBake(room, out, older));
    CHECK(older.errorCount() == 1);
    fs::remove(out / "hall.glb");
    put(out / "manifest.json", R"({"generator": "radbake 0.0.9", "files": [{"path": "room.glb"}, {"path": "room.ply"}]})");
    put(out / "room.ply", "an older room's ply");
    Diagnostics ours;
    REQUIRE(writeBake(room, out, ours));
    CHECK(readBytes(out / "room.ply") != "an older room's ply");
}

TEST_CASE("a folder another bake holds is refused before the scene is read, also one that does not exist yet") {
    const TempDir tmp;
    const std::string scene = writeLampFile(tmp.path / "lamp.wrl");
    for (const bool exists : {false, true}) {
        CAPTURE(exists);
        const fs::path out = tmp.path / (exists ? "old" : "new");
        if (exists) fs::create_directory(out);
        Diagnostics holder_diagnostics;
        {
            OutputTransaction holder(out);  // another bake, between its begin and its commit
            REQUIRE(holder.begin(holder_diagnostics));
            Progress progress(false);
            PhaseLog log;
            log.attach(progress);
            Diagnostics diagnostics;
            Bake result;
            CHECK_FALSE(bakeInto(scene, out, draft(false, false, false), progress, diagnostics, &result));
            REQUIRE(diagnostics.errorCount() == 1);
            CHECK(diagnostics.all()[0].message.find("another bake is writing into this directory") !=
                  std::string::npos);
            CHECK(log.begun.empty());  // no import, no solve
            CHECK(fs::exists(out) == exists);
        }
        // Once the other is done, the bake goes ahead.
        Progress progress(false);
        Diagnostics diagnostics;
        Bake result;
        WrittenBake written;
        REQUIRE(bakeInto(scene, out, draft(true, false, false), progress, diagnostics, &result, &written));
        CHECK(result.ok());
        CHECK(fs::is_regular_file(out / "lamp.glb"));
        CHECK(fs::is_regular_file(out / "lightmaps" / "lamp_0.exr"));
        CHECK(written.files.size() == files(out).size());
    }
}

TEST_CASE("sceneNameOf names a scene file's outputs as importScene names the scene") {
    const TempDir tmp;
    for (const char* file : {"room.wrl", "furnace_rho_0.99.wrl", "two words.wrl"}) {
        CAPTURE(file);
        const std::string path = writeLampFile(tmp.path / file);
        Diagnostics diagnostics;
        const std::optional<Scene> scene = importScene(path, ImportOptions{}, diagnostics);
        REQUIRE(scene);
        CHECK(sceneNameOf(path) == scene->name);
    }
    CHECK(sceneNameOf("levels/castle.wrl.gz") == "castle");
    CHECK(sceneNameOf("levels/.wrl") == ".wrl");
}
