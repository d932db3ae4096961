// Atlas packing, checked texel by texel: no two charts (with their padding) share a texel,
// everything is inside its atlas, every chart is placed, occupancy is what the texels say.
#include <doctest/doctest.h>

#include <random>

#include "bake/lightmap_pack.h"

using namespace radbake;

namespace {

std::vector<LightmapChart> chartsOfSizes(const std::vector<std::pair<int, int>>& sizes) {
    std::vector<LightmapChart> charts;
    for (const auto& [w, h] : sizes) {
        LightmapChart chart;
        chart.width = w;
        chart.height = h;
        charts.push_back(chart);
    }
    return charts;
}

// Marks each chart's padded rectangle texel by texel; fails on any texel claimed twice or
// outside the atlas. Returns the number of texels claimed by charts proper.
size_t checkTexelByTexel(const LightmapLayout& layout, int padding) {
    std::vector<std::vector<int>> owner(layout.atlases.size());
    for (size_t a = 0; a < layout.atlases.size(); ++a)
        owner[a].assign(static_cast<size_t>(layout.atlases[a].width) * layout.atlases[a].height, -1);
    size_t chart_texels = 0, overlaps = 0, outside = 0;
    for (size_t c = 0; c < layout.charts.size(); ++c) {
        const LightmapChart& chart = layout.charts[c];
        REQUIRE(chart.atlas >= 0);
        REQUIRE(chart.atlas < static_cast<int>(layout.atlases.size()));
        const LightmapAtlas& atlas = layout.atlases[chart.atlas];
        for (int y = chart.y - padding; y < chart.y + chart.height + padding; ++y)
            for (int x = chart.x - padding; x < chart.x + chart.width + padding; ++x) {
                if (x < 0 || y < 0 || x >= atlas.width || y >= atlas.height) {
                    ++outside;
                    continue;
                }
                int& cell = owner[chart.atlas][static_cast<size_t>(y) * atlas.width + x];
                if (cell != -1) ++overlaps;
                cell = static_cast<int>(c);
            }
        chart_texels += static_cast<size_t>(chart.width) * chart.height;
    }
    CHECK(overlaps == 0);
    CHECK(outside == 0);
    return chart_texels;
}

}  // namespace

TEST_CASE("random charts pack without overlap and with padding, texel by texel") {
    std::mt19937 random(12345);
    std::uniform_int_distribution<int> side(1, 60);
    for (int padding : {0, 1, 2, 4}) {
        CAPTURE(padding);
        std::vector<std::pair<int, int>> sizes;
        for (int i = 0; i < 300; ++i) sizes.emplace_back(side(random), side(random));
        LightmapOptions options;
        options.atlas_size = 256;
        options.padding = padding;
        LightmapLayout layout;
        Diagnostics diagnostics;
        REQUIRE(packLightmapCharts(chartsOfSizes(sizes), options, layout, diagnostics));
        REQUIRE(layout.charts.size() == 300);
        CHECK(layout.atlases.size() >= 2);  // ~280k texels of charts do not fit 65k
        size_t listed = 0, atlas_texels = 0;
        for (const LightmapAtlas& atlas : layout.atlases) {
            CHECK(atlas.width <= 256);
            CHECK(atlas.height <= atlas.width);
            CHECK(atlas.height % 4 == 0);
            listed += atlas.charts.size();
            atlas_texels += static_cast<size_t>(atlas.width) * atlas.height;
        }
        CHECK(listed == 300);
        for (size_t c = 0; c < layout.charts.size(); ++c) {  // sizes kept, in order
            CHECK(layout.charts[c].width == sizes[c].first);
            CHECK(layout.charts[c].height == sizes[c].second);
        }
        const size_t chart_texels = checkTexelByTexel(layout, padding);
        CHECK(layout.occupancy == doctest::Approx(static_cast<double>(chart_texels) / atlas_texels));
        if (padding == 0) CHECK(layout.padded_occupancy == layout.occupancy);
        else CHECK(layout.padded_occupancy > layout.occupancy);
        CHECK(layout.padded_occupancy <= 1.0);
    }
}

TEST_CASE("atlases fill one after another and the last one shrinks") {
    // 60 x 60 charts with padding 2 take 64 x 64: four per 128 atlas; 17 charts: 4 full + 1.
    LightmapOptions options;
    options.atlas_size = 128;
    options.padding = 2;
    LightmapLayout layout;
    Diagnostics diagnostics;
    REQUIRE(packLightmapCharts(chartsOfSizes(std::vector<std::pair<int, int>>(17, {60, 60})), options, layout, diagnostics));
    REQUIRE(layout.atlases.size() == 5);
    for (int a = 0; a < 4; ++a) {
        CHECK(layout.atlases[a].width == 128);
        CHECK(layout.atlases[a].charts.size() == 4);
    }
    CHECK(layout.atlases[4].width == 64);
    CHECK(layout.atlases[4].height == 64);
    CHECK(layout.atlases[4].charts.size() == 1);
    checkTexelByTexel(layout, 2);
    CHECK(layout.occupancy == doctest::Approx(17.0 * 3600.0 / (4 * 128 * 128 + 64 * 64)));

    // A small scene gets a small atlas.
    REQUIRE(packLightmapCharts(chartsOfSizes({{10, 10}, {5, 3}}), options, layout, diagnostics));
    REQUIRE(layout.atlases.size() == 1);
    CHECK(layout.atlases[0].width == 32);
    CHECK(layout.atlases[0].height == 16);  // rows 0..13 used (14 = 10 + 2 * 2), rounded up to 4
    checkTexelByTexel(layout, 2);
}

TEST_CASE("a chart larger than the atlas is reported") {
    LightmapOptions options;
    options.atlas_size = 64;
    options.padding = 2;
    LightmapLayout layout;
    Diagnostics diagnostics;
    CHECK_FALSE(packLightmapCharts(chartsOfSizes({{10, 10}, {61, 5}}), options, layout, diagnostics));
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].message == "lightmap chart of 61x5 texels (mesh 0) does not fit a 64 atlas with padding 2");
}
