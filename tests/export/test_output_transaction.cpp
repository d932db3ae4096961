// The output transaction: outputs appear only on commit; a failure part-way leaves OUTDIR
// (new or existing) exactly as it was and no staging directory behind.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "export/output_transaction.h"

using namespace radbake;
namespace fs = std::filesystem;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        std::string pattern = (fs::temp_directory_path() / "radbake-test-XXXXXX").string();
        REQUIRE(mkdtemp(pattern.data()) != nullptr);
        path = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// name -> content of every regular file under `dir`, and "name/" for directories.
std::map<std::string, std::string> listing(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        const std::string name = fs::relative(entry.path(), dir).string();
        out[entry.is_directory() ? name + "/" : name] = entry.is_directory() ? "" : slurp(entry.path());
    }
    return out;
}

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
