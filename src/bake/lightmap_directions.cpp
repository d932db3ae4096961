#include "bake/lightmap_directions.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <optional>

#include "bake/chart_texels.h"
#include "geometry/polygon.h"
#include "readout/evaluate_probe.h"
#include "readout/reconstruct.h"

namespace radbake {
namespace {

double luminance(const DVec3& rgb) { return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z; }

constexpr int kDirectionSamples = 8;  // tilted normals a texel is read at, round its normal

// Zero directions and no texel covered, per atlas of the layout.
void emptyDirections(const LightmapLayout& layout, LightmapDirections& out, std::vector<std::vector<uint8_t>>& covered) {
    for (const LightmapAtlas& atlas : layout.atlases) {
        const size_t texels = static_cast<size_t>(atlas.width) * static_cast<size_t>(atlas.height);
        out.images.emplace_back(texels * 3, 0.0f);
        covered.emplace_back(texels, 0);
        out.widths.push_back(atlas.width);
        out.heights.push_back(atlas.height);
    }
}

}  // namespace

ChartRecords readDirectionRecords(const Solution& solution, const ReadoutOptions& readout, const LightmapLayout& layout,
                                  std::span<const uint8_t> wanted, ParallelRunner& runner) {
    LightmapDirections out;
    std::vector<std::vector<uint8_t>> covered;
    emptyDirections(layout, out, covered);
    std::optional<LinkReconstruction> links;
    if (readout.gather == GatherMode::Links) links.emplace(solution, readout, runner);
    const auto read = [&](uint32_t mesh, uint32_t triangle, const DVec3& p, const DVec3& n) {
        return links ? links->irradiance(mesh, triangle, p, n, LinkReconstruction::Reading::Texel)
                     : surfaceIrradiance(solution, readout, p, n, mesh, triangle);
    };
    const double tilt = kDirectionTiltDegrees * kPi / 180.0, c = std::cos(tilt), s = std::sin(tilt);
    // Charts' rectangles are disjoint: each task writes its own texels.
    runner.forEach(layout.charts.size(), 1, [&](size_t index) {
        const LightmapChart& chart = layout.charts[index];
        if (chart.atlas < 0 || !chartWanted(wanted, index)) return;
        const size_t a = static_cast<size_t>(chart.atlas);
        for (int ty = chart.y; ty < chart.y + chart.height; ++ty)
            for (int tx = chart.x; tx < chart.x + chart.width; ++tx) {
                DVec2 centre;
                const ChartFace* face = faceAtTexel(chart, tx, ty, centre);
                if (!face) continue;
                const size_t i = static_cast<size_t>(ty) * static_cast<size_t>(out.widths[a]) + static_cast<size_t>(tx);
                covered[a][i] = 1;
                const DVec3 p = face->worldPoint(centre), n0 = face->normal_world;
                DVec3 t, b;
                tangentFrame(n0, t, b);
                const double e0 = luminance(read(chart.mesh, face->triangle, p, n0));
                if (!(e0 > 0.0)) continue;
                // b minimising the relative error of e0 + b . (n - n0) at eight normals 30 degrees
                // round n0 (exact at n0): light near a tilted horizon bends E(n) away from linear,
                // so a fit exact at a few tilts misses the others.
                glm::dmat3 normal_matrix(0.0);
                DVec3 right(0.0);
                for (int k = 0; k < kDirectionSamples; ++k) {
                    const double azimuth = 2.0 * kPi * k / kDirectionSamples;
                    const DVec3 n = c * n0 + s * (std::cos(azimuth) * t + std::sin(azimuth) * b);
                    const double e = luminance(read(chart.mesh, face->triangle, p, n));
                    const DVec3 d = n - n0;
                    const double w = 1.0 / std::max(e * e, 1e-6 * e0 * e0);
                    normal_matrix += w * glm::outerProduct(d, d);
                    right += w * (e - e0) * d;
                }
                const DVec3 g = glm::inverse(normal_matrix) * right / e0;
                for (int k = 0; k < 3; ++k) out.images[a][3 * i + k] = static_cast<float>(g[k]);
            }
    });
    return collectChartRecords(layout, wanted, kDirectionRecord, [&](size_t atlas, size_t texel, uint8_t* record) {
        std::memcpy(record, &out.images[atlas][3 * texel], 3 * sizeof(float));
        record[3 * sizeof(float)] = covered[atlas][texel];
    });
}

std::optional<LightmapDirections> assembleDirections(const LightmapLayout& layout, int padding,
                                                     std::span<const ChartRecords> parts) {
    LightmapDirections out;
    std::vector<std::vector<uint8_t>> covered;
    emptyDirections(layout, out, covered);
    const bool whole = spreadChartRecords(layout, parts, kDirectionRecord, [&](size_t atlas, size_t texel, const uint8_t* record) {
        std::memcpy(&out.images[atlas][3 * texel], record, 3 * sizeof(float));
        covered[atlas][texel] = record[3 * sizeof(float)];
        out.texels += record[3 * sizeof(float)];
    });
    if (!whole) return std::nullopt;
    for (size_t a = 0; a < layout.atlases.size(); ++a)
        for (const uint32_t chart : layout.atlases[a].charts)
            dilateChartTexels(layout.charts[chart], padding, out.widths[a], out.heights[a], covered[a],
                              [&](size_t to, size_t from) { std::copy_n(&out.images[a][3 * from], 3, &out.images[a][3 * to]); });
    return out;
}

LightmapDirections bakeLightmapDirections(const Solution& solution, const ReadoutOptions& readout,
                                          const LightmapLayout& layout, int padding, ParallelRunner& runner) {
    const ChartRecords all = readDirectionRecords(solution, readout, layout, {}, runner);
    return *assembleDirections(layout, padding, std::span<const ChartRecords>(&all, 1));
}

}  // namespace radbake
