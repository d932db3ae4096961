#pragma once
// What a lightmap texel holds (issue 33, --lightmap-quantity): the irradiance H/pi (the
// default: an engine multiplies it by the surface's albedo) or the reflected radiance
// rho H/pi (for unlit pipelines that show the lightmap as it is). Emission is in neither.
#include <string_view>

#include "bake/lightmap_bake.h"
#include "scene/scene.h"

namespace radbake {

enum class LightmapQuantity { Irradiance, Radiance };

const char* toString(LightmapQuantity quantity);

// Multiplies every texel of each chart's padded rectangle by the reflectance of the surface
// there (the polygon whose face holds the texel centre, else the nearest face's): H/pi
// becomes rho H/pi. `padding` is the bake's (LightmapOptions::padding).
void toReflectedRadiance(const Scene& scene, int padding, Lightmaps& lightmaps);

}  // namespace radbake
