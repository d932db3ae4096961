#pragma once
// Shared by the Assimp fuzz targets: writes each input to a file in the process's scratch
// folder (Assimp reads from a path and picks the importer by extension), then runs the whole
// import stage, importScene (Assimp, conversion, triangulation, validation), on it. Any MTL,
// buffer or texture the input names is looked up in that otherwise empty folder.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "fuzz_scratch.h"
#include "io/import.h"

namespace radbake::fuzz {

inline int importBytes(const uint8_t* data, size_t size, const char* extension) {
    const std::string path = scratchFolder() + "/input" + extension;
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    Diagnostics diagnostics;
    ImportOptions options;
    options.strict = size > 0 && (data[size - 1] & 1);
    const std::optional<Scene> scene = importScene(path, options, diagnostics);
    std::remove(path.c_str());
    // Every failure must come with an error to show the user.
    if (!scene && !diagnostics.hasErrors()) std::abort();
    return 0;
}

}  // namespace radbake::fuzz
