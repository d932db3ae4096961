// The output folder as a content build sees it: the user's umask, what a killed bake leaves,
// two bakes racing for one folder, and outputs that did not change keeping their file.
#include <doctest/doctest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "export/output_transaction.h"
#include "temp_files.h"

using namespace radbake;
namespace fs = std::filesystem;
using testfs::TempDir;

namespace {

bool stageText(OutputTransaction& transaction, const std::string& name, const std::string& text,
               Diagnostics& diagnostics) {
    return writeFileBytes(transaction.stage(name), text, diagnostics);
}

// Names in `dir` starting with `prefix`.
int countPrefixed(const fs::path& dir, const std::string& prefix) {
    int n = 0;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().filename().string().rfind(prefix, 0) == 0) ++n;
    return n;
}

mode_t modeOf(const fs::path& p) {
    struct stat st {};
    REQUIRE(::stat(p.c_str(), &st) == 0);
    return st.st_mode & 07777;
}

// Commits a.txt = text into out; true on success.
bool bakeText(const fs::path& out, const std::string& text) {
    Diagnostics diagnostics;
    OutputTransaction transaction(out);
    return transaction.begin(diagnostics) && stageText(transaction, "a.txt", text, diagnostics) &&
           transaction.commit(diagnostics);
}

}  // namespace

TEST_CASE("a new output folder and its sub-folders get the user's umask, not mkdtemp's 0700") {
    const TempDir tmp;
    for (const mode_t mask : {mode_t{022}, mode_t{027}}) {
        CAPTURE(mask);
        const mode_t old = ::umask(mask);
        const fs::path out = tmp.path / ("out" + std::to_string(mask));
        Diagnostics diagnostics;
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        REQUIRE(stageText(transaction, "lightmaps/a.txt", "x", diagnostics));
        REQUIRE(transaction.commit(diagnostics));
        ::umask(old);
        CHECK(modeOf(out) == (0777 & ~mask));
        CHECK(modeOf(out / "lightmaps") == (0777 & ~mask));
        CHECK(modeOf(out / "lightmaps" / "a.txt") == (0666 & ~mask));
    }
}

TEST_CASE("the staging folder of a bake killed with SIGKILL is removed by the next bake, a live one is not") {
    const TempDir tmp;
    for (const bool out_exists : {false, true}) {
        CAPTURE(out_exists);
        const fs::path out = tmp.path / (out_exists ? "old" : "new");
        if (out_exists) REQUIRE(bakeText(out, "first"));
        const pid_t child = fork();
        REQUIRE(child >= 0);
        if (child == 0) {
            Diagnostics diagnostics;
            OutputTransaction transaction(out);
            if (transaction.begin(diagnostics)) stageText(transaction, "a.txt", "half", diagnostics);
            ::raise(SIGKILL);  // no destructor, no handler: what `kill -9` leaves
            _exit(1);
        }
        int status = 0;
        REQUIRE(waitpid(child, &status, 0) == child);
        REQUIRE(WIFSIGNALED(status));
        const fs::path where = out_exists ? out : tmp.path;
        const std::string prefix = out_exists ? ".radbake-tmp-" : ".new.radbake-tmp-";
        REQUIRE(countPrefixed(where, prefix) == 1);  // the killed bake's leftovers

        // A live bake's staging folder (begun, not committed) is left alone by another bake.
        Diagnostics live_diagnostics;
        OutputTransaction live(tmp.path / "other");
        REQUIRE(live.begin(live_diagnostics));
        REQUIRE(bakeText(out, "second"));
        CHECK(countPrefixed(where, prefix) == 0);
        CHECK(countPrefixed(tmp.path, ".other.radbake-tmp-") == 1);
        CHECK(testfs::readBytes(out / "a.txt") == "second");
    }
}

TEST_CASE("two bakes into one existing folder: the second is refused with a clear error, never interleaved") {
    const TempDir tmp;
    const fs::path out = tmp.path / "out";
    REQUIRE(bakeText(out, "zero"));
    Diagnostics first_diagnostics, second_diagnostics;
    OutputTransaction first(out);
    REQUIRE(first.begin(first_diagnostics));
    REQUIRE(stageText(first, "a.txt", "one", first_diagnostics));
    {
        OutputTransaction second(out);
        CHECK_FALSE(second.begin(second_diagnostics));
        REQUIRE(second_diagnostics.hasErrors());
        CHECK(second_diagnostics.all().front().message.find("another bake") != std::string::npos);
    }
    REQUIRE(first.commit(first_diagnostics));
    CHECK(testfs::readBytes(out / "a.txt") == "one");
    // Once the first is done, the next may bake.
    CHECK(bakeText(out, "two"));
}

TEST_CASE("two bakes racing to create one folder: the second is refused at begin, and no lock file is left") {
    const TempDir tmp;
    const fs::path out = tmp.path / "out";
    Diagnostics da, db;
    OutputTransaction a(out);
    REQUIRE(a.begin(da));  // no folder yet: locked all the same
    {
        OutputTransaction b(out);
        CHECK_FALSE(b.begin(db));
        REQUIRE(db.hasErrors());
        CHECK(db.all().front().message.find("another bake") != std::string::npos);
    }
    REQUIRE(stageText(a, "a.txt", "from a", da));
    REQUIRE(a.commit(da));
    CHECK(testfs::readBytes(out / "a.txt") == "from a");
    CHECK(countPrefixed(tmp.path, ".out.") == 0);  // no staging, no lock file
    // Once the first is done, the next may bake; an abandoned bake of a new folder leaves nothing.
    CHECK(bakeText(out, "from c"));
    {
        Diagnostics dd;
        OutputTransaction d(tmp.path / "never");
        REQUIRE(d.begin(dd));
    }
    CHECK(countPrefixed(tmp.path, ".never.") == 0);
    CHECK_FALSE(fs::exists(tmp.path / "never"));
}

TEST_CASE("an output whose bytes did not change keeps its file and time; changed ones are counted") {
    const TempDir tmp;
    const fs::path out = tmp.path / "out";
    {
        Diagnostics diagnostics;
        OutputTransaction transaction(out);
        REQUIRE(transaction.begin(diagnostics));
        REQUIRE(stageText(transaction, "same.txt", "unchanged", diagnostics));
        REQUIRE(stageText(transaction, "new.txt", "v1", diagnostics));
        REQUIRE(transaction.commit(diagnostics));
        CHECK(transaction.changedCount() == 2);
    }
    // An old time, so a rewrite would show.
    const auto old_time = fs::file_time_type::clock::now() - std::chrono::hours(24);
    fs::last_write_time(out / "same.txt", old_time);
    fs::last_write_time(out / "new.txt", old_time);
    Diagnostics diagnostics;
    OutputTransaction transaction(out);
    REQUIRE(transaction.begin(diagnostics));
    REQUIRE(stageText(transaction, "same.txt", "unchanged", diagnostics));
    REQUIRE(stageText(transaction, "new.txt", "v2", diagnostics));
    REQUIRE(transaction.commit(diagnostics));
    CHECK(transaction.changedCount() == 1);
    CHECK(fs::last_write_time(out / "same.txt") == old_time);
    CHECK(fs::last_write_time(out / "new.txt") != old_time);
    CHECK(testfs::readBytes(out / "new.txt") == "v2");
    CHECK(countPrefixed(out, ".radbake-tmp-") == 0);
}
