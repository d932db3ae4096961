#pragma once
// Packing lightmap charts into atlases with stb_rect_pack (the only file that
// includes it is lightmap_pack.cpp).
#include <vector>

#include "bake/lightmap_charts.h"
#include "core/diagnostics.h"

namespace radbake {

// Places every chart with `padding` free texels on each side (so two charts are at least
// 2 * padding apart and no chart is closer than padding to an atlas edge). Atlases are
// filled one after the other at options.atlas_size; the last one shrinks to the smallest
// power of two (or atlas_size) that still holds its charts, and keeps only the rows it uses
// (rounded up to a multiple of 4), so it may be wider than tall. False after reporting a chart
// that cannot fit an empty atlas (only possible when the cap exceeds the atlas).
bool packLightmapCharts(std::vector<LightmapChart> charts, const LightmapOptions& options, LightmapLayout& layout,
                        Diagnostics& diagnostics);

}  // namespace radbake
