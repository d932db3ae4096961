#pragma once
// A chart's texels: which face holds a texel's centre, and the dilation of per-texel data beside
// the lightmap (the shadowmask, the directions) into the chart's padding.
#include <algorithm>
#include <cstdint>
#include <span>
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

// Per-texel records of some charts' rectangles, for the parts of a read-out split by chart:
// `size` bytes a texel, chart after chart (increasing), row after row.
struct ChartRecords {
    std::vector<uint32_t> charts;
    uint32_t size = 0;
    std::vector<uint8_t> bytes;
};

inline bool chartWanted(std::span<const uint8_t> wanted, size_t chart) {
    return wanted.empty() || (chart < wanted.size() && wanted[chart]);
}

// The records of the placed charts `wanted` selects (empty: all); get(atlas, texel, out) writes
// one texel's `size` bytes.
template <class Get>
ChartRecords collectChartRecords(const LightmapLayout& layout, std::span<const uint8_t> wanted, uint32_t size, Get&& get) {
    ChartRecords records;
    records.size = size;
    for (uint32_t c = 0; c < layout.charts.size(); ++c) {
        const LightmapChart& chart = layout.charts[c];
        if (chart.atlas < 0 || !chartWanted(wanted, c)) continue;
        records.charts.push_back(c);
        const size_t width = static_cast<size_t>(layout.atlases[static_cast<size_t>(chart.atlas)].width);
        for (int y = chart.y; y < chart.y + chart.height; ++y)
            for (int x = chart.x; x < chart.x + chart.width; ++x) {
                records.bytes.resize(records.bytes.size() + size);
                get(static_cast<size_t>(chart.atlas), static_cast<size_t>(y) * width + static_cast<size_t>(x),
                    records.bytes.data() + records.bytes.size() - size);
            }
    }
    return records;
}

// Calls put(atlas, texel, bytes) for every texel of parts that cover every placed chart once,
// with records of `size` bytes; false (part way) when they do not.
template <class Put>
bool spreadChartRecords(const LightmapLayout& layout, std::span<const ChartRecords> parts, uint32_t size, Put&& put) {
    std::vector<uint8_t> seen(layout.charts.size(), 0);
    for (const ChartRecords& part : parts) {
        if (part.size != size) return false;
        size_t at = 0;
        for (const uint32_t c : part.charts) {
            if (c >= layout.charts.size() || seen[c] || layout.charts[c].atlas < 0) return false;
            seen[c] = 1;
            const LightmapChart& chart = layout.charts[c];
            const size_t width = static_cast<size_t>(layout.atlases[static_cast<size_t>(chart.atlas)].width);
            if (at + static_cast<size_t>(chart.width) * chart.height * size > part.bytes.size()) return false;
            for (int y = chart.y; y < chart.y + chart.height; ++y)
                for (int x = chart.x; x < chart.x + chart.width; ++x, at += size)
                    put(static_cast<size_t>(chart.atlas), static_cast<size_t>(y) * width + static_cast<size_t>(x),
                        part.bytes.data() + at);
        }
        if (at != part.bytes.size()) return false;
    }
    for (size_t c = 0; c < layout.charts.size(); ++c)
        if (layout.charts[c].atlas >= 0 && !seen[c]) return false;
    return true;
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
