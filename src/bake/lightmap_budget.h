#pragma once
// The texel budget, applied before the solve (a budget error must not cost a solve first):
// every chart texel costs an evaluation of the solution, so a bake holds at most max_texels
// chart texels (padding excluded). The charts built at the density chosen here are the
// ones bakeLightmaps fills.
#include <cstddef>
#include <optional>

#include "bake/lightmap_bake.h"
#include "core/diagnostics.h"
#include "scene/scene.h"

namespace radbake {

// Without a density given: 16 texels per metre (6.25 cm texels), whatever the file's unit, so
// a scene in centimetres read with --unit-scale 0.01 gets the same lightmaps as one in metres;
// but at least kMinTexelsAcross along the scene's largest side, so a small scene (a model
// box half a metre wide) still gets walls a few dozen texels across (defaultTexelsPerMetre).
inline constexpr double kDefaultTexelsPerMetre = 16.0;
inline constexpr double kMinTexelsAcross = 34.0;

// The default density for `scene` (in metres), texels per metre.
double defaultTexelsPerMetre(const Scene& scene);

struct LightmapBudget {
    double texels_per_unit = 0.0;        // the density asked for, per scene unit; 0: the default
    double metres_per_unit = 1.0;        // ImportOptions::unit_scale, to convert it
    size_t max_texels = size_t{1} << 22; // chart texels of the whole bake (4 full 1024^2 atlases)
};

// Charts at the density asked for (or the default). Over the budget, the default density is
// lowered until the charts fit, with a warning; a density the user gave is an error naming
// one that fits. nullopt after reporting. `options.texels_per_metre` is overwritten.
std::optional<LightmapCharts> chartLightmapsWithinBudget(const Scene& scene, LightmapOptions options,
                                                         const LightmapBudget& budget, Diagnostics& diagnostics);

}  // namespace radbake
