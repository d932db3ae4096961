// The output transaction: outputs appear only on commit; a failure part-way leaves OUTDIR
// (new or existing) exactly as it was and no staging directory behind.
#include <doctest/doctest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "export/output_transaction.h"
#include "temp_files.h"

using namespace radbake;
namespace fs = std::filesystem;
using testfs::listing;
using testfs::readBytes;
using testfs::TempDir;

namespace {

void put(const fs::path& p, const std::string& content) { std::ofstream(p, std::ios::binary) << content; }

}  // namespace

TEST_CASE("a committed transaction creates OUTDIR and its missing parents, with no leftovers") {
    TempDir tmp;
    const fs::path out = tmp.path / "baked" / "room";
    Diagnostics diagnostics;
    {
        OutputTransaction transaction(out.string() + "/");  // a trailing slash names the same directory
        REQUIRE(transaction.begin(diagnostics));
        CHECK_FALSE(fs::exists(out));  // nothing visible before the commit
        CHECK(transaction.stagingDir().parent_path() == out.parent_path());
        CHECK(writeFileBytes(transaction.stage("a.glb"), "AAAA", diagnostics));
        CHECK(writeFileBytes(transaction.stage("stats.json"), "{}", diagnostics));
        REQUIRE(transaction.commit(diagnostics));
    }
    CHECK(diagnostics.all().empty());
    const std::map<std::string, std::string> expected = {
        {"baked/", ""}, {"baked/room/", ""}, {"baked/room/a.glb", "AAAA"}, {"baked/room/stats.json", "{}"}};
    CHECK(listing(tmp.path) == expected);
}

TEST_CASE("a write failing part-way leaves a new OUTDIR absent and removes the parents it made") {
    TempDir tmp;
    const fs::path out = tmp.path / "deep" / "er" / "room";
    Diagnostics diagnostics;
    {
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        CHECK(writeFileBytes(transaction.stage("a.glb"), "AAAA", diagnostics));
        // The second output's staged name leads to a full device: it fails mid-write.
        const fs::path full = transaction.stage("room.ply");
        fs::create_symlink("/dev/full", full);
        CHECK_FALSE(writeFileBytes(full, std::string(1 << 16, 'x'), diagnostics));
        // The bake gives up here: the transaction is destroyed without commit.
    }
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].message == "cannot write file: No space left on device");
    CHECK(listing(tmp.path).empty());
}

TEST_CASE("a failed bake leaves an existing OUTDIR's older files untouched") {
    TempDir tmp;
    const fs::path out = tmp.path / "room";
    fs::create_directory(out);
    put(out / "room.glb", "old glb");
    put(out / "room.ply", "old ply");
    put(out / "notes.txt", "the user's own file");
    put(out / "probes.csv", "old probes");
    const auto before = listing(tmp.path);
    Diagnostics diagnostics;
    {
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        CHECK(writeFileBytes(transaction.stage("room.glb"), "new glb", diagnostics));
        // The next output cannot be created: its staged name is taken by a directory.
        const fs::path blocked = transaction.stage("room.ply");
        fs::create_directory(blocked);
        CHECK_FALSE(writeFileBytes(blocked, "new ply", diagnostics));
        transaction.retire("probes.csv");  // not committed: the old probes stay too
    }
    CHECK(diagnostics.errorCount() == 1);
    CHECK(listing(tmp.path) == before);
}

TEST_CASE("committing into an existing OUTDIR replaces our outputs and keeps other files") {
    TempDir tmp;
    const fs::path out = tmp.path / "room";
    fs::create_directory(out);
    put(out / "room.glb", "old glb");
    put(out / "probes.csv", "old probes");
    put(out / "notes.txt", "the user's own file");
    Diagnostics diagnostics;
    {
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        CHECK(transaction.stagingDir().parent_path() == out);  // stays inside the existing OUTDIR
        CHECK(writeFileBytes(transaction.stage("room.glb"), "new glb", diagnostics));
        CHECK(writeFileBytes(transaction.stage("stats.json"), "{}", diagnostics));
        transaction.retire("probes.csv");  // this bake has no probes: the old file goes
        transaction.retire("absent.csv");  // nothing to remove: fine
        REQUIRE(transaction.commit(diagnostics));
    }
    const std::map<std::string, std::string> expected = {
        {"room/", ""}, {"room/room.glb", "new glb"}, {"room/notes.txt", "the user's own file"}, {"room/stats.json", "{}"}};
    CHECK(listing(tmp.path) == expected);
}

TEST_CASE("OUTDIR that is a file is refused before anything is written") {
    TempDir tmp;
    put(tmp.path / "room", "a file");
    Diagnostics diagnostics;
    OutputTransaction transaction(tmp.path / "room");
    CHECK_FALSE(transaction.begin(diagnostics));
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].message == "output path exists and is not a directory");
    CHECK(listing(tmp.path).size() == 1);
}

TEST_CASE("a first bake with lightmaps creates OUTDIR with its lightmaps/ sub-directory") {
    TempDir tmp;
    const fs::path out = tmp.path / "room";
    Diagnostics diagnostics;
    {
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        CHECK(writeFileBytes(transaction.stage("room.glb"), "glb", diagnostics));
        CHECK(writeFileBytes(transaction.stage("lightmaps/room_0.exr"), "exr0", diagnostics));
        CHECK(writeFileBytes(transaction.stage("lightmaps/room_1.exr"), "exr1", diagnostics));
        transaction.stage("room.glb");  // staged twice: listed once
        CHECK(transaction.staged() ==
              std::vector<std::string>{"room.glb", "lightmaps/room_0.exr", "lightmaps/room_1.exr"});
        REQUIRE(transaction.commit(diagnostics));
    }
    CHECK(diagnostics.all().empty());
    const std::map<std::string, std::string> expected = {{"room/", ""},
                                                         {"room/room.glb", "glb"},
                                                         {"room/lightmaps/", ""},
                                                         {"room/lightmaps/room_0.exr", "exr0"},
                                                         {"room/lightmaps/room_1.exr", "exr1"}};
    CHECK(listing(tmp.path) == expected);
}

TEST_CASE("a re-bake with fewer atlases retires only the older files it is told of; the rest stay") {
    TempDir tmp;
    const fs::path out = tmp.path / "room";
    fs::create_directories(out / "lightmaps" / "user");
    put(out / "room.glb", "old glb");
    put(out / "notes.txt", "the user's own file");
    for (int k = 0; k < 3; ++k) put(out / "lightmaps" / ("room_" + std::to_string(k) + ".exr"), "old exr");
    put(out / "lightmaps" / "README", "the user's own file, beside our atlases");
    put(out / "lightmaps" / "user" / "keep.txt", "inside a sub-directory: not ours");
    Diagnostics diagnostics;
    {
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        for (int k = 0; k < 3; ++k) transaction.retire("lightmaps/room_" + std::to_string(k) + ".exr");
        CHECK(writeFileBytes(transaction.stage("room.glb"), "new glb", diagnostics));
        CHECK(writeFileBytes(transaction.stage("lightmaps/room_0.exr"), "new exr", diagnostics));
        REQUIRE(transaction.commit(diagnostics));
    }
    CHECK(diagnostics.all().empty());
    std::map<std::string, std::string> expected = {{"room/", ""},
                                                   {"room/room.glb", "new glb"},
                                                   {"room/notes.txt", "the user's own file"},
                                                   {"room/lightmaps/", ""},
                                                   {"room/lightmaps/room_0.exr", "new exr"},
                                                   {"room/lightmaps/README", "the user's own file, beside our atlases"},
                                                   {"room/lightmaps/user/", ""},
                                                   {"room/lightmaps/user/keep.txt", "inside a sub-directory: not ours"}};
    CHECK(listing(tmp.path) == expected);

    // No lightmaps: the last atlas goes; the directory stays only while it holds something else.
    for (const bool readme : {true, false}) {
        CAPTURE(readme);
        fs::remove_all(out / "lightmaps" / "user");
        if (!readme) fs::remove(out / "lightmaps" / "README");
        put(out / "lightmaps" / "room_0.exr", "new exr");
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        transaction.retire("lightmaps/room_0.exr");
        CHECK(writeFileBytes(transaction.stage("room.glb"), "third glb", diagnostics));
        REQUIRE(transaction.commit(diagnostics));
        expected = {{"room/", ""}, {"room/room.glb", "third glb"}, {"room/notes.txt", "the user's own file"}};
        if (readme) {
            expected["room/lightmaps/"] = "";
            expected["room/lightmaps/README"] = "the user's own file, beside our atlases";
        }
        CHECK(listing(tmp.path) == expected);
    }
    CHECK(diagnostics.all().empty());
}

TEST_CASE("retire() removes only a regular file reached through real directories") {
    TempDir tmp;
    const fs::path out = tmp.path / "room", elsewhere = tmp.path / "elsewhere";
    fs::create_directories(out);
    fs::create_directories(elsewhere / "lightmaps");
    put(elsewhere / "lightmaps" / "room_0.exr", "not in the folder");
    put(elsewhere / "target.txt", "a link's target");
    fs::create_directory_symlink(elsewhere / "lightmaps", out / "lightmaps");
    fs::create_symlink(elsewhere / "target.txt", out / "link.txt");
    fs::create_directory(out / "dir.exr");
    const auto before = listing(tmp.path);
    Diagnostics diagnostics;
    OutputTransaction transaction(out);
    REQUIRE(transaction.begin(diagnostics));
    for (const char* name : {"lightmaps/room_0.exr", "link.txt", "dir.exr", "absent.exr"}) transaction.retire(name);
    REQUIRE(writeFileBytes(transaction.stage("room.glb"), "glb", diagnostics));
    REQUIRE(transaction.commit(diagnostics));
    auto expected = before;
    expected["room/room.glb"] = "glb";
    CHECK(listing(tmp.path) == expected);
}

TEST_CASE("an abandoned bake with lightmaps leaves an existing OUTDIR untouched and no staging behind") {
    TempDir tmp;
    const fs::path out = tmp.path / "room";
    fs::create_directories(out / "lightmaps");
    put(out / "room.glb", "old glb");
    put(out / "lightmaps" / "room_0.exr", "old exr 0");
    put(out / "lightmaps" / "room_1.exr", "old exr 1");
    const auto before = listing(tmp.path);
    Diagnostics diagnostics;
    {
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        transaction.retire("lightmaps/room_1.exr");
        CHECK(writeFileBytes(transaction.stage("lightmaps/room_0.exr"), "new exr", diagnostics));
        CHECK(fs::is_regular_file(transaction.stagingDir() / "lightmaps" / "room_0.exr"));
        // The bake fails before commit.
    }
    CHECK(listing(tmp.path) == before);

    // A new OUTDIR: abandoning leaves nothing at all.
    const fs::path fresh = tmp.path / "fresh" / "room";
    {
        OutputTransaction transaction(fresh);
        REQUIRE(transaction.begin(diagnostics));
        CHECK(writeFileBytes(transaction.stage("lightmaps/a/room_0.exr"), "new exr", diagnostics));
    }
    CHECK(listing(tmp.path) == before);
    CHECK(diagnostics.all().empty());
}

TEST_CASE("a commit failing part-way restores replaced and retired files in sub-directories") {
    TempDir tmp;
    const fs::path out = tmp.path / "room";
    fs::create_directories(out / "lightmaps");
    put(out / "room.glb", "old glb");
    put(out / "lightmaps" / "room_0.exr", "old exr 0");
    put(out / "lightmaps" / "room_2.exr", "old exr 2");
    put(out / "extra", "a file where the last output needs a directory");
    const auto before = listing(tmp.path);
    Diagnostics diagnostics;
    {
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        transaction.retire("lightmaps/room_2.exr");
        CHECK(writeFileBytes(transaction.stage("room.glb"), "new glb", diagnostics));
        CHECK(writeFileBytes(transaction.stage("lightmaps/room_0.exr"), "new exr 0", diagnostics));
        CHECK(writeFileBytes(transaction.stage("lightmaps/new/room_1.exr"), "in a new directory", diagnostics));
        CHECK(writeFileBytes(transaction.stage("extra/room_1.exr"), "cannot land", diagnostics));
        CHECK_FALSE(transaction.commit(diagnostics));
    }
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].location.file == (out / "extra").string());
    CHECK(diagnostics.all()[0].message == "cannot create output directory: a file is in the way");
    CHECK(listing(tmp.path) == before);  // room_2 back, room_0 and the glb old again, lightmaps/new/ gone
}

TEST_CASE("output names that could leave OUTDIR are refused at commit") {
    for (const char* bad : {"../escape.glb", "/tmp/abs.glb", "lightmaps/../../x.exr", "a//b.exr", "./a.glb", ""}) {
        CAPTURE(bad);
        TempDir tmp;
        const fs::path out = tmp.path / "room";
        Diagnostics diagnostics;
        {
            OutputTransaction transaction(out);
            REQUIRE(transaction.begin(diagnostics));
            const fs::path scratch = transaction.stage(bad);
            CHECK(scratch.parent_path() == transaction.stagingDir());  // writing it harms nothing
            CHECK(writeFileBytes(scratch, "x", diagnostics));
            CHECK(transaction.staged().empty());
            CHECK_FALSE(transaction.commit(diagnostics));
        }
        REQUIRE(diagnostics.errorCount() == 1);
        CHECK(diagnostics.all()[0].message ==
              "internal: output name '" + std::string(bad) + "' is not a relative path inside the output directory");
        CHECK(listing(tmp.path).empty());
        CHECK_FALSE(fs::exists(tmp.path.parent_path() / "escape.glb"));
    }
    Diagnostics diagnostics;
    TempDir tmp;
    OutputTransaction transaction(tmp.path / "room");
    REQUIRE(transaction.begin(diagnostics));
    transaction.retire("../x");  // a file beside OUTDIR
    CHECK_FALSE(transaction.commit(diagnostics));
    CHECK(diagnostics.errorCount() == 1);
}

TEST_CASE("a bake killed by SIGTERM leaves no staging directory, even with files in sub-directories") {
    TempDir tmp;
    const fs::path out = tmp.path / "room";
    fs::create_directory(out);
    put(out / "room.glb", "old glb");
    const auto before = listing(tmp.path);
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        // The child stages outputs in sub-directories and is killed before it commits.
        cleanUpStagingOnSignals();
        Diagnostics diagnostics;
        OutputTransaction transaction(out);
        if (!transaction.begin(diagnostics)) _exit(3);
        writeFileBytes(transaction.stage("room.glb"), "new glb", diagnostics);
        writeFileBytes(transaction.stage("lightmaps/room_0.exr"), "exr", diagnostics);
        writeFileBytes(transaction.stage("preview/deep/room_view.png"), "png", diagnostics);
        ::raise(SIGTERM);
        _exit(4);  // not reached: the handler re-raises with the default action
    }
    int status = 0;
    REQUIRE(waitpid(child, &status, 0) == child);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == SIGTERM);
    CHECK(listing(tmp.path) == before);
}
