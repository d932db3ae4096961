#pragma once
// Fixtures shared by the VRML 1.0 reader tests: literal files written to a fresh temp folder
// and read through importScene, with their diagnostics kept for inspection.
#include <atomic>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <unistd.h>

#include "io/import.h"

namespace vrml1_test {

using namespace radbake;
namespace fs = std::filesystem;

struct Read {
    std::optional<Scene> scene;
    Diagnostics diagnostics;
    std::string path;

    int count(Severity severity, const std::string& part) const {
        int n = 0;
        for (const Diagnostic& d : diagnostics.all())
            if (d.severity == severity && d.message.find(part) != std::string::npos) ++n;
        return n;
    }
    const Diagnostic* find(Severity severity, const std::string& part) const {
        for (const Diagnostic& d : diagnostics.all())
            if (d.severity == severity && d.message.find(part) != std::string::npos) return &d;
        return nullptr;
    }
};

inline fs::path tempDir() {
    static std::atomic<int> counter{0};
    fs::path dir = fs::temp_directory_path() /
                   ("radbake_vrml1_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(dir);
    return dir;
}

inline void writeFile(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

// Reads a file already on disk.
inline Read readPath(const fs::path& path, bool strict = false) {
    Read r;
    r.path = path.string();
    ImportOptions options;
    options.strict = strict;
    r.scene = importScene(r.path, options, r.diagnostics);
    return r;
}

// Writes `body` after a VRML 1.0 header to `path` and reads it.
inline Read readAt(const fs::path& path, const std::string& body, bool strict = false) {
    writeFile(path, "#VRML V1.0 ascii\n" + body);
    return readPath(path, strict);
}

}  // namespace vrml1_test
