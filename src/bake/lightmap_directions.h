#pragma once
// Directional lightmaps (issue 33, --directional): how a texel's irradiance changes with the
// normal, for normal-mapped surfaces. Per texel the irradiance is read at the surface normal n0
// and at eight normals tilted 30 degrees round it, and its luminance fitted by a linear function
// of the normal, E(n) = a + b . n (the form L1 spherical harmonics give irradiance): exact at n0,
// least relative squares at the tilts. Stored is
//     g = b / E(n0)   (world space)
// so a shader rebuilds E(n) = lightmap x max(0, 1 + g . (n - n0)), with n the normal-mapped
// normal and n0 the surface's (the colour of the lightmap, the direction of the luminance).
// Fitting the irradiance itself over the tilts a normal map uses, rather than L1 radiance over
// the sphere, avoids the linear reconstruction of L1 radiance being 25 % low for one dominant
// source.
#include <optional>
#include <span>
#include <vector>

#include "bake/chart_texels.h"
#include "bake/lightmap_charts.h"
#include "core/parallel.h"
#include "radiosity/solution.h"
#include "readout/readout_options.h"

namespace radbake {

inline constexpr double kDirectionTiltDegrees = 30.0;

struct LightmapDirections {
    std::vector<std::vector<float>> images;  // per atlas: g (x y z, world) per texel, row 0 at the top
    std::vector<int> widths, heights;
    size_t texels = 0;                       // texels read (nine reads each)
};

// The directions of every covered texel of the layout, padding dilated from the charts' texels.
LightmapDirections bakeLightmapDirections(const Solution& solution, const ReadoutOptions& readout,
                                          const LightmapLayout& layout, int padding, ParallelRunner& runner);

// The same in pieces, for a read-out split by chart: the charts `wanted` selects (empty: all)
// read into records (g and whether the texel was read: 13 bytes a texel), then the directions
// from records covering every chart, dilated. The pieces give bakeLightmapDirections' bytes.
inline constexpr uint32_t kDirectionRecord = 3 * sizeof(float) + 1;
ChartRecords readDirectionRecords(const Solution& solution, const ReadoutOptions& readout, const LightmapLayout& layout,
                                  std::span<const uint8_t> wanted, ParallelRunner& runner);
std::optional<LightmapDirections> assembleDirections(const LightmapLayout& layout, int padding,
                                                     std::span<const ChartRecords> parts);

}  // namespace radbake
