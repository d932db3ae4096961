#pragma once
// Test support for running the built `radbake` program on files in a temporary directory.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <algorithm>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "../export/temp_files.h"

namespace clitest {

namespace fs = std::filesystem;
using testfs::readBytes;
using testfs::TempDir;

inline void writeText(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

struct RunResult {
    int exit_code = -1;
    std::string output;  // stdout and stderr together
};

// Runs a shell command line, its output and exit status (-1: killed by a signal).
inline RunResult runShell(const std::string& command) {
    RunResult result;
    std::FILE* pipe = popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    char buffer[4096];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) result.output.append(buffer, n);
    const int status = pclose(pipe);
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

// Runs `radbake ARGS` with stderr merged into stdout; ARGS is passed to the shell as is.
// With `seconds`, a run that takes longer is killed (exit status 137): a hang fails the test
// instead of stopping the suite.
inline RunResult runRadbake(const std::string& args, int seconds = 0) {
    const std::string limit = seconds > 0 ? "timeout -s KILL " + std::to_string(seconds) + " " : std::string();
    return runShell(limit + "'" + RADBAKE_EXE + "' " + args + " 2>&1");
}

inline std::string quote(const fs::path& path) { return "'" + path.string() + "'"; }

// Every file under `dir` but timings.json (which differs between runs), by relative path.
inline std::vector<std::pair<std::string, std::string>> outputsOf(const fs::path& dir) {
    std::vector<std::pair<std::string, std::string>> files;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(dir))
        if (entry.is_regular_file() && entry.path().filename() != "timings.json")
            files.emplace_back(fs::relative(entry.path(), dir).string(), readBytes(entry.path()));
    std::sort(files.begin(), files.end());
    return files;
}

// Checks that `dir` holds the files `want` lists (outputsOf), byte for byte.
inline void checkSameOutputs(const fs::path& dir, const std::vector<std::pair<std::string, std::string>>& want) {
    const auto got = outputsOf(dir);
    REQUIRE(got.size() == want.size());
    for (size_t i = 0; i < got.size(); ++i) {
        CAPTURE(got[i].first);
        CHECK(got[i].first == want[i].first);
        CHECK(got[i].second == want[i].second);
    }
}

}  // namespace clitest
