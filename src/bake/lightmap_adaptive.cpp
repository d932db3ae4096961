// Adaptive texel evaluation: a quadtree over each chart's texels, evaluated level by level.
#include "bake/lightmap_adaptive.h"

#include <algorithm>
#include <atomic>
#include <cmath>


namespace radbake {
namespace {

// A texel is fully covered when its clipped pieces fill its square to this relative
// rounding (clipping and the shoelace sums lose ~1e-15 of the texel area; the slack covers
// faces that meet with float-rounded corners).
constexpr double kFullCoverage = 1.0 - 1e-6;
// A block's corners may differ by at most this fraction of its light (whatever the
// tolerance): a steady gradient is interpolated exactly, and the test points check that it is
// steady, but a block spanning a large change (half a penumbra) could hide a feature between
// its test points. Lit surfaces at 64 texels/m change by ~4% a texel (Cornell box floor), so
// a bound in tolerances would refuse every 8-texel block on them.
constexpr double kMaxSpread = 0.5;

constexpr TexelCover kEmpty = TexelCover::Empty, kPartial = TexelCover::Partial, kFull = TexelCover::Full;
enum Fill : uint8_t { kNone = 0, kEvaluated = 1, kInterpolated = 2 };

// One chart's texels, flattened into the global arrays at `offset`.
struct ChartSpan {
    size_t offset = 0;
    int width = 0, height = 0;
};

struct Block {
    uint32_t chart = 0;
    int i0 = 0, i1 = 0, j0 = 0, j1 = 0;  // corner texels, inclusive
};

struct State {
    const LightmapLayout& layout;
    const IrradianceFunction& irradiance;
    std::vector<ChartSpan> spans{};
    std::vector<TexelSite> sites{};
    std::vector<DVec3> values{};  // H / pi
    std::vector<Fill> fill{};
    std::vector<uint8_t> requested{};
    size_t evaluations = 0;
    // Progress: the texel phase moves progress from 0 to kTexelShare of the lightmap phase,
    // by texels settled (evaluated, or inside a block accepted for interpolation) over covered.
    Progress* progress = nullptr;
    size_t covered = 0;
    std::atomic<size_t> settled{0};

    void reportProgress() const {
        if (progress && covered > 0)
            progress->update(kTexelShare * std::min(1.0, static_cast<double>(settled) / static_cast<double>(covered)));
    }

    size_t at(const Block& b, int i, int j) const { return spans[b.chart].offset + static_cast<size_t>(j) * spans[b.chart].width + i; }
};

// Lattice coordinates along one axis: every step-th texel and the last one.
std::vector<int> lattice(int count, int step) {
    std::vector<int> coords;
    for (int k = 0; k < count; k += step) coords.push_back(k);
    if (coords.back() != count - 1) coords.push_back(count - 1);
    return coords;
}

// Evaluates the requested texels in parallel, each into its own slot.
void evaluateBatch(State& s, std::vector<size_t>& batch, ParallelRunner& runner) {
    runner.forRanges(batch.size(), 16, [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) {
            const size_t t = batch[k];
            // The chart of a flat index: spans are sorted by offset.
            const auto it = std::upper_bound(s.spans.begin(), s.spans.end(), t,
                                             [](size_t v, const ChartSpan& span) { return v < span.offset; });
            const LightmapChart& chart = s.layout.charts[static_cast<size_t>(it - s.spans.begin()) - 1];
            const ChartFace& face = chart.faces[s.sites[t].face];
            s.values[t] = s.irradiance({face.worldPoint(s.sites[t].p_plane), face.normal_world, chart.mesh, face.triangle}) / kPi;
            s.fill[t] = kEvaluated;
        }
        s.settled += end - begin;
        s.reportProgress();
    });
    s.evaluations += batch.size();
    batch.clear();
}

void request(State& s, size_t t, std::vector<size_t>& batch) {
    if (s.sites[t].cover == kEmpty || s.requested[t]) return;
    s.requested[t] = 1;
    batch.push_back(t);
}

// Every texel of the closed block is fully covered (no chart edge crosses it).
bool interpolable(const State& s, const Block& b) {
    if (b.i1 == b.i0 || b.j1 == b.j0) return false;  // a one-texel-wide chart: evaluate it
    for (int j = b.j0; j <= b.j1; ++j)
        for (int i = b.i0; i <= b.i1; ++i)
            if (s.sites[s.at(b, i, j)].cover != kFull) return false;
    return true;
}

// Bilinear interpolation of the block's corner values at a plane point, inverting the
// bilinear map of the corners' sample points (Newton from the texel-index guess), so a
// field linear in the plane is reproduced exactly wherever the sample points sit.
DVec3 interpolate(const State& s, const Block& b, int i, int j) {
    const size_t ia = s.at(b, b.i0, b.j0), ib = s.at(b, b.i1, b.j0), ic = s.at(b, b.i0, b.j1), id = s.at(b, b.i1, b.j1);
    const DVec2 a = s.sites[ia].p_plane, e_s = s.sites[ib].p_plane - a, e_t = s.sites[ic].p_plane - a;
    const DVec2 twist = a - s.sites[ib].p_plane - s.sites[ic].p_plane + s.sites[id].p_plane;
    const DVec2 target = s.sites[s.at(b, i, j)].p_plane;
    const double s0 = static_cast<double>(i - b.i0) / (b.i1 - b.i0), t0 = static_cast<double>(j - b.j0) / (b.j1 - b.j0);
    double u = s0, v = t0;
    for (int iteration = 0; iteration < 6; ++iteration) {
        const DVec2 f = a + u * e_s + v * e_t + u * v * twist - target;
        const DVec2 ju = e_s + v * twist, jv = e_t + u * twist;
        const double det = ju.x * jv.y - ju.y * jv.x;
        if (!(std::fabs(det) > 0.0)) break;
        u -= (f.x * jv.y - f.y * jv.x) / det;
        v -= (ju.x * f.y - ju.y * f.x) / det;
    }
    // A wild solution (a folded corner quad) falls back to the texel-index position.
    if (!(u >= -0.5 && u <= 1.5 && v >= -0.5 && v <= 1.5)) u = s0, v = t0;
    return (1.0 - u) * (1.0 - v) * s.values[ia] + u * (1.0 - v) * s.values[ib] + (1.0 - u) * v * s.values[ic] +
           u * v * s.values[id];
}

int middle(int lo, int hi) { return lo + (hi - lo) / 2; }

// The block's light is smooth: its corners differ by at most kMaxSpread, and every
// texel evaluated inside it (centre, edge midpoints, texels next to chart edges) matches
// the bilinear prediction within the tolerance, relative to the block's light or the floor.
bool smooth(const State& s, const Block& b, double tolerance, double floor) {
    const DVec3 corner[4] = {s.values[s.at(b, b.i0, b.j0)], s.values[s.at(b, b.i1, b.j0)], s.values[s.at(b, b.i0, b.j1)],
                             s.values[s.at(b, b.i1, b.j1)]};
    DVec3 allowed;
    for (int c = 0; c < 3; ++c) {
        double lo = corner[0][c], hi = corner[0][c], sum = 0.0;
        for (const DVec3& v : corner) {
            lo = std::min(lo, v[c]);
            hi = std::max(hi, v[c]);
            sum += v[c];
        }
        const double level = std::max(std::fabs(sum) / 4.0, floor);
        allowed[c] = tolerance * level;
        if (hi - lo > kMaxSpread * level) return false;
    }
    for (int j = b.j0; j <= b.j1; ++j)
        for (int i = b.i0; i <= b.i1; ++i) {
            const size_t t = s.at(b, i, j);
            if (s.fill[t] != kEvaluated) continue;
            const DVec3 predicted = interpolate(s, b, i, j);
            for (int c = 0; c < 3; ++c)
                if (std::fabs(s.values[t][c] - predicted[c]) > allowed[c]) return false;
        }
    return true;
}

void split(const Block& b, std::vector<Block>& out) {
    const int mi = b.i1 - b.i0 >= 2 ? middle(b.i0, b.i1) : -1, mj = b.j1 - b.j0 >= 2 ? middle(b.j0, b.j1) : -1;
    const std::vector<std::pair<int, int>> is = mi < 0 ? std::vector<std::pair<int, int>>{{b.i0, b.i1}}
                                                       : std::vector<std::pair<int, int>>{{b.i0, mi}, {mi, b.i1}};
    const std::vector<std::pair<int, int>> js = mj < 0 ? std::vector<std::pair<int, int>>{{b.j0, b.j1}}
                                                       : std::vector<std::pair<int, int>>{{b.j0, mj}, {mj, b.j1}};
    for (const auto& [j0, j1] : js)
        for (const auto& [i0, i1] : is) out.push_back(Block{b.chart, i0, i1, j0, j1});
}

bool leaf(const Block& b) { return b.i1 - b.i0 <= 1 && b.j1 - b.j0 <= 1; }

// The texels a leaf block owns: half-open on its far sides, except at the chart's last
// column and row, so the leaves of a chart partition its texels.
void interpolateOwned(State& s, const Block& b) {
    const ChartSpan& span = s.spans[b.chart];
    const int i_end = b.i1 == span.width - 1 ? b.i1 : b.i1 - 1, j_end = b.j1 == span.height - 1 ? b.j1 : b.j1 - 1;
    for (int j = b.j0; j <= j_end; ++j)
        for (int i = b.i0; i <= i_end; ++i) {
            const size_t t = s.at(b, i, j);
            if (s.fill[t] != kNone || s.sites[t].cover == kEmpty) continue;
            s.values[t] = interpolate(s, b, i, j);
            s.fill[t] = kInterpolated;
        }
}

}  // namespace

std::vector<TexelSite> chartTexelSites(const LightmapChart& chart, ParallelRunner& runner, const HiddenTest& hidden) {
    const int width = chart.width, height = chart.height;
    std::vector<TexelSite> sites(static_cast<size_t>(width) * height);
    runner.forRanges(sites.size(), 64, [&](size_t begin, size_t end) {
        for (size_t t = begin; t < end; ++t) {
            TexelSite& site = sites[t];
            size_t face = 0;
            const double covered =
                texelCoverage(chart, static_cast<int>(t % width), static_cast<int>(t / width), site.p_plane, face);
            site.face = static_cast<uint32_t>(face);
            site.cover = covered <= 0.0 ? kEmpty : covered >= kFullCoverage ? kFull : kPartial;
            if (site.cover == kEmpty || !hidden) continue;
            const ChartFace& on = chart.faces[face];
            if (hidden({on.worldPoint(site.p_plane), on.normal_world, chart.mesh, on.triangle})) {
                site.cover = kEmpty;
                site.hidden = true;
            }
        }
    });
    const auto full = [&](int i, int j) {
        return i >= 0 && j >= 0 && i < width && j < height && sites[static_cast<size_t>(j) * width + i].cover == kFull;
    };
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            TexelSite& site = sites[static_cast<size_t>(j) * width + i];
            if (site.cover == kEmpty) continue;
            site.edge = site.cover == kPartial;
            for (int dj = -1; dj <= 1 && !site.edge; ++dj)
                for (int di = -1; di <= 1 && !site.edge; ++di) site.edge = !full(i + di, j + dj);
        }
    return sites;
}

AdaptiveCounts evaluateTexelsAdaptive(const LightmapLayout& layout, std::vector<LightmapImage>& images,
                                      const IrradianceFunction& irradiance, double tolerance, ParallelRunner& runner,
                                      Progress* progress, const HiddenTest& hidden, double dark,
                                      std::span<const uint8_t> wanted) {
    State s{.layout = layout, .irradiance = irradiance, .progress = progress};
    size_t total = 0;
    for (size_t c = 0; c < layout.charts.size(); ++c) {
        const LightmapChart& chart = layout.charts[c];
        const bool filled = chart.atlas >= 0 && (wanted.empty() || (c < wanted.size() && wanted[c]));
        s.spans.push_back(ChartSpan{total, filled ? chart.width : 0, filled ? chart.height : 0});
        total += static_cast<size_t>(s.spans.back().width) * s.spans.back().height;
    }
    s.sites.resize(total);
    s.values.assign(total, DVec3(0.0));
    s.fill.assign(total, kNone);
    s.requested.assign(total, 0);

    // Sample points, coverage and edges of every texel.
    for (uint32_t c = 0; c < layout.charts.size(); ++c) {
        if (s.spans[c].width == 0) continue;
        const std::vector<TexelSite> sites = chartTexelSites(layout.charts[c], runner, hidden);
        std::copy(sites.begin(), sites.end(), s.sites.begin() + static_cast<std::ptrdiff_t>(s.spans[c].offset));
    }
    size_t hidden_texels = 0;
    for (const TexelSite& site : s.sites) {
        s.covered += site.cover != kEmpty ? 1 : 0;
        hidden_texels += site.hidden ? 1 : 0;
    }
    std::vector<size_t> batch;
    std::vector<Block> blocks;
    size_t required = 0;
    for (uint32_t c = 0; c < layout.charts.size(); ++c) {
        const ChartSpan& span = s.spans[c];
        for (int j = 0; j < span.height; ++j)
            for (int i = 0; i < span.width; ++i) {
                const TexelSite& site = s.sites[span.offset + static_cast<size_t>(j) * span.width + i];
                if (site.cover == kEmpty) continue;
                const bool must = tolerance <= 0.0 || site.edge;
                if (must) request(s, span.offset + static_cast<size_t>(j) * span.width + i, batch);
                required += must;
            }
        if (tolerance <= 0.0 || span.width == 0) continue;
        const std::vector<int> is = lattice(span.width, kCoarsestStep), js = lattice(span.height, kCoarsestStep);
        for (size_t bj = 0; bj + 1 < std::max<size_t>(js.size(), 2); ++bj)
            for (size_t bi = 0; bi + 1 < std::max<size_t>(is.size(), 2); ++bi) {
                const int i0 = is[std::min(bi, is.size() - 1)], i1 = is[std::min(bi + 1, is.size() - 1)];
                const int j0 = js[std::min(bj, js.size() - 1)], j1 = js[std::min(bj + 1, js.size() - 1)];
                blocks.push_back(Block{c, i0, i1, j0, j1});
            }
    }

    // Level by level: evaluate the blocks' corners (and, for candidates, their test points), then
    // accept smooth blocks and split the others. The decisions read evaluated values only.
    double floor = dark >= 0.0 ? std::max(dark, 1e-300) : -1.0;
    std::vector<Block> accepted;
    while (!blocks.empty()) {
        std::vector<uint8_t> candidate(blocks.size());
        for (size_t k = 0; k < blocks.size(); ++k) {
            const Block& b = blocks[k];
            for (const int j : {b.j0, b.j1})
                for (const int i : {b.i0, b.i1}) request(s, s.at(b, i, j), batch);
            candidate[k] = !leaf(b) && interpolable(s, b);
            if (!candidate[k]) continue;
            // The test points: the next level's corners, so none is wasted when the block splits.
            const int mi = middle(b.i0, b.i1), mj = middle(b.j0, b.j1);
            for (const auto& [i, j] : {std::pair{mi, mj}, std::pair{mi, b.j0}, std::pair{mi, b.j1}, std::pair{b.i0, mj},
                                       std::pair{b.i1, mj}})
                request(s, s.at(b, i, j), batch);
        }
        evaluateBatch(s, batch, runner);
        if (floor < 0.0) {
            double brightest = 0.0;
            for (size_t t = 0; t < total; ++t)
                if (s.fill[t] == kEvaluated) brightest = std::max({brightest, s.values[t].x, s.values[t].y, s.values[t].z});
            floor = std::max(kDarkFloor * brightest, 1e-300);
        }
        std::vector<Block> next;
        for (size_t k = 0; k < blocks.size(); ++k) {
            const Block& b = blocks[k];
            if (leaf(b)) continue;
            if (candidate[k] && smooth(s, b, tolerance, floor)) {
                accepted.push_back(b);
                // Its texels but the (already counted) corners and test points are settled now.
                s.settled += static_cast<size_t>(std::max(0, (b.i1 - b.i0 + 1) * (b.j1 - b.j0 + 1) - 9));
            } else {
                split(b, next);
            }
        }
        blocks = std::move(next);
    }
    runner.forRanges(accepted.size(), 8, [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) interpolateOwned(s, accepted[k]);
    });
    evaluateBatch(s, batch, runner);  // with no blocks (tolerance 0), the texels requested above
    // Safety net: a covered texel no leaf filled (none should remain) is evaluated.
    for (size_t t = 0; t < total; ++t)
        if (s.sites[t].cover != kEmpty && s.fill[t] == kNone) batch.push_back(t);
    evaluateBatch(s, batch, runner);

    AdaptiveCounts counts;
    counts.evaluated = s.evaluations;
    counts.required = tolerance > 0.0 ? required : 0;
    counts.hidden = hidden_texels;
    for (uint32_t c = 0; c < layout.charts.size(); ++c) {
        const LightmapChart& chart = layout.charts[c];
        const ChartSpan& span = s.spans[c];
        if (span.width == 0) continue;
        LightmapImage& image = images[chart.atlas];
        for (int j = 0; j < span.height; ++j)
            for (int i = 0; i < span.width; ++i) {
                const size_t t = span.offset + static_cast<size_t>(j) * span.width + i;
                if (s.fill[t] == kNone) continue;
                const size_t pixel = static_cast<size_t>(chart.y + j) * image.width + chart.x + i;
                for (int ch = 0; ch < 3; ++ch) image.rgb[3 * pixel + ch] = static_cast<float>(s.values[t][ch]);
                image.state[pixel] = TexelState::Covered;
                ++counts.covered;
                counts.interpolated += s.fill[t] == kInterpolated;
            }
    }
    return counts;
}

}  // namespace radbake
