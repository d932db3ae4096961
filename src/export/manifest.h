#pragma once
// manifest.json: every output file of a bake with its size and SHA-256, so a content
// pipeline can check a bake directory is complete and unchanged without re-baking.
//
//   {"generator": "radbake 0.1.0",
//    "excluded": ["timings.json"],
//    "files": [{"path": "lightmaps/room_0.exr", "bytes": 123, "sha256": "ab..."}, ...]}
//
// Paths are relative to the bake directory with '/' separators, sorted, each listed once.
// timings.json (stats_json.h: wall time, phases, peak memory, threads) is never listed, as
// "excluded" says: it differs from run to run, and the manifest must not (DESIGN.md section 4).
#include <filesystem>
#include <string>
#include <vector>

#include "core/diagnostics.h"

namespace radbake {

// Hashes root/<file> for each of `relative_files` (e.g. OutputTransaction::staged() with
// root = its staging directory) and writes the manifest to `manifest_path`; entries naming
// the manifest itself or timings.json (at the root) are left out. False after reporting a
// file that cannot be read or written.
bool writeManifest(const std::filesystem::path& manifest_path, const std::filesystem::path& root,
                   std::vector<std::string> relative_files, const std::string& generator,
                   Diagnostics& diagnostics);

}  // namespace radbake
