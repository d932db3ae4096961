// Adaptive texel evaluation against the exhaustive one: tolerance 0 is bit-identical, smooth
// fields are reproduced within the tolerance from far fewer evaluations, a shadow edge is
// resolved texel by texel, and partly covered texels are always evaluated.
#include <doctest/doctest.h>

#include <cmath>
#include <mutex>
#include <set>

#include "bake/lightmap_adaptive.h"
#include "bake/lightmap_bake.h"
#include "lightmap_test_scenes.h"

using namespace radbake;
using lightmap_test::sceneOf;

namespace {

// A 4 m x 4 m floor facing +Y (two triangles), 64 x 64 texels at 16 texels/m.
Scene floorScene() { return sceneOf({lightmap_test::polygonMesh({{0, 0, 0}, {0, 0, 4}, {4, 0, 4}, {4, 0, 0}})}); }

LightmapLayout layoutOf(const Scene& scene, double density) {
    LightmapOptions options;
    options.texels_per_metre = density;
    LightmapLayout layout;
    Diagnostics diagnostics;
    REQUIRE(packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics));
    return layout;
}

Lightmaps bakeWith(const LightmapLayout& layout, const IrradianceFunction& f, double tolerance, int threads = 0) {
    ParallelRunner runner(Threading{.threads = threads});
    return evaluateLightmaps(layout, f, 2, runner, tolerance);
}

// Worst |adaptive - exhaustive| / (tolerance * max(|exhaustive|, 1% of the brightest texel))
// over covered texels and channels: <= 1 means within the tolerance everywhere.
double worstOverTolerance(const Lightmaps& adaptive, const Lightmaps& exhaustive, double tolerance) {
    double brightest = 0.0, worst = 0.0;
    for (const LightmapImage& image : exhaustive.images)
        for (float v : image.rgb) brightest = std::max(brightest, static_cast<double>(v));
    for (size_t a = 0; a < exhaustive.images.size(); ++a)
        for (size_t t = 0; t < exhaustive.images[a].state.size(); ++t) {
            if (exhaustive.images[a].state[t] != TexelState::Covered) continue;
            REQUIRE(adaptive.images[a].state[t] == TexelState::Covered);
            for (int c = 0; c < 3; ++c) {
                const double want = exhaustive.images[a].rgb[3 * t + c], got = adaptive.images[a].rgb[3 * t + c];
                worst = std::max(worst, std::fabs(got - want) / (tolerance * std::max(std::fabs(want), kDarkFloor * brightest)));
            }
        }
    return worst;
}

}  // namespace

TEST_CASE("tolerance 0 gives the exhaustive texels bit for bit") {
    // A triangle (partly covered texels along the hypotenuse) and a wall, a curved field.
    const Scene scene = sceneOf({lightmap_test::polygonMesh({{0, 0, 0}, {0, 0, 2}, {3, 0, 0}}),
                                 lightmap_test::polygonMesh({{0, 0, 0}, {0, 2, 0}, {0, 2, 2}, {0, 0, 2}})});
    const IrradianceFunction field = [](const SurfacePoint& at) { const DVec3& p = at.p_world; const DVec3& n = at.normal_world; 
        return kPi * DVec3(1.0 + std::sin(3.0 * p.x) * p.z, 0.5 + n.x, std::exp(-p.y));
    };
    const LightmapLayout layout = layoutOf(scene, 10.0);
    const Lightmaps lightmaps = bakeWith(layout, field, 0.0);
    CHECK(lightmaps.interpolated_texels == 0);
    CHECK(lightmaps.evaluated_texels == lightmaps.covered_texels);
    // The exhaustive answer written out here: every texel with geometry, at its sample point.
    size_t covered = 0;
    for (const LightmapChart& chart : layout.charts) {
        const LightmapImage& image = lightmaps.images[chart.atlas];
        for (int j = 0; j < chart.height; ++j)
            for (int i = 0; i < chart.width; ++i) {
                DVec2 p;
                size_t f = 0;
                const size_t at = static_cast<size_t>(chart.y + j) * image.width + chart.x + i;
                if (!texelSamplePoint(chart, i, j, p, f)) {
                    CHECK(image.state[at] != TexelState::Covered);
                    continue;
                }
                ++covered;
                const DVec3 value =
                    field({chart.faces[f].worldPoint(p), chart.faces[f].normal_world, chart.mesh, chart.faces[f].triangle}) / kPi;
                REQUIRE(image.state[at] == TexelState::Covered);
                for (int c = 0; c < 3; ++c) CHECK(image.rgb[3 * at + c] == static_cast<float>(value[c]));
            }
    }
    CHECK(covered == lightmaps.covered_texels);
}

TEST_CASE("smooth fields are interpolated within the tolerance from far fewer evaluations") {
    const LightmapLayout layout = layoutOf(floorScene(), 16.0);
    REQUIRE(layout.charts.size() == 1);
    REQUIRE(layout.charts[0].width == 64);
    REQUIRE(layout.charts[0].height == 64);
    const double tolerance = 0.01;
    SUBCASE("linear ramp") {
        // H / pi = 1 + 0.01 x + 0.005 z: corners of an 8-texel block differ by under 1%.
        const IrradianceFunction ramp = [](const SurfacePoint& at) { const DVec3& p = at.p_world; 
            return kPi * DVec3(1.0 + 0.01 * p.x + 0.005 * p.z, 2.0 - 0.01 * p.z, 0.5);
        };
        const Lightmaps exhaustive = bakeWith(layout, ramp, 0.0), adaptive = bakeWith(layout, ramp, tolerance);
        CHECK(adaptive.covered_texels == 64 * 64);
        CHECK(adaptive.evaluated_texels + adaptive.interpolated_texels == 64 * 64);
        // Bilinear interpolation at the texels' own sample points reproduces a linear field
        // to rounding (float texels: 1e-6 relative), far inside the tolerance.
        CHECK(worstOverTolerance(adaptive, exhaustive, tolerance) <= 1e-4);
        // Evaluated: the outer ring (252), on which every texel next to a texel without full
        // cover is evaluated; the 8-texel lattice (9 x 9 with the last row and column); one
        // centre per interior block (36); the blocks touching the ring refined down to every
        // texel (rows and columns 0..8 and 56..63). Bounded, not pinned: under 1 in 3.
        CHECK(adaptive.evaluated_texels < 64 * 64 / 3);
        CHECK(adaptive.interpolated_texels > 64 * 64 / 2);
    }
    SUBCASE("quadratic bowl") {
        const IrradianceFunction bowl = [](const SurfacePoint& at) { const DVec3& p = at.p_world; 
            const double r2 = (p.x - 2.0) * (p.x - 2.0) + (p.z - 1.5) * (p.z - 1.5);
            return kPi * DVec3(1.0 + 0.02 * r2, 1.0, 1.0 + 0.01 * p.x * p.z);
        };
        const Lightmaps exhaustive = bakeWith(layout, bowl, 0.0), adaptive = bakeWith(layout, bowl, tolerance);
        CHECK(worstOverTolerance(adaptive, exhaustive, tolerance) <= 1.0);
        CHECK(adaptive.evaluated_texels + adaptive.interpolated_texels == 64 * 64);
        CHECK(adaptive.evaluated_texels < 64 * 64 / 2);
    }
}

TEST_CASE("a sharp shadow edge is resolved texel by texel") {
    const LightmapLayout layout = layoutOf(floorScene(), 16.0);
    const double tolerance = 0.01;
    // Lit 1 on one side of a slanted line, 0.1 in its shadow: off the texel grid.
    const IrradianceFunction shadow = [](const SurfacePoint& at) { const DVec3& p = at.p_world; 
        return kPi * DVec3(p.x + 0.37 * p.z < 2.13 ? 1.0 : 0.1);
    };
    const Lightmaps exhaustive = bakeWith(layout, shadow, 0.0), adaptive = bakeWith(layout, shadow, tolerance);
    const LightmapChart& chart = layout.charts[0];
    const LightmapImage& want = exhaustive.images[0];
    const LightmapImage& got = adaptive.images[0];
    size_t lit = 0, dark = 0;
    for (int j = 0; j < chart.height; ++j)
        for (int i = 0; i < chart.width; ++i) {
            const size_t at = static_cast<size_t>(chart.y + j) * want.width + chart.x + i;
            REQUIRE(got.state[at] == TexelState::Covered);
            (want.rgb[3 * at] > 0.5f ? lit : dark) += 1;
            // Exact on both sides: the value is one of the two levels, never a blend.
            CHECK(std::fabs(got.rgb[3 * at] - want.rgb[3 * at]) <= tolerance * want.rgb[3 * at]);
        }
    CHECK(lit > 1000);
    CHECK(dark > 1000);
    CHECK(adaptive.interpolated_texels > 64 * 64 / 3);  // away from the edge, blocks are still interpolated
}

TEST_CASE("partly covered texels are always evaluated, whatever the field") {
    // A triangle floor: its hypotenuse crosses a texel row diagonally.
    const Scene scene = sceneOf({lightmap_test::polygonMesh({{0, 0, 0}, {0, 0, 3}, {4, 0, 0}})});
    const LightmapLayout layout = layoutOf(scene, 16.0);
    REQUIRE(layout.charts.size() == 1);
    std::set<std::array<double, 3>> evaluated;
    std::mutex mutex;
    const IrradianceFunction constant = [&](const SurfacePoint& at) { const DVec3& p = at.p_world; 
        const std::lock_guard<std::mutex> lock(mutex);
        evaluated.insert({p.x, p.y, p.z});
        return DVec3(kPi);
    };
    const Lightmaps lightmaps = bakeWith(layout, constant, 0.05, 2);
    CHECK(lightmaps.interpolated_texels > 0);  // a constant field: the interior is interpolated
    CHECK(evaluated.size() == lightmaps.evaluated_texels);
    const LightmapChart& chart = layout.charts[0];
    size_t partial = 0;
    for (int j = 0; j < chart.height; ++j)
        for (int i = 0; i < chart.width; ++i) {
            DVec2 p;
            size_t f = 0;
            const double cover = texelCoverage(chart, i, j, p, f);
            if (cover <= 0.0 || cover >= 1.0 - 1e-6) continue;
            ++partial;
            const DVec3 w = chart.faces[f].worldPoint(p);
            CHECK(evaluated.count({w.x, w.y, w.z}) == 1);
        }
    CHECK(partial >= 64);  // at least one per texel column the hypotenuse crosses
}

TEST_CASE("adaptive texels do not depend on the thread count") {
    const LightmapLayout layout = layoutOf(floorScene(), 16.0);
    const IrradianceFunction field = [](const SurfacePoint& at) { const DVec3& p = at.p_world; 
        return kPi * DVec3(1.0 + 0.2 * std::sin(p.x) * std::cos(p.z), p.x < 1.7 ? 1.0 : 0.3, 0.5);
    };
    const Lightmaps one = bakeWith(layout, field, 0.02, 1), two = bakeWith(layout, field, 0.02, 2);
    CHECK(one.evaluated_texels == two.evaluated_texels);
    CHECK(one.interpolated_texels > 0);
    CHECK(one.images[0].rgb == two.images[0].rgb);
}

TEST_CASE("a smooth edge inside a chart is resolved like a shadow edge") {
    // Two panels hinged along x = 2.03 (off the texel grid) at 20 degrees, one mesh with a 45-degree crease
    // angle: one chart across the hinge, whose faces' normals differ.
    Mesh mesh;
    const float rise = 2.0f * std::tan(20.0f * static_cast<float>(kPi) / 180.0f);
    mesh.positions = {{0, 0, 0}, {0, 0, 4}, {2.03f, 0, 4}, {2.03f, 0, 0}, {4.03f, rise, 4}, {4.03f, rise, 0}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 2, 4}, {3, 4, 5}};
    mesh.triangle_polygon = {0, 0, 1, 1};
    mesh.polygon_count = 2;
    mesh.crease_angle = 45.0f * static_cast<float>(kPi) / 180.0f;
    const LightmapLayout layout = layoutOf(sceneOf({mesh}), 16.0);
    REQUIRE(layout.charts.size() == 1);
    // Light that depends on the facing only: a step across the hinge, constant on each panel.
    const IrradianceFunction facing = [](const SurfacePoint& at) { const DVec3& n = at.normal_world;  return kPi * DVec3(1.0 + 2.0 * n.x * n.x); };
    const double tolerance = 0.01;
    const Lightmaps exhaustive = bakeWith(layout, facing, 0.0), adaptive = bakeWith(layout, facing, tolerance);
    // Each texel holds its own panel's value (the one under its sample point), never a blend.
    CHECK(worstOverTolerance(adaptive, exhaustive, tolerance) <= 1e-4);
    CHECK(adaptive.interpolated_texels > adaptive.covered_texels / 2);
}
