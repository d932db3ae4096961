#pragma once
// The bake options every step of a bake takes (`radbake bake`, `radbake solve`): one parser,
// so a build farm passes the same command line to each step.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "core/progress.h"
#include "radbake.h"

namespace radbake::cli {

struct BakeArgs {
    std::string scene;
    std::string out_dir;  // empty: baked/<scene name>
    std::string quality_name = "medium";
    std::string visibility_name = "aabb";
    int threads = 0;
    bool no_pin_threads = false;
    std::string probes;
    std::string lightmap_scales;
    std::string depfile;
    std::string solution_file;
    ImportOptions import;
    bool quiet = false;
    bool preview = false;
    bool export_lights = false;
    bool no_lightmaps = false;
    bool no_clustering = false;
    std::string edge_correction;  // "", "off", "shared" or "on": the quality's choice unless given
    std::string lightmap_quantity = "irradiance";
    std::string realtime_lights;
    LightmapSettings lightmaps;
    // Raw knobs; applied over the preset only when given on the command line.
    double error_threshold = 0.0;
    double local_error_threshold = 0.0;
    double min_area = 0.0;
    double tolerance = 0.0;
    int max_iterations = 0;
    double max_memory_mb = 0.0;
    CLI::Option* error_threshold_option = nullptr;
    CLI::Option* local_error_threshold_option = nullptr;
    CLI::Option* min_area_option = nullptr;
    CLI::Option* tolerance_option = nullptr;
    CLI::Option* max_iterations_option = nullptr;
    CLI::Option* texel_tolerance_option = nullptr;
};

// Registers every bake option (all but the scene and the output folder) on `cmd`, into `args`.
void addBakeOptions(CLI::App& cmd, BakeArgs& args);

// The preset of --quality, then every knob the command line gave; shared between `ranks`.
BakeOptions bakeOptions(const BakeArgs& args, const Ranks& ranks = Ranks::one());

// Reads the files the options name (--probes, --lightmap-scales, --realtime-lights) into
// `options`; false after reporting.
bool readBakeSideFiles(const BakeArgs& args, BakeOptions& options, Diagnostics& diagnostics);

// False after reporting when --depfile names something the command could not replace (checked
// before any work, which would otherwise write every other output first).
bool depfileWritable(const BakeArgs& args, Diagnostics& diagnostics);

// A log (stderr not a terminal) gets plain lines; --quiet none.
ProgressStyle progressStyleOf(bool quiet);

// Diagnostics go to stderr; notes only when the run is interactive (not quiet, a terminal).
void routeDiagnostics(Diagnostics& diagnostics, Progress& progress);

// The ranks a step runs on. A step that shares its work (bake, solve) runs on the processes
// mpirun started; any other is refused (thrown) when mpirun started more than one of it.
const Ranks& stepRanks(const char* step, bool shares);
// A rank other than the lead reports its errors only, each marked with its rank, and shows no
// progress; the lead reports as routeDiagnostics does.
void routeRankDiagnostics(const Ranks& ranks, Diagnostics& diagnostics, Progress& progress);

// What writes a bake folder: a bake made from the options (a whole bake, or merged shards).
using MakeBake = std::function<Bake(const BakeOptions& options, Progress& progress, Diagnostics& diagnostics)>;
// `radbake bake`'s run around `make`: the output folder (args.out_dir, default baked/<scene
// name>) locked and claimed before any work, the side files read, the bake committed all or
// nothing, the depfile (the bake's inputs, then `extra_inputs`) and the one-line summary. The
// exit code. With several ranks, every rank makes the bake and the lead alone writes.
int runBakeInto(const BakeArgs& args, const Ranks& ranks, const MakeBake& make,
                const std::vector<std::string>& extra_inputs = {});

// The program's outer boundary for a command on `scene`: nothing escapes; unwinding abandons
// the outputs. Sets `result` to run()'s exit code, or 1 after printing what was thrown.
void runGuarded(const std::string& scene, const char* doing, int& result, const std::function<int()>& run);

}  // namespace radbake::cli
