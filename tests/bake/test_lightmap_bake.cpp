// Lightmap texels against closed forms: with a known irradiance field every covered texel
// holds H / pi at a point of its own triangle inside its own square, a chart-corner texel
// agrees with the vertex there to within the field's change over one texel, dilation fills
// every padding texel from its own chart only, and the thread count changes nothing.
#include <doctest/doctest.h>

#include <cmath>

#include "bake/lightmap_bake.h"
#include "lightmap_test_scenes.h"

using namespace radbake;
using lightmap_test::sceneOf;

namespace {

Lightmaps bake(const Scene& scene, const LightmapOptions& options, const IrradianceFunction& f, int threads = 0) {
    LightmapLayout layout;
    Diagnostics diagnostics;
    REQUIRE(packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics));
    ParallelRunner runner(Threading{.threads = threads});
    return evaluateLightmaps(std::move(layout), f, options.padding, runner);
}

// H / pi = 1 + x + 2 z: a plane of light over the floor.
DVec3 linearField(const SurfacePoint& at) { return kPi * DVec3(1.0 + at.p_world.x + 2.0 * at.p_world.z, 1.0, 0.5); }

bool insideTriangle(const DVec2& p, const std::vector<DVec2>& t) {
    for (int k = 0; k < 3; ++k) {
        const DVec2 e = t[(k + 1) % 3] - t[k], d = p - t[k];
        if (e.x * d.y - e.y * d.x < -1e-12) return false;
    }
    return true;
}

}  // namespace

TEST_CASE("covered texels hold H/pi at a point of their own triangle and square") {
    // A triangle floor facing +Y, 3 m by 2 m: half its chart rectangle is empty.
    const Scene scene = sceneOf({lightmap_test::polygonMesh({{0, 0, 0}, {0, 0, 2}, {3, 0, 0}})});
    LightmapOptions options;
    options.texels_per_metre = 8.0;
    options.padding = 2;
    const Lightmaps lightmaps = bake(scene, options, linearField);
    REQUIRE(lightmaps.layout.charts.size() == 1);
    const LightmapChart& chart = lightmaps.layout.charts[0];
    CHECK(chart.width == 24);
    CHECK(chart.height == 16);
    const LightmapImage& image = lightmaps.images[0];
    const std::vector<DVec2>& triangle = chart.faces[0].p_plane;
    size_t covered = 0, centre_inside = 0;
    for (int j = 0; j < chart.height; ++j) {
        for (int i = 0; i < chart.width; ++i) {
            const size_t at = static_cast<size_t>(chart.y + j) * image.width + chart.x + i;
            const DVec2 centre = chart.min_plane + (DVec2(i, j) + 0.5) / chart.texels_per_metre;
            if (insideTriangle(centre, triangle)) {
                ++centre_inside;
                CHECK(image.state[at] == TexelState::Covered);
            }
            if (image.state[at] != TexelState::Covered) {
                CHECK(image.state[at] == TexelState::Dilated);  // every texel of the chart is filled
                continue;
            }
            ++covered;
            DVec2 p;
            REQUIRE(texelSamplePoint(chart, i, j, p));
            CHECK(insideTriangle(p, triangle));
            const DVec2 t = (p - chart.min_plane) * chart.texels_per_metre;
            CHECK(t.x >= i);
            CHECK(t.x <= i + 1);
            CHECK(t.y >= j);
            CHECK(t.y <= j + 1);
            const DVec3 w = chart.worldPoint(p);
            CHECK(image.rgb[3 * at] == doctest::Approx(1.0 + w.x + 2.0 * w.z).epsilon(1e-6));
            CHECK(image.rgb[3 * at + 1] == doctest::Approx(1.0));
            CHECK(image.rgb[3 * at + 2] == doctest::Approx(0.5));
        }
    }
    CHECK(covered == lightmaps.evaluated_texels);
    CHECK(covered >= centre_inside);
    CHECK(covered > 24 * 16 / 2);  // half the rectangle plus the texels the hypotenuse crosses
    CHECK(covered < 24 * 16 * 3 / 4);

    // Each corner's texel agrees with the vertex value within |grad| * texel diagonal.
    const double tolerance = std::sqrt(1.0 + 4.0) * std::sqrt(2.0) / chart.texels_per_metre;
    for (const Vec3& v : scene.meshes[0].positions) {
        const DVec2 t = chart.atlasTexel(DVec2(glm::dot(DVec3(v) - chart.origin_world, chart.u_world),
                                               glm::dot(DVec3(v) - chart.origin_world, chart.v_world)));
        const int x = std::min(static_cast<int>(t.x), chart.x + chart.width - 1);
        const int y = std::min(static_cast<int>(t.y), chart.y + chart.height - 1);
        const size_t at = static_cast<size_t>(y) * image.width + x;
        CHECK(image.state[at] == TexelState::Covered);
        CHECK(std::fabs(image.rgb[3 * at] - (1.0 + v.x + 2.0 * v.z)) <= tolerance);
    }
}

TEST_CASE("dilation fills every padding texel from its own chart only") {
    // Two unit squares far apart, facing +Y and -Y, lit 1 and 5: no bleeding either way.
    const Scene scene = sceneOf({lightmap_test::polygonMesh({{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}),
                                 lightmap_test::polygonMesh({{5, 0, 0}, {6, 0, 0}, {6, 0, 1}, {5, 0, 1}})});
    LightmapOptions options;
    options.texels_per_metre = 6.0;
    options.padding = 3;
    const Lightmaps lightmaps =
        bake(scene, options, [](const SurfacePoint& at) { const DVec3& n = at.normal_world;  return DVec3(kPi * (n.y > 0 ? 1.0 : 5.0)); });
    REQUIRE(lightmaps.layout.charts.size() == 2);
    REQUIRE(lightmaps.images.size() == 1);
    const LightmapImage& image = lightmaps.images[0];
    std::vector<bool> in_padded(image.state.size(), false);
    for (const LightmapChart& chart : lightmaps.layout.charts) {
        const float expected = chart.normal_world.y > 0 ? 1.0f : 5.0f;
        for (int y = chart.y - options.padding; y < chart.y + chart.height + options.padding; ++y)
            for (int x = chart.x - options.padding; x < chart.x + chart.width + options.padding; ++x) {
                const size_t at = static_cast<size_t>(y) * image.width + x;
                in_padded[at] = true;
                const bool inside = x >= chart.x && y >= chart.y && x < chart.x + chart.width && y < chart.y + chart.height;
                CHECK(image.state[at] == (inside ? TexelState::Covered : TexelState::Dilated));
                CHECK(image.rgb[3 * at] == doctest::Approx(expected));
            }
    }
    for (size_t at = 0; at < image.state.size(); ++at)
        if (!in_padded[at]) CHECK(image.state[at] == TexelState::Empty);
}

TEST_CASE("texels do not depend on the thread count") {
    const Scene scene = sceneOf({lightmap_test::polygonMesh({{0, 0, 0}, {0, 0, 2}, {3, 0, 2}, {3, 0, 0}}),
                                 lightmap_test::polygonMesh({{0, 0, 0}, {0, 2, 0}, {0, 2, 2}, {0, 0, 2}})});
    LightmapOptions options;
    options.texels_per_metre = 10.0;
    const Lightmaps one = bake(scene, options, linearField, 1);
    const Lightmaps two = bake(scene, options, linearField, 2);
    REQUIRE(one.images.size() == two.images.size());
    for (size_t a = 0; a < one.images.size(); ++a) CHECK(one.images[a].rgb == two.images[a].rgb);
}
