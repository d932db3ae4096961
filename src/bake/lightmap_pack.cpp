// Atlas packing with stb_rect_pack (skyline, bottom-left, rectangles sorted by height).
#define STB_RECT_PACK_IMPLEMENTATION
#include <stb_rect_pack.h>

#include "bake/lightmap_pack.h"

#include <algorithm>
#include <string>

namespace radbake {
namespace {

// Packs as many of `pending` as fit a size x size atlas; returns the rects (was_packed set).
std::vector<stbrp_rect> tryPack(const std::vector<LightmapChart>& charts, const std::vector<uint32_t>& pending,
                                int size, int padding) {
    std::vector<stbrp_rect> rects(pending.size());
    for (size_t i = 0; i < pending.size(); ++i) {
        const LightmapChart& chart = charts[pending[i]];
        rects[i].id = static_cast<int>(pending[i]);
        rects[i].w = chart.width + 2 * padding;
        rects[i].h = chart.height + 2 * padding;
    }
    std::vector<stbrp_node> nodes(static_cast<size_t>(size));
    stbrp_context context;
    stbrp_init_target(&context, size, size, nodes.data(), size);
    stbrp_pack_rects(&context, rects.data(), static_cast<int>(rects.size()));
    return rects;
}

bool allPacked(const std::vector<stbrp_rect>& rects) {
    return std::all_of(rects.begin(), rects.end(), [](const stbrp_rect& r) { return r.was_packed != 0; });
}

}  // namespace

bool packLightmapCharts(std::vector<LightmapChart> charts, const LightmapOptions& options, LightmapLayout& layout,
                        Diagnostics& diagnostics) {
    layout = LightmapLayout{};
    const int padding = std::max(options.padding, 0);
    for (const LightmapChart& chart : charts) {
        if (chart.width + 2 * padding > options.atlas_size || chart.height + 2 * padding > options.atlas_size) {
            diagnostics.error({}, "lightmap chart of " + std::to_string(chart.width) + "x" + std::to_string(chart.height) +
                                      " texels (mesh " + std::to_string(chart.mesh) + ") does not fit a " +
                                      std::to_string(options.atlas_size) + " atlas with padding " + std::to_string(padding));
            return false;
        }
    }
    std::vector<uint32_t> pending(charts.size());
    for (uint32_t i = 0; i < pending.size(); ++i) pending[i] = i;
    double chart_texels = 0.0, padded_texels = 0.0, atlas_texels = 0.0;
    while (!pending.empty()) {
        int size = options.atlas_size;
        std::vector<stbrp_rect> rects = tryPack(charts, pending, size, padding);
        if (allPacked(rects)) {
            // The last atlas: the smallest power of two that still holds everything left.
            for (int smaller = 16; smaller < options.atlas_size; smaller *= 2) {
                std::vector<stbrp_rect> trial = tryPack(charts, pending, smaller, padding);
                if (allPacked(trial)) {
                    size = smaller;
                    rects = std::move(trial);
                    break;
                }
            }
        }
        LightmapAtlas atlas;
        atlas.width = atlas.height = size;
        if (pending.size() == rects.size() && allPacked(rects)) {
            // The last atlas keeps only the rows it uses, rounded up to a multiple of 4 (the
            // block size of GPU texture compression): engines take non-square lightmaps.
            int used = 0;
            for (const stbrp_rect& rect : rects) used = std::max(used, rect.y + rect.h);
            atlas.height = std::min(size, (used + 3) / 4 * 4);
        }
        std::vector<uint32_t> left;
        for (const stbrp_rect& rect : rects) {
            const uint32_t index = static_cast<uint32_t>(rect.id);
            if (!rect.was_packed) {
                left.push_back(index);
                continue;
            }
            LightmapChart& chart = charts[index];
            chart.atlas = static_cast<int>(layout.atlases.size());
            chart.x = rect.x + padding;
            chart.y = rect.y + padding;
            atlas.charts.push_back(index);
            chart_texels += static_cast<double>(chart.width) * chart.height;
            padded_texels += static_cast<double>(rect.w) * rect.h;
        }
        if (left.size() == pending.size()) {  // cannot happen after the size check above; never loop
            diagnostics.error({}, "lightmap packing made no progress");
            return false;
        }
        std::sort(atlas.charts.begin(), atlas.charts.end());
        atlas_texels += static_cast<double>(atlas.width) * atlas.height;
        layout.atlases.push_back(std::move(atlas));
        pending = std::move(left);
    }
    layout.charts = std::move(charts);
    layout.occupancy = atlas_texels > 0.0 ? chart_texels / atlas_texels : 0.0;
    layout.padded_occupancy = atlas_texels > 0.0 ? padded_texels / atlas_texels : 0.0;
    return true;
}

}  // namespace radbake
