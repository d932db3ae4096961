#pragma once
// stats.json: what a bake did and what it cost, for content-build logs and benchmarks.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "radiosity/solver.h"

namespace radbake {

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
};

// Peak resident set size of this process so far, in MiB (getrusage).
double peakRssMegabytes();

std::string formatStatsJson(const BakeReport& report);

bool writeStatsJson(const std::filesystem::path& path, const BakeReport& report, Diagnostics& diagnostics);

}  // namespace radbake
