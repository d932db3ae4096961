#pragma once
// The stages a bake's steps share (internal to src/pipeline): `bake` runs them all, a read-out
// shard (`gather`) the preparation, the saved solution and its share of the read-out, `merge`
// the preparation, the parts' assembly and the rest.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/bake.h"

namespace radbake {

// One step's shared state: its result, threads, progress and diagnostics.
struct StageRun {
    Bake& out;
    ParallelRunner runner;
    Progress& progress;
    Diagnostics& diagnostics;
    // True, with out.status set, when the run was cancelled or an error was reported.
    bool stopped();
    // A named phase, started within the bake's memory budget.
    void beginPhase(const char* name);
};

// What runs on an imported scene (its back twins added, its real-time lights marked); sets out.status.
using Stages = std::function<void(Bake&, Progress&, Diagnostics&)>;
// Reads the scene at `path` (options.import) and runs `stages` on it.
Bake importAndRun(const std::string& path, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics,
                  const Stages& stages);

// Before the solve: the scene's checks, its inputs' hashes, the lightmap charts (when the bake
// has lightmaps; their density then set in out.options). False when stopped.
bool prepareStages(StageRun& run, std::optional<LightmapCharts>& charts);
// The read-out's options: the exhaustive gather at --texel-tolerance 0.
ReadoutOptions readoutOptionsOf(const BakeOptions& options);
// Probes [begin, end) of `probes` (clamped), H in W/m^2 each.
std::vector<DVec3> evaluateProbes(const Solution& solution, const ReadoutOptions& readout,
                                  const std::vector<Probe>& probes, double metres_per_unit, ParallelRunner& runner,
                                  Progress& progress, size_t begin, size_t end);
ReadoutReport readoutReport(const ReadoutWork& work);
// The lightmaps made into outputs: the radiance quantity, the shadowmask and the directions
// (read from `solution`; without one, those `baked` holds), the meshes split at chart seams,
// the file names and the report; sets out.lightmaps.
void completeLightmaps(StageRun& run, BakedLightmaps baked, const LightmapOptions& used, const Solution* solution,
                       const ReadoutOptions& readout);
// With more than one rank (run.runner.ranks()), after the solve: each rank reads its shard of
// the read-out (shards.h), the lead assembles them and finishes the bake; the other ranks' Bake
// is Ok with no outputs.
void readOutAcrossRanks(StageRun& run, std::optional<LightmapCharts> charts);
// After the read-out: the previews, the report's times, status Ok.
void finishStages(StageRun& run);

}  // namespace radbake
