#pragma once
// stats.json: what a bake did and what it cost, for content-build logs and benchmarks.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "radiosity/solver.h"

namespace radbake {

// The lightmap stage's figures (all zero when lightmaps were not baked).
struct LightmapReport {
    bool baked = false;
    double texels_per_unit = 0.0;  // --texel-density, texels per scene unit
    int atlas_size = 0;            // --atlas-size: the largest atlas side
    int padding = 0;
    size_t charts = 0, atlases = 0;
    size_t atlas_texels = 0;       // texels of every atlas together
    size_t covered_texels = 0;     // texels with geometry (the rest is padding or empty)
    size_t interpolated_texels = 0;  // covered texels interpolated from evaluated ones (--texel-tolerance)
    double texel_tolerance = 0.0;
    double occupancy = 0.0;        // chart texels (padding excluded) / atlas texels
};

struct BakeReport {
    std::string generator;  // "radbake <version>"
    std::string scene;      // path as given
    double seconds = 0.0;   // wall time of the whole bake
    std::vector<std::pair<std::string, double>> phases;  // wall seconds per phase, in order
    SolveStats solve;
    SolverOptions options;  // the knobs actually used (after preset and overrides)
    int threads = 0;        // worker threads actually used
    double peak_rss_mb = 0.0;
    size_t meshes = 0, vertices = 0, triangles = 0, probes = 0;
    int warnings = 0;
    LightmapReport lightmaps;
};

// Peak resident set size of this process so far, in MiB (getrusage).
double peakRssMegabytes();

std::string formatStatsJson(const BakeReport& report);

bool writeStatsJson(const std::filesystem::path& path, const BakeReport& report, Diagnostics& diagnostics);

}  // namespace radbake
