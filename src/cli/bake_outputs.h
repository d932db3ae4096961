#pragma once
// The outputs of `radbake bake` beyond the per-vertex meshes: lightmap atlases (EXR), their
// UV meshes for the mesh writers, preview PNGs and the manifest. Each stages files into the
// bake's OutputTransaction and returns false after reporting.
#include <string>
#include <utility>
#include <vector>

#include "bake/lightmap_bake.h"
#include "bake/vertex_bake.h"
#include "core/diagnostics.h"
#include "export/lightmap_files.h"
#include "export/output_transaction.h"
#include "export/stats_json.h"
#include "radiosity/solver.h"
#include "scene/scene.h"

namespace radbake::cli {

// Without --texel-density: 16 texels per metre (6.25 cm texels), whatever the file's unit, so a
// scene in centimetres given --unit-scale 0.01 gets the same lightmaps as one in metres.
inline constexpr double kDefaultTexelsPerMetre = 16.0;

struct LightmapArgs {
    bool skip = false;           // --no-lightmaps
    double texel_density = 0.0;  // --texel-density: texels per scene unit; 0: kDefaultTexelsPerMetre
    int atlas_size = 1024;       // --atlas-size
    int padding = 2;             // --padding
    bool exr_float = false;      // --exr-float
    double texel_tolerance = 0.0;  // --texel-tolerance, or the quality's (texelToleranceFor)
    size_t max_texels = size_t{1} << 22;  // --max-texels: chart texels of the whole bake (4 full 1024^2 atlases)
    double texels_per_metre = 0.0;  // resolved by chooseTexelDensity
};

// Resolves args.texels_per_metre before the solve, from --texel-density (or the default) and
// --max-texels: the chart texels (padding excluded) must fit the budget, since every texel
// costs an evaluation of the solution (about a millisecond). Over budget, the default density
// is lowered until the charts fit, with a warning; a density the user gave is an error naming
// one that fits. False after reporting.
bool chooseTexelDensity(const Scene& scene, LightmapArgs& args, float unit_scale, Diagnostics& diagnostics);

// The --texel-tolerance of each --quality: a block of texels is interpolated from evaluated
// ones when they agree within this (0: every texel evaluated). Measured in the issue 5 note:
// at 0.02 the RMS texel error against exhaustive evaluation is 0.1-1 %, the worst texel up to
// 17 % at 64 texels/m, for 1.2-5x less time.
double texelToleranceFor(Quality quality);

struct BakedLightmaps {
    Lightmaps lightmaps;
    LightmapFiles files;
};

// Charts, packing, texels, dilation, seams; fills the report. `unit_scale`: metres per scene unit.
bool bakeSceneLightmaps(const Scene& scene, const Solution& solution, const LightmapArgs& args, float unit_scale,
                        BakedLightmaps& baked, LightmapReport& report, Diagnostics& diagnostics);

// One EXR per atlas as lightmaps/<name>_<k>.exr, each carrying `provenance` (name, value)
// plus its own atlas number in its header.
bool stageLightmapExrs(OutputTransaction& transaction, const BakedLightmaps& baked,
                       const std::vector<std::pair<std::string, std::string>>& provenance, bool exr_float,
                       Diagnostics& diagnostics);

// preview/<name>_view.png (the scene from its first Viewpoint, or a default camera) and, with
// lightmaps, preview/<name>_atlas_<k>.png for each atlas.
bool stagePreviews(OutputTransaction& transaction, const Scene& scene, const VertexBake& bake,
                   const BakedLightmaps* baked, Diagnostics& diagnostics);

}  // namespace radbake::cli
