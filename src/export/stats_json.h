#pragma once
// stats.json and timings.json, for content-build logs and benchmarks. stats.json holds only
// what the scene and the options determine (counts, knobs, lightmap figures), so it is
// byte-identical from run to run whatever the thread count (DESIGN.md section 4) and the
// manifest can hash it; timings.json holds what the run costs (wall time, seconds per phase,
// peak memory, threads), which differs every run, and the manifest leaves it out.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "radiosity/solver_options.h"

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
    size_t hidden_texels = 0;      // texels with geometry inside other geometry (under a block), dilated
    double texel_tolerance = 0.0;
    double occupancy = 0.0;        // chart texels (padding excluded) / atlas texels
    // Mixed lighting (--realtime-lights): lights the engine draws, those the shadowmask has no
    // channel for, and texels more than four of them light.
    size_t realtime_lights = 0, shadowmask_lights_without_channel = 0, shadowmask_texels_over_channels = 0;
};

// The link read-out's work (LinkReconstruction::work) at vertices and at texels (seam fit
// included): points read and the rays and point form factors they took; zero when the exhaustive
// gather read them (--texel-tolerance 0).
struct ReadoutReport {
    size_t points = 0, rays = 0, form_factors = 0;
};

struct BakeReport {
    std::string generator;  // "radbake <version>"
    std::string scene;      // path as given
    double seconds = 0.0;   // timings.json: wall time of the whole bake
    std::vector<std::pair<std::string, double>> phases;  // timings.json: wall seconds per phase, in order
    SolveStats solve;
    SolverOptions options;  // the knobs actually used (after preset and overrides)
    int threads = 0;        // timings.json: worker threads actually used
    double peak_rss_mb = 0.0;  // timings.json
    int ranks = 1;             // timings.json: processes that shared the bake (mpirun)
    double exchanged_mb = 0.0; // timings.json: MiB the lead sent and received between ranks
    size_t exchanges = 0;      // timings.json: the exchanges (collectives) that carried them
    double exchange_seconds = 0.0;  // timings.json: the lead's wall time in exchanges
    double shared_seconds = 0.0;    // timings.json: the lead's wall time computing its share
    size_t meshes = 0, vertices = 0, triangles = 0, probes = 0;  // as written: back twins included
    size_t two_sided_meshes = 0;  // meshes given a back twin (scene/two_sided.h)
    size_t two_sided_closed_meshes = 0;  // two-sided, but closed and dark inside: no twin
    // Vertices split at hard edges at import (Scene::crease_split): the shared ones, and the
    // copies added (counted in `vertices`).
    size_t hard_edge_vertices = 0, hard_edge_copies = 0;
    // Files the scene named that the read policy refused (Scene::refused_inputs), each warned.
    size_t refused_inputs = 0;
    int warnings = 0;
    LightmapReport lightmaps;
    ReadoutReport vertex_readout, texel_readout;
};

// Peak resident set size of this process so far, in MiB (getrusage).
double peakRssMegabytes();

// The file the manifest never lists (see manifest.h), beside stats.json in a bake directory.
inline constexpr const char* kTimingsJsonName = "timings.json";

// stats.json: generator, scene, the solve's counts, visibility, quality and knobs, mesh
// counts, the lightmap figures (only when lightmaps were baked) and warnings, in that order.
std::string formatStatsJson(const BakeReport& report);

bool writeStatsJson(const std::filesystem::path& path, const BakeReport& report, Diagnostics& diagnostics);

// timings.json: generator, scene, seconds, phases (a phase run in rounds is one key with its
// total), peak_rss_mb and threads; ranks, exchanged_mb, exchanges,
// exchange_s and shared_s when ranks shared the bake.
std::string formatTimingsJson(const BakeReport& report);

bool writeTimingsJson(const std::filesystem::path& path, const BakeReport& report, Diagnostics& diagnostics);

}  // namespace radbake
