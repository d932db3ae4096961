#include "bake/shadowmask.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <set>

#include "bake/chart_texels.h"
#include "radiosity/punctual_lights.h"
#include "readout/gather.h"

namespace radbake {
namespace {

constexpr size_t kMaxMaskedLights = 64;  // one bit each in a texel's reach mask

struct AtlasMask {
    int width = 0, height = 0;
    std::vector<uint64_t> reach;              // per texel: bit k when real-time light k lights it
    std::vector<uint8_t> covered;             // per texel: its centre lies on the chart's geometry
    std::vector<std::vector<uint8_t>> seen;   // per real-time light, per texel: visible share x 255
};

// Visibility of every real-time light at the covered texels of one chart.
void maskChart(const Solution& solution, const LightmapChart& chart, const std::vector<uint32_t>& realtime,
               AtlasMask& atlas) {
    const Scene& scene = *solution.scene;
    for (int ty = chart.y; ty < chart.y + chart.height; ++ty)
        for (int tx = chart.x; tx < chart.x + chart.width; ++tx) {
            DVec2 centre;
            const ChartFace* face = faceAtTexel(chart, tx, ty, centre);
            if (!face) continue;
            const size_t i = static_cast<size_t>(ty) * static_cast<size_t>(atlas.width) + static_cast<size_t>(tx);
            atlas.covered[i] = 1;
            const DVec3 normal = face->normal_world;
            const DVec3 from = gather::punctualFrom(solution, chart.mesh, face->triangle, face->worldPoint(centre), normal);
            for (size_t k = 0; k < realtime.size(); ++k) {
                const Light& light = scene.lights[realtime[k]];
                if (!light.lights(chart.mesh)) continue;
                const DVec3 open = lightIrradiance(light, nullptr, from, normal);
                const double peak = std::max({open.x, open.y, open.z});
                if (!(peak > 0.0)) continue;
                const DVec3 lit = lightIrradiance(light, solution.rays.get(), from, normal);
                const double share = std::clamp(std::max({lit.x, lit.y, lit.z}) / peak, 0.0, 1.0);
                atlas.seen[k][i] = static_cast<uint8_t>(std::lround(255.0 * share));
                atlas.reach[i] |= uint64_t{1} << k;
            }
        }
}

}  // namespace

Shadowmask bakeShadowmask(const Solution& solution, const LightmapLayout& layout, int padding, ParallelRunner& runner,
                          Diagnostics& diagnostics) {
    Shadowmask mask;
    const Scene& scene = *solution.scene;
    mask.channel.assign(scene.lights.size(), -1);
    std::vector<uint32_t> realtime;
    for (uint32_t l = 0; l < scene.lights.size(); ++l)
        if (scene.lights[l].realtime && scene.lights[l].on) realtime.push_back(l);
    mask.lights = realtime.size();
    if (realtime.empty()) return mask;
    if (realtime.size() > kMaxMaskedLights) {
        mask.lights_without_channel += realtime.size() - kMaxMaskedLights;
        realtime.resize(kMaxMaskedLights);
    }
    std::vector<AtlasMask> atlases(layout.atlases.size());
    for (size_t a = 0; a < atlases.size(); ++a) {
        AtlasMask& atlas = atlases[a];
        atlas.width = layout.atlases[a].width;
        atlas.height = layout.atlases[a].height;
        const size_t texels = static_cast<size_t>(atlas.width) * static_cast<size_t>(atlas.height);
        atlas.reach.assign(texels, 0);
        atlas.covered.assign(texels, 0);
        atlas.seen.assign(realtime.size(), std::vector<uint8_t>(texels, 255));
    }
    // Charts' rectangles are disjoint: each task writes its own texels.
    runner.forEach(layout.charts.size(), 1, [&](size_t c) {
        const LightmapChart& chart = layout.charts[c];
        if (chart.atlas >= 0) maskChart(solution, chart, realtime, atlases[static_cast<size_t>(chart.atlas)]);
    });

    // Lights that light a common texel conflict; each takes the first channel its coloured
    // neighbours leave free.
    std::set<uint64_t> overlaps;
    for (const AtlasMask& atlas : atlases)
        for (const uint64_t reach : atlas.reach) {
            if (std::popcount(reach) > 1) overlaps.insert(reach);
            mask.texels_over_channels += std::popcount(reach) > kShadowmaskChannels;
        }
    std::string left_out;
    for (size_t k = 0; k < realtime.size(); ++k) {
        bool taken[kShadowmaskChannels] = {};
        for (const uint64_t reach : overlaps)
            if (reach >> k & 1)
                for (size_t j = 0; j < k; ++j)
                    if ((reach >> j & 1) && mask.channel[realtime[j]] >= 0) taken[mask.channel[realtime[j]]] = true;
        const auto free = std::find(std::begin(taken), std::end(taken), false);
        if (free != std::end(taken)) {
            mask.channel[realtime[k]] = static_cast<int>(free - std::begin(taken));
        } else {
            ++mask.lights_without_channel;
            left_out += (left_out.empty() ? "'" : ", '") + scene.lights[realtime[k]].name + "'";
        }
    }
    if (mask.lights_without_channel > 0)
        diagnostics.warning({scene.source_path, 0, 0},
                            std::to_string(mask.lights_without_channel) + " real-time light(s) have no shadowmask channel (" +
                                left_out + "): more than " + std::to_string(kShadowmaskChannels) +
                                " overlap at " + std::to_string(mask.texels_over_channels) + " texels");

    for (size_t a = 0; a < atlases.size(); ++a) {
        AtlasMask& atlas = atlases[a];
        std::vector<uint8_t> image(atlas.reach.size() * 4, 255);
        for (size_t i = 0; i < atlas.reach.size(); ++i)
            for (size_t k = 0; k < realtime.size(); ++k)
                if ((atlas.reach[i] >> k & 1) && mask.channel[realtime[k]] >= 0)
                    image[4 * i + static_cast<size_t>(mask.channel[realtime[k]])] = atlas.seen[k][i];
        for (const uint32_t c : layout.atlases[a].charts)
            dilateChartTexels(layout.charts[c], padding, atlas.width, atlas.height, atlas.covered,
                              [&](size_t to, size_t from) { std::copy_n(&image[4 * from], 4, &image[4 * to]); });
        mask.images.push_back(std::move(image));
        mask.widths.push_back(atlas.width);
        mask.heights.push_back(atlas.height);
    }
    return mask;
}

}  // namespace radbake
