#pragma once
// Every knob of a bake, resolved in one place: BakeOptions::forQuality sets every preset
// (the solver's, the texel tolerance); a front end then overrides what its user gave.
// Units are in the names: a density per scene unit is `texels_per_unit`, per metre
// `texels_per_metre` (the imported scene is in metres, ImportOptions::unit_scale converts).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "export/probes.h"
#include "io/import.h"
#include "bake/lightmap_quantity.h"
#include "pipeline/lightmap_scales.h"
#include "pipeline/realtime_lights.h"
#include "radiosity/solver_options.h"
#include "readout/readout_options.h"

namespace radbake {

struct LightmapSettings {
    bool enabled = true;               // false: per-vertex light only (--no-lightmaps)
    double texels_per_unit = 0.0;      // --texel-density; 0: the default (defaultTexelsPerMetre)
    int atlas_size = 1024;             // --atlas-size: the largest atlas side, in texels
    int padding = 2;                   // --padding: texels around every chart, filled by dilation
    double texel_tolerance = 0.02;     // --texel-tolerance; forQuality: draft 0.05, medium 0.02,
                                       // high 0.01, reference 0 (every texel evaluated)
    size_t max_texels = size_t{1} << 22;  // --max-texels: chart texels of the whole bake
    bool exr_float = false;            // --exr-float: 32-bit EXRs instead of half
    // --lightmap-quantity: what a texel holds, H/pi (engines multiply by the albedo) or rho H/pi.
    LightmapQuantity quantity = LightmapQuantity::Irradiance;
    bool directional = false;          // --directional: also each texel's direction atlas (lightmap_directions.h)
    // --lightmap-scales FILE: per mesh or material name, a factor on the texel density
    // (lightmap_scales.h); empty: every mesh at the bake's density.
    std::vector<LightmapScaleRule> scales;
};

struct BakeOptions {
    ImportOptions import;              // when bake() reads the scene from a path
    // --realtime-lights FILE: the lights whose direct light the engine draws (realtime_lights.h).
    std::vector<RealtimeLightName> realtime_lights;
    SolverOptions solver;
    // How vertices, texels and probes read the solution (with lightmaps.texel_tolerance 0, the
    // exhaustive gather whatever readout.gather says).
    ReadoutOptions readout;
    LightmapSettings lightmaps;
    // Points whose irradiance H (W/m^2) the bake reports (probes.csv), positions in the scene
    // file's units; nullopt: no probes.csv (an empty list writes one with its header only).
    std::optional<std::vector<Probe>> probes;
    bool preview = false;              // render preview PNGs (the first Viewpoint, each atlas)
    // --export-lights: the glb also holds the scene's lights (KHR_lights_punctual), marked as
    // baked. Off by default: their light is baked already, an engine would add it again.
    bool export_lights = false;
    // --solution FILE: reuse the radiosity solution saved there when the scene and solver
    // settings match (pipeline/solution_cache.h), else solve and save it there; empty: neither.
    std::string solution_file;
    // Every phase's threads (0: all cores; not pinned). With threading.ranks (Ranks::world(),
    // core/ranks.h), every rank calls bake() alike and shares the work; only the lead's Bake
    // holds the outputs (the others' is Ok and empty), so only the lead writes.
    Threading threading;

    // Every preset of `quality`: the solver's and the read-out's knobs and the texel tolerance.
    static BakeOptions forQuality(Quality quality);
};

// The --texel-tolerance of each --quality. Measured in the issue 5 note: at 0.02 the RMS
// texel error against exhaustive evaluation is 0.1-1 %, the worst texel up to 17 % at 64
// texels/m, for 1.2-5x less time.
double texelToleranceFor(Quality quality);

// "radbake <version>": written into every output that records its generator.
std::string radbakeGenerator();

}  // namespace radbake
