#pragma once
// manifest.json: every output file of a bake with its size and SHA-256, so a content
// pipeline can check a bake directory is complete and unchanged without re-baking.
//
//   {"generator": "radbake 0.1.0",
//    "scene": "room",
//    "excluded": ["timings.json"],
//    "files": [{"path": "lightmaps/room_0.exr", "bytes": 123, "sha256": "ab..."}, ...]}
//
// Paths are relative to the bake directory with '/' separators, sorted, each listed once.
// timings.json (stats_json.h: wall time, phases, peak memory, threads) is never listed, as
// "excluded" says: it differs from run to run, and the manifest must not (DESIGN.md section 4).
// "scene" names the scene baked (its outputs are called by it), so that a later bake knows
// whose files the folder holds.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"

namespace radbake {

inline constexpr const char* kManifestName = "manifest.json";

// Hashes root/<file> for each of `relative_files` (e.g. OutputTransaction::staged() with
// root = its staging directory) and writes the manifest to `manifest_path`; entries naming
// the manifest itself or timings.json (at the root) are left out. False after reporting a
// file that cannot be read or written.
bool writeManifest(const std::filesystem::path& manifest_path, const std::filesystem::path& root,
                   std::vector<std::string> relative_files, const std::string& generator,
                   const std::string& scene, Diagnostics& diagnostics);

// What a manifest radbake wrote says: the scene (empty when an older manifest does not say)
// and every file listed, timings.json and the manifest itself included (both ours too).
struct ManifestContents {
    std::string scene;
    std::vector<std::string> files;
};

// The manifest at `path`; nullopt with `why` set when it is not a regular file, not JSON, or
// not one radbake wrote (no "generator" of ours, a listed path leaving the folder).
std::optional<ManifestContents> readManifest(const std::filesystem::path& path, std::string& why);

}  // namespace radbake
