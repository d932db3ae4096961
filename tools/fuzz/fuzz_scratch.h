#pragma once
// A private scratch folder per fuzzing process, for the inputs the readers must take as files.
// libFuzzer's -fork mode starts a process per job and ends a crashing or timed-out one without
// running exit handlers, so each process removes its folder at exit and, on start, the folders
// of earlier processes that are gone: however a run ends, at most one folder per live process.
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <unistd.h>

namespace radbake::fuzz {

inline constexpr std::string_view kScratchPrefix = "radbake_fuzz_";

// Under $TMPDIR when set (tools/fuzz.sh points it at the run's own folder), else /tmp.
inline std::filesystem::path scratchParent() {
    const char* tmpdir = std::getenv("TMPDIR");
    return tmpdir && *tmpdir ? std::filesystem::path(tmpdir) : std::filesystem::path("/tmp");
}

// Removes radbake_fuzz_<pid> folders whose process no longer exists.
inline void removeStaleScratch(const std::filesystem::path& parent) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(parent, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.compare(0, kScratchPrefix.size(), kScratchPrefix) != 0) continue;
        const std::string digits = name.substr(kScratchPrefix.size());
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        const long pid = std::strtol(digits.c_str(), nullptr, 10);
        if (pid <= 0 || pid == getpid()) continue;
        if (kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
        std::error_code ignored;
        std::filesystem::remove_all(entry.path(), ignored);
    }
}

// Never destroyed: the exit handler that removes the folder runs after static destructors.
inline const std::string& scratchFolder() {
    static const std::string* const folder = [] {
        const std::filesystem::path parent = scratchParent();
        removeStaleScratch(parent);
        const std::filesystem::path made = parent / (std::string(kScratchPrefix) + std::to_string(getpid()));
        std::error_code ec;
        std::filesystem::remove_all(made, ec);
        if (!std::filesystem::create_directory(made, ec)) std::abort();
        return new std::string(made.string());
    }();
    static const bool registered = std::atexit([] {
        std::error_code ignored;
        std::filesystem::remove_all(*folder, ignored);
    }) == 0;
    (void)registered;
    return *folder;
}

}  // namespace radbake::fuzz
