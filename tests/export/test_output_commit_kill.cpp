// A commit into an existing folder killed after any number of its renames (and the undoing of
// it killed too): the next bake finds the older bake whole, its manifest true to the files,
// and no journal or staging directory left.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "export/hash.h"
#include "export/manifest.h"
#include "export/output_transaction.h"
#include "temp_files.h"

using namespace radbake;
namespace fs = std::filesystem;
using testfs::listing;
using testfs::readBytes;
using testfs::TempDir;

namespace {

constexpr int kKilled = 42;

using Files = std::map<std::string, std::string>;

// One bake as the pipeline writes it: its files, then a manifest of them; the older files
// of `retire` that it does not write are retired.
bool commitBake(OutputTransaction& transaction, const Files& files, const std::vector<std::string>& retire) {
    Diagnostics diagnostics;
    if (!transaction.begin(diagnostics)) return false;
    for (const std::string& name : retire) transaction.retire(name);
    for (const auto& [name, content] : files)
        if (!writeFileBytes(transaction.stage(name), content, diagnostics)) return false;
    return writeManifest(transaction.stage("manifest.json"), transaction.stagingDir(), transaction.staged(), "radbake",
                         "room", diagnostics) &&
           transaction.commit(diagnostics);
}

const Files kOld = {{"room.glb", "old glb"},
                    {"room.ply", "the same ply"},
                    {"lightmaps/room_0.exr", "old exr 0"},
                    {"lightmaps/room_1.exr", "old exr 1"},
                    {"probes.csv", "old probes"}};
const Files kNew = {{"room.glb", "new glb"},
                    {"room.ply", "the same ply"},
                    {"lightmaps/room_0.exr", "new exr 0"},
                    {"preview/room_view.png", "new preview"}};
const std::vector<std::string> kOldNames = {"room.glb", "room.ply", "lightmaps/room_0.exr", "lightmaps/room_1.exr",
                                            "probes.csv", "manifest.json"};

// In a child process: begins a transaction on `out` whose renames die at rename `kill_at`
// (0: never), then runs `work` on it. The child's exit status: kKilled when it died there,
// 0 when `work` succeeded, 1 when it failed.
template <typename Work>
int inChild(const fs::path& out, size_t kill_at, Work work) {
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        OutputTransaction transaction(out);
        transaction.setRenameHookForTesting([kill_at](size_t renames) {
            if (renames == kill_at) ::_exit(kKilled);  // no destructor, no clean-up: a kill
        });
        ::_exit(work(transaction) ? 0 : 1);
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    REQUIRE(WIFEXITED(status));
    return WEXITSTATUS(status);
}

// Every file the manifest lists exists with the listed size and SHA-256.
void checkManifestTrue(const fs::path& out) {
    const nlohmann::json manifest = nlohmann::json::parse(readBytes(out / "manifest.json"));
    for (const nlohmann::json& entry : manifest.at("files")) {
        const std::string path = entry.at("path").get<std::string>();
        CAPTURE(path);
        REQUIRE(fs::is_regular_file(out / path));
        CHECK(fs::file_size(out / path) == entry.at("bytes").get<uintmax_t>());
        CHECK(sha256Hex(readBytes(out / path)) == entry.at("sha256").get<std::string>());
    }
}

}  // namespace

TEST_CASE("a commit killed after any number of renames: the next bake restores the older bake whole") {
    const TempDir tmp;
    size_t renames_in_commit = 0;
    for (size_t kill_at = 1;; ++kill_at) {
        CAPTURE(kill_at);
        const fs::path out = tmp.path / ("out" + std::to_string(kill_at));
        {
            OutputTransaction first(out);
            REQUIRE(commitBake(first, kOld, {}));
        }
        const auto before = listing(out);
        const int status = inChild(out, kill_at, [](OutputTransaction& t) { return commitBake(t, kNew, kOldNames); });
        if (status == 0) {  // past the last rename: the commit completed
            renames_in_commit = kill_at - 1;
            const auto after = listing(out);
            CHECK(after.count("lightmaps/room_1.exr") == 0);
            CHECK(after.count("probes.csv") == 0);
            CHECK(after.at("preview/room_view.png") == "new preview");
            checkManifestTrue(out);
            break;
        }
        REQUIRE(status == kKilled);
        CHECK(listing(out) != before);  // the kill left a mix (or a journal): something to undo

        // The next bake locks the folder and undoes the half commit before anything else.
        Diagnostics diagnostics;
        {
            OutputTransaction next(out);
            REQUIRE(next.begin(diagnostics));
        }
        CHECK(listing(out) == before);
        checkManifestTrue(out);
        REQUIRE(kill_at < 64);
    }
    // Two retired files, three replaced (two renames each), one added, the third unchanged.
    CHECK(renames_in_commit == 9);
}

TEST_CASE("the undoing of a killed commit, killed in turn, is finished by the bake after") {
    const TempDir tmp;
    for (size_t kill_at = 1; kill_at <= 9; ++kill_at) {
        for (size_t undo_kill_at = 1;; ++undo_kill_at) {
            CAPTURE(kill_at);
            CAPTURE(undo_kill_at);
            const fs::path out = tmp.path / ("out" + std::to_string(kill_at) + "_" + std::to_string(undo_kill_at));
            {
                OutputTransaction first(out);
                REQUIRE(commitBake(first, kOld, {}));
            }
            const auto before = listing(out);
            REQUIRE(inChild(out, kill_at, [](OutputTransaction& t) { return commitBake(t, kNew, kOldNames); }) ==
                    kKilled);
            const int status = inChild(out, undo_kill_at, [](OutputTransaction& t) {
                Diagnostics diagnostics;
                return t.begin(diagnostics);
            });
            Diagnostics diagnostics;
            {
                OutputTransaction next(out);
                REQUIRE(next.begin(diagnostics));
            }
            CHECK(listing(out) == before);
            if (status == 0) break;  // the undo had fewer renames than undo_kill_at
            REQUIRE(status == kKilled);
        }
    }
}

TEST_CASE("a journal that is not ours, or whose backups are gone, stops the bake and is kept") {
    const TempDir tmp;
    const fs::path out = tmp.path / "out";
    {
        OutputTransaction first(out);
        REQUIRE(commitBake(first, kOld, {}));
    }
    for (const std::string journal : {std::string("not json"),
                                      std::string(R"({"staging": "../../etc", "made_dirs": [], "steps": []})"),
                                      std::string(R"({"staging": ".radbake-tmp-gone", "made_dirs": [], "steps": []})")}) {
        CAPTURE(journal);
        std::ofstream(out / ".radbake-journal", std::ios::binary) << journal;
        const auto before = listing(out);
        Diagnostics diagnostics;
        {
            OutputTransaction next(out);
            CHECK_FALSE(next.begin(diagnostics));
        }
        REQUIRE(diagnostics.errorCount() == 1);
        CHECK(diagnostics.all()[0].message.find("interrupted commit") != std::string::npos);
        CHECK(listing(out) == before);
    }
}
