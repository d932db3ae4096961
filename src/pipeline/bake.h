#pragma once
// The whole bake in memory, and the writing of it: what `radbake bake` does, for any program
// that links the library (an asset importer, a level-build step, a test harness).
//
// Fit to live inside another program: no signal handlers, no process-wide TBB limit, threads
// pinned only when BakeOptions::threading asks; two bakes may run side by side on two
// threads; Progress::cancel() (from its sink or any thread) makes bake() return promptly
// with BakeStatus::Cancelled.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bake/lightmap_bake.h"
#include "bake/lightmap_directions.h"
#include "bake/shadowmask.h"
#include "readout/vertex_bake.h"
#include "core/diagnostics.h"
#include "core/progress.h"
#include "export/lightmap_files.h"
#include "export/output_transaction.h"
#include "export/preview.h"
#include "export/stats_json.h"
#include "pipeline/bake_options.h"
#include "radiosity/solution.h"
#include "scene/scene.h"

namespace radbake {

enum class BakeStatus {
    Ok,
    InputError,  // bad scene, probes or options: located errors are in the Diagnostics
    Cancelled,   // Progress::cancel() was called; nothing is complete
};
const char* toString(BakeStatus status);

struct BakedLightmaps {
    Lightmaps lightmaps;  // atlases (EXR images), layout, texel counts
    LightmapFiles files;  // the meshes split at chart seams (TEXCOORD_1) and each atlas's file name
    Shadowmask shadowmask;  // with real-time lights (--realtime-lights): their visibility per texel
    LightmapDirections directions;  // with --directional: how each texel's light changes with the normal
};

struct PreviewImage {
    std::string file;     // relative to the bake folder: "preview/<name>_view.png"
    RgbImage image;       // linear
    double exposure = 1;  // for encodePreviewPng
};

struct Bake {
    BakeStatus status = BakeStatus::InputError;
    BakeOptions options;                // as used: presets applied, the lightmap density chosen
    std::unique_ptr<Scene> scene;       // owned here: solution points into it
    std::optional<Solution> solution;
    VertexBake vertices;                // H / pi per vertex of every mesh
    std::optional<BakedLightmaps> lightmaps;
    std::vector<DVec3> probe_irradiance;  // H (W/m^2) per options.probes entry
    std::vector<PreviewImage> previews;
    std::string scene_sha256;           // of the scene file (empty for a scene built in memory)
    // Of every input file's SHA-256 in Scene::input_files order: an edit to an Inline'd file
    // or an MTL changes it, though the scene file's own hash stays.
    std::string inputs_sha256;
    BakeReport report;                  // what stats.json holds

    bool ok() const { return status == BakeStatus::Ok; }
};

// Reads the scene at `path` (options.import) and bakes it.
Bake bake(const std::string& path, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics);
// Bakes a scene already in memory (e.g. built by an importer), in metres: options.import is
// not used (probe positions are in metres too).
Bake bake(Scene scene, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics);

// `radbake solve`: the solve alone, the first step of a bake split over machines. Reads the
// scene at `path` and, unless options.solution_file already holds its solution for these
// solver settings (then kept as it is, unread past its key), solves it and writes the
// solution there (an error when it cannot be written). Read-out and lightmap options are not used.
struct SolveOnly {
    BakeStatus status = BakeStatus::InputError;
    bool kept = false;                     // the file held this solution already
    SolveStats stats;                      // of the solve (none when kept)
    std::vector<std::string> input_files;  // every file the scene read or looked for
    double seconds = 0.0;
    bool ok() const { return status == BakeStatus::Ok; }
};
SolveOnly solveOnly(const std::string& path, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics);

// The lightmap charts bake() fills for `scene` (its back twins added): options.lightmaps'
// atlas size, padding, tolerance and per-mesh scales, at the density asked for within the
// texel budget (options.import.unit_scale converts it). bake() builds them before its solve;
// a tool that rebuilds a bake's lightmap layout calls this, then packLightmapCharts.
// nullopt after reporting (a density over the budget).
std::optional<LightmapCharts> chartBakeLightmaps(const Scene& scene, const BakeOptions& options,
                                                 Diagnostics& diagnostics);

// What writeBake wrote.
struct WrittenBake {
    std::vector<std::string> files;  // relative to the folder, in writing order
    size_t changed = 0;              // of those, new or with other bytes (the rest kept their file and time)
};

// Writes an Ok bake into `out_dir`, all or nothing (OutputTransaction): <name>.glb,
// <name>.ply, lightmaps/<name>_<k>.exr and .png, probes.csv, preview/*.png, stats.json and
// manifest.json; files the folder's last bake wrote (its manifest lists them) that this one
// does not write are removed, every other file is kept; a folder holding another scene's bake
// is refused; files whose bytes did not change are left as they were (so build tools' restat
// sees them unchanged). One bake at a time per folder: a second is refused. False after
// reporting; then `out_dir` is as it was.
bool writeBake(const Bake& bake, const std::filesystem::path& out_dir, Diagnostics& diagnostics,
               WrittenBake* written = nullptr);
// The same into a transaction begun before the bake (so the folder was locked before any work).
bool commitBake(const Bake& bake, OutputTransaction& transaction, Diagnostics& diagnostics,
                WrittenBake* written = nullptr);

// Checks, right after OutputTransaction::begin(), that the folder holds no other scene's bake
// (refused: false after reporting), and retires what its last bake wrote. writeBake does it
// too; calling it first refuses a wrong folder before the bake.
bool claimOutputFolder(OutputTransaction& transaction, const std::string& scene_name, Diagnostics& diagnostics);

// The name a scene file's outputs are called by (as importScene names the scene): the file
// name without its format suffix, "room.wrl.gz" -> "room".
std::string sceneNameOf(const std::string& path);

// `radbake bake` in one call: locks `out_dir` and checks it is this scene's (a second bake, or
// a folder of another scene, is refused before the scene is read), bakes `path`, and writes
// the bake there. `result` (optional) receives the bake. False after reporting.
bool bakeInto(const std::string& path, const std::filesystem::path& out_dir, const BakeOptions& options,
              Progress& progress, Diagnostics& diagnostics, Bake* result = nullptr, WrittenBake* written = nullptr);

}  // namespace radbake
