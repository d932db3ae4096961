#pragma once
// A chart's texels: which face holds a texel's centre, and the dilation of per-texel data beside
// the lightmap (the shadowmask, the directions) into the chart's padding.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "bake/lightmap_charts.h"

namespace radbake {

// Texels of a chart's padded rectangle off its geometry take a covered 4-neighbour's value, ring
// by ring, so bilinear filtering at the chart's edge reads the chart's own values. `covered`
// (atlas width x height) marks the texels with values and is updated; copy(to, from) copies one
// texel's value.
template <class Copy>
void dilateChartTexels(const LightmapChart& chart, int padding, int width, int height, std::vector<uint8_t>& covered,
                       Copy&& copy) {
    const int x0 = std::max(0, chart.x - padding), x1 = std::min(width, chart.x + chart.width + padding);
    const int y0 = std::max(0, chart.y - padding), y1 = std::min(height, chart.y + chart.height + padding);
    const auto index = [&](int x, int y) { return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x); };
    for (std::vector<size_t> filled{1}; !filled.empty();) {
        filled.clear();
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                if (covered[index(x, y)]) continue;
                const int near[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
                for (const auto& n : near)
                    if (n[0] >= x0 && n[0] < x1 && n[1] >= y0 && n[1] < y1 && covered[index(n[0], n[1])]) {
                        copy(index(x, y), index(n[0], n[1]));
                        filled.push_back(index(x, y));
                        break;
                    }
            }
        for (const size_t i : filled) covered[i] = 1;
    }
}

// The centre of atlas texel (tx, ty) in the chart's plane.
inline DVec2 texelCentre(const LightmapChart& chart, int tx, int ty) {
    return chart.min_plane + (DVec2(tx - chart.x, ty - chart.y) + 0.5) / chart.texels_per_metre;
}

// Whether `p` lies on the face (its polygon is convex and counter-clockwise; the outline counts).
inline bool onFace(const ChartFace& face, const DVec2& p) {
    for (size_t k = 0; k < face.p_plane.size(); ++k) {
        const DVec2 e = face.p_plane[(k + 1) % face.p_plane.size()] - face.p_plane[k], d = p - face.p_plane[k];
        if (e.x * d.y - e.y * d.x < 0.0) return false;
    }
    return true;
}

// The chart face holding the centre of atlas texel (tx, ty), and that centre in the chart's
// plane; null when the centre is off the chart's geometry.
inline const ChartFace* faceAtTexel(const LightmapChart& chart, int tx, int ty, DVec2& centre) {
    centre = texelCentre(chart, tx, ty);
    for (const ChartFace& face : chart.faces)
        if (onFace(face, centre)) return &face;
    return nullptr;
}

}  // namespace radbake
