// --depfile and --solution write over what can be ours only (issue 32): a regular file, or
// nothing. A directory or FIFO at the path is refused by name and kept; a write that fails
// (a full disk, simulated with RLIMIT_FSIZE in a child process) keeps the old file and
// leaves no temporary behind.
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "pipeline/depfile.h"
#include "pipeline/solution_cache.h"
#include "../export/temp_files.h"

using namespace radbake;
using testfs::readBytes;
using testfs::TempDir;
namespace fs = std::filesystem;

namespace {

// Runs `write` in a child process that may make no file larger than `max_bytes`, as a full
// disk would (SIGXFSZ ignored: the write fails with EFBIG instead of killing it). The child's
// status: 0 when `write` reported success, 1 when it reported a failure.
int statusWithFileSizeLimit(rlim_t max_bytes, const std::function<bool()>& write) {
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        const rlimit limit{max_bytes, max_bytes};
        if (::signal(SIGXFSZ, SIG_IGN) == SIG_ERR || ::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(3);
        ::_exit(write() ? 0 : 1);
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) != 3);  // the limit could not be set: nothing was tested
    return WEXITSTATUS(status);
}

fs::path temporaryOf(const fs::path& path) {
    fs::path temporary = path;
    return temporary += ".radbake-tmp";
}

// Depfile contents larger than any limit below.
const std::vector<std::string> kTargets(64, "out/some_output_file.glb");
const std::vector<std::string> kInputs(64, "scenes/some_input_file.wrl");

bool writeTestDepfile(const fs::path& path, Diagnostics& diagnostics) {
    return writeDepfile(path, kTargets, kInputs, diagnostics);
}

void makeFifo(const fs::path& path) { REQUIRE_MESSAGE(::mkfifo(path.c_str(), 0600) == 0, std::strerror(errno)); }

}  // namespace

TEST_CASE("a depfile or solution that cannot be written whole keeps the old file and leaves no temporary") {
    TempDir dir;
    const fs::path depfile = dir.path / "bake.d", solution = dir.path / "bake.solution";
    testfs::writeText(dir, "bake.d", "old: depfile\n");
    testfs::writeText(dir, "bake.solution", "old solution");
    const fs::path new_depfile = dir.path / "new.d";

    CHECK(statusWithFileSizeLimit(64, [&] {
              Diagnostics diagnostics;
              return writeTestDepfile(depfile, diagnostics);
          }) == 1);
    CHECK(statusWithFileSizeLimit(64, [&] {
              Diagnostics diagnostics;
              return writeTestDepfile(new_depfile, diagnostics);
          }) == 1);
    CHECK(statusWithFileSizeLimit(16, [&] {
              Diagnostics diagnostics;
              return saveSolution(Solution{}, "key", solution, diagnostics);
          }) == 1);
    CHECK(readBytes(depfile) == "old: depfile\n");
    CHECK_FALSE(fs::exists(new_depfile));
    CHECK(readBytes(solution) == "old solution");
    for (const fs::path& path : {depfile, new_depfile, solution}) CHECK_FALSE(fs::exists(temporaryOf(path)));

    // Without the limit the same writes succeed: the failures above were the disk's.
    Diagnostics diagnostics;
    CHECK(writeTestDepfile(depfile, diagnostics));
    CHECK(saveSolution(Solution{}, "key", solution, diagnostics));
    CHECK(readBytes(depfile) == formatDepfile(kTargets, kInputs));
    CHECK(readBytes(solution) != "old solution");
    CHECK(diagnostics.all().empty());
}

TEST_CASE("a depfile or solution path that is a directory or a FIFO is refused by name and never replaced") {
    TempDir dir;
    const fs::path folder = dir.path / "folder", fifo = dir.path / "fifo";
    fs::create_directory(folder);
    makeFifo(fifo);
    for (const auto& [path, kind] : {std::pair{folder, "a directory"}, std::pair{fifo, "a FIFO"}}) {
        CAPTURE(path);
        Diagnostics depfile_diagnostics;
        CHECK_FALSE(writeTestDepfile(path, depfile_diagnostics));
        REQUIRE(depfile_diagnostics.errorCount() == 1);
        const Diagnostic& error = depfile_diagnostics.all().back();
        CHECK(error.location.file == path.string());
        CHECK(error.message.find(kind) != std::string::npos);
        CHECK(error.message.find("Success") == std::string::npos);

        Diagnostics save_diagnostics;
        CHECK_FALSE(saveSolution(Solution{}, "key", path, save_diagnostics));
        CHECK(save_diagnostics.all().back().message.find(kind) != std::string::npos);

        // A bake refuses it before it solves: it would save there.
        Diagnostics load_diagnostics;
        CHECK_FALSE(loadSolution(Scene{}, SolverOptions{}, "key", path, 1, load_diagnostics));
        REQUIRE(load_diagnostics.errorCount() == 1);
        CHECK(load_diagnostics.all().back().location.file == path.string());
        CHECK(load_diagnostics.all().back().message.find(kind) != std::string::npos);
        CHECK_FALSE(fs::exists(temporaryOf(path)));
    }
    CHECK(fs::is_directory(folder));
    CHECK(fs::is_empty(folder));
    CHECK(fs::is_fifo(fifo));
}
