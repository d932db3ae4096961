#pragma once
// Shared by the Assimp fuzz targets: writes each input to a file in a private temporary
// folder (Assimp reads from a path and picks the importer by extension), then runs the whole
// import stage, importScene (Assimp, conversion, triangulation, validation), on it. Any MTL
// or other file the input names is looked up in that otherwise empty folder.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

#include "io/import.h"

namespace radbake::fuzz {

inline const std::string& fuzzFolder() {
    static const std::string folder = [] {
        char name[] = "/tmp/radbake_fuzz_XXXXXX";
        const char* made = mkdtemp(name);
        if (!made) std::abort();
        return std::string(made);
    }();
    return folder;
}

inline int importBytes(const uint8_t* data, size_t size, const char* extension) {
    const std::string path = fuzzFolder() + "/input" + extension;
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    Diagnostics diagnostics;
    ImportOptions options;
    options.strict = size > 0 && (data[size - 1] & 1);
    const std::optional<Scene> scene = importScene(path, options, diagnostics);
    // Every failure must come with an error to show the user.
    if (!scene && !diagnostics.hasErrors()) std::abort();
    std::remove(path.c_str());
    return 0;
}

}  // namespace radbake::fuzz
