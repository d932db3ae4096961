// Charts narrower than a texel (issue 27): the sides of a board 4 mm thick at 16 texels/m,
// two-sided, with light as the read-out gives it on thin boards of real scenes (a point
// exactly on an edge reads the face it meets there). The edge and seam fit keeps every covered
// texel within the light read on its chart, and the lookup at each texel's own point at that
// point's light: the lines along a side's edges do not light (or darken) the side.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "bake/lightmap_adaptive.h"
#include "bake/lightmap_pack.h"
#include "bake/lightmap_seams.h"
#include "scene/two_sided.h"
#include "../radiosity/test_scenes.h"

using namespace radbake;
using namespace radbake::test;

namespace {

constexpr double kTop = 0.704;  // the board spans [0.5, 1.5] x [0.8, 1.2] x [0.7, kTop]

// Six quads facing out, each its own two-sided mesh: none is closed, so each gets a back
// twin facing into the board.
Scene thinBoard() {
    Scene scene;
    const uint32_t wood = addMaterial(scene, Vec3(0.6f, 0.5f, 0.4f), Vec3(0.0f));
    Scene box;
    addInwardBox(box, wood, Vec3(0.5f, 0.8f, 0.7f), Vec3(1.5f, 1.2f, static_cast<float>(kTop)));
    for (Mesh& face : box.meshes) {
        std::reverse(face.positions.begin(), face.positions.end());
        face.solid = false;
        scene.meshes.push_back(face);
    }
    addBackTwins(scene);
    return scene;
}

bool intoBoard(const SurfacePoint& at) { return glm::dot(at.normal_world, at.p_world - DVec3(1.0, 1.0, 0.702)) < 0.0; }
bool sideFace(const SurfacePoint& at) { return std::fabs(at.normal_world.z) < 0.5; }

// H / pi: the top 1, the sides 0.3, the bottom 0.1. A point exactly on a side's edge reads
// the face it meets there, as the read-out does at such edges of real boards (it sees past
// the corner): outside, the top's light along the top edge and the bottom's along the bottom one;
// inside the board, 0 but the top's light along the top edge.
DVec3 boardLight(const SurfacePoint& at) {
    const DVec3& p = at.p_world;
    const bool top_edge = std::fabs(p.z - kTop) < 1e-6, bottom_edge = std::fabs(p.z - 0.7) < 1e-6;
    if (intoBoard(at)) return DVec3(sideFace(at) && top_edge ? kPi : 0.0);
    if (!sideFace(at)) return DVec3(at.normal_world.z > 0.0 ? kPi : 0.1 * kPi);
    return kPi * DVec3(top_edge ? 1.0 : bottom_edge ? 0.1 : 0.3);
}

struct Board {
    Scene scene = thinBoard();
    LightmapOptions options;
    Lightmaps before, after;  // texels as evaluated (dilated), then fitted to the edges
    Board() {
        options.texels_per_metre = 16.0;  // the sides are 0.064 texel wide
        options.atlas_size = 256;
        LightmapLayout layout;
        Diagnostics diagnostics;
        REQUIRE(packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics));
        before = evaluateLightmaps(std::move(layout), boardLight, options.padding, testRunner());
        after = before;
        stitchLightmaps(scene, after, boardLight, options.padding, testRunner());
    }
};

double brightest(const DVec3& v) { return std::max({v.x, v.y, v.z}); }

DVec3 texelValue(const LightmapImage& image, int x, int y) {
    const size_t at = 3 * (static_cast<size_t>(y) * image.width + x);
    return DVec3(image.rgb[at], image.rgb[at + 1], image.rgb[at + 2]);
}

SurfacePoint surfacePoint(const LightmapChart& chart, const TexelSite& site) {
    const ChartFace& face = chart.faces[site.face];
    return SurfacePoint{face.worldPoint(site.p_plane), face.normal_world, chart.mesh, face.triangle};
}

}  // namespace

TEST_CASE("thin board: no covered texel leaves the light read on its chart") {
    const Board board;
    const ChartEdges edges = findChartEdges(board.scene, board.after.layout);
    size_t thin = 0;
    for (uint32_t c = 0; c < board.after.layout.charts.size(); ++c) {
        const LightmapChart& chart = board.after.layout.charts[c];
        const std::vector<TexelSite> sites = chartTexelSites(chart, testRunner());
        // The light read on the chart: at its texels' points and its edge points.
        double lo = 1e300, hi = 0.0;
        for (const TexelSite& site : sites)
            if (site.cover != TexelCover::Empty) {
                const double h = brightest(boardLight(surfacePoint(chart, site))) / kPi;
                lo = std::min(lo, h), hi = std::max(hi, h);
            }
        for (const EdgeSample& e : edges.edges)
            if (e.chart == c) {
                const double h = brightest(boardLight({e.p_world, e.normal_world, e.mesh, e.triangle})) / kPi;
                lo = std::min(lo, h), hi = std::max(hi, h);
            }
        thin += std::min(chart.width, chart.height) <= 2;
        for (size_t t = 0; t < sites.size(); ++t) {
            if (sites[t].cover == TexelCover::Empty) continue;
            const double value = brightest(texelValue(board.after.images[chart.atlas], chart.x + static_cast<int>(t % chart.width),
                                                      chart.y + static_cast<int>(t / chart.width)));
            CHECK(value >= lo - 1e-6);
            CHECK(value <= hi + 1e-6);
        }
    }
    CHECK(thin == 8);  // the four sides, each seen from out and in
}

TEST_CASE("thin board: a side reads the light of its own points, not of the lines along its edges") {
    // A renderer's lookup on a side (under a texel wide) reads its texels and the padding about
    // equally: at each texel's own point it must give that point's light.
    const Board board;
    size_t dark = 0, lit = 0;
    for (const LightmapChart& chart : board.after.layout.charts) {
        const std::vector<TexelSite> sites = chartTexelSites(chart, testRunner());
        for (size_t t = 0; t < sites.size(); ++t) {
            const SurfacePoint at = surfacePoint(chart, sites[t]);
            if (sites[t].cover == TexelCover::Empty || !sideFace(at)) continue;
            const int x = chart.x + static_cast<int>(t % chart.width), y = chart.y + static_cast<int>(t / chart.width);
            const double own = brightest(texelValue(board.before.images[chart.atlas], x, y));
            const double lookup = brightest(bilinearLookup(board.after.images[chart.atlas], chart.atlasTexel(sites[t].p_plane)));
            CHECK(own == doctest::Approx(intoBoard(at) ? 0.0 : 0.3));
            CHECK(std::fabs(lookup - own) <= 0.01);
            if (intoBoard(at)) {  // the texel itself stays dark too: nothing around it is lit
                ++dark;
                CHECK(brightest(texelValue(board.after.images[chart.atlas], x, y)) <= 1e-3);
            } else {
                ++lit;
            }
        }
    }
    CHECK(dark == 2 * (16 + 7));
    CHECK(lit == 2 * (16 + 7));
}
