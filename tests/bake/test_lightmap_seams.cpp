// Seams and chart edges: a bilinear lookup on the cut between two pieces of a split floor
// gives the same light from both pieces (and did not before stitching), a lookup at a chart
// edge gives the light there, a chart corner's lookup agrees with the vertex bake on a real
// solve, and the fit does not depend on the thread count.
#include <doctest/doctest.h>

#include <cmath>

#include "bake/lightmap_mesh.h"
#include "bake/lightmap_seams.h"
#include "readout/vertex_bake.h"
#include "../radiosity/test_scenes.h"
#include "lightmap_test_scenes.h"

using namespace radbake;
using lightmap_test::sceneOf;

namespace {

Mesh floorMesh(float size_x, float size_z) {
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {0, 0, size_z}, {size_x, 0, size_z}, {size_x, 0, 0}};  // faces +Y
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    mesh.triangle_polygon = {0, 0};
    mesh.polygon_count = 1;
    return mesh;
}

// H / pi = 1 + 4 x + 3 z + 2 x z: steep, not linear, but linear along every axis-aligned
// line, so a bilinear lookup along the (axis-aligned) chart edges can reproduce it exactly.
DVec3 fieldAt(const DVec3& p) { return kPi * DVec3(1.0 + 4.0 * p.x + 3.0 * p.z + 2.0 * p.x * p.z, 2.0, 0.5 + p.z); }
DVec3 field(const SurfacePoint& at) { return fieldAt(at.p_world); }

Lightmaps bakeField(const Scene& scene, const LightmapOptions& options, int threads) {
    LightmapLayout layout;
    Diagnostics diagnostics;
    REQUIRE(packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics));
    ParallelRunner runner(Threading{.threads = threads});
    Lightmaps lightmaps = evaluateLightmaps(std::move(layout), field, options.padding, runner);
    if (options.stitch_seams) stitchLightmaps(scene, lightmaps, field, options.padding, runner);
    return lightmaps;
}

double relativeGap(const DVec3& a, const DVec3& b) {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(a[c] - b[c]) / std::max(std::fabs(a[c]), std::fabs(b[c])));
    return worst;
}

}  // namespace

TEST_CASE("both pieces of a floor cut by the cap give the same light along the cut") {
    // 4 m x 2 m at 8 texels/m: 32 x 16 texels, cut at 12 texels into 3 x 2 pieces along
    // x = 1.5, x = 3 and (the plane's v axis is -z, counted from z = 2) z = 0.5.
    const Scene scene = sceneOf({floorMesh(4.0f, 2.0f)});
    LightmapOptions options;
    options.texels_per_metre = 8.0;
    options.max_chart_texels = 12;
    options.atlas_size = 128;
    options.stitch_seams = false;
    const Lightmaps before = bakeField(scene, options, 1);
    REQUIRE(before.layout.charts.size() == 6);
    const ChartEdges edges = findChartEdges(scene, before.layout);
    REQUIRE(edges.seams.size() > 0);
    double length = 0.0;  // seam samples lie on the cuts only, from two different charts
    for (const SeamSample& s : edges.seams) {
        CHECK(s.a.chart != s.b.chart);
        const DVec3& p = s.a.p_world;
        const bool on_cut = std::fabs(p.x - 1.5) < 1e-6 || std::fabs(p.x - 3.0) < 1e-6 || std::fabs(p.z - 0.5) < 1e-6;
        CHECK(on_cut);
        CHECK(std::fabs(p.y) < 1e-9);
        length = std::max(length, p.x);
    }
    CHECK(length == doctest::Approx(4.0));  // the z = 0.5 cut is sampled to the far end
    // Every chart-edge sample not on a cut lies on the floor's outline.
    for (const EdgeSample& e : edges.edges) {
        const DVec3& p = e.p_world;
        const bool outline = std::fabs(p.x) < 1e-6 || std::fabs(p.x - 4.0) < 1e-6 || std::fabs(p.z) < 1e-6 || std::fabs(p.z - 2.0) < 1e-6;
        const bool on_cut = std::fabs(p.x - 1.5) < 1e-6 || std::fabs(p.x - 3.0) < 1e-6 || std::fabs(p.z - 0.5) < 1e-6;
        CHECK((outline || on_cut));
    }

    // Dilation alone: the two sides differ by about one texel of gradient (>= 4 / 8 on 1..29).
    double worst_before = 0.0;
    for (const SeamSample& s : edges.seams)
        worst_before = std::max(worst_before, relativeGap(bilinearLookup(before.images[0], s.a.texel),
                                                          bilinearLookup(before.images[0], s.b.texel)));
    CHECK(worst_before > 0.02);
    CHECK(before.stitch.seam_samples == 0);

    options.stitch_seams = true;
    const Lightmaps after = bakeField(scene, options, 1);
    REQUIRE(after.layout.charts.size() == 6);
    CHECK(after.stitch.seam_samples == edges.seams.size());
    CHECK(after.stitch.max_seam_before == doctest::Approx(worst_before));
    for (const SeamSample& s : edges.seams) {
        const DVec3 a = bilinearLookup(after.images[0], s.a.texel), b = bilinearLookup(after.images[0], s.b.texel);
        CHECK(relativeGap(a, b) < 1e-3);
        // ... and both give the light at that point, not just any common value.
        CHECK(relativeGap(a, fieldAt(s.a.p_world) / kPi) < 1e-3);
    }
    // Lookups along the outline give the light there too.
    for (const EdgeSample& e : edges.edges)
        CHECK(relativeGap(bilinearLookup(after.images[0], e.texel), fieldAt(e.p_world) / kPi) < 1e-3);
    CHECK(after.stitch.max_edge_after < 1e-3);

    // Covered texels away from every edge keep their evaluated value exactly.
    size_t interior = 0;
    for (const LightmapChart& chart : after.layout.charts)
        for (int j = 1; j + 1 < chart.height; ++j)
            for (int i = 1; i + 1 < chart.width; ++i) {
                const size_t at = 3 * (static_cast<size_t>(chart.y + j) * after.images[0].width + chart.x + i);
                CHECK(after.images[0].rgb[at] == before.images[0].rgb[at]);
                ++interior;
            }
    CHECK(interior == 10 * 10 * 2 + 10 * 2 * 2 + 6 * 10 + 6 * 2);
    // Every padding texel is still filled.
    for (const LightmapChart& chart : after.layout.charts)
        for (int y = chart.y - options.padding; y < chart.y + chart.height + options.padding; ++y)
            for (int x = chart.x - options.padding; x < chart.x + chart.width + options.padding; ++x)
                CHECK(after.images[0].state[static_cast<size_t>(y) * after.images[0].width + x] != TexelState::Empty);
}

TEST_CASE("stitching does not depend on the thread count") {
    const Scene scene = sceneOf({floorMesh(4.0f, 2.0f)});
    LightmapOptions options;
    options.texels_per_metre = 8.0;
    options.max_chart_texels = 12;
    options.atlas_size = 128;
    const Lightmaps one = bakeField(scene, options, 1);
    const Lightmaps two = bakeField(scene, options, 2);
    REQUIRE(one.images.size() == 1);
    CHECK(one.images[0].rgb == two.images[0].rgb);
    CHECK(one.stitch.iterations == two.stitch.iterations);
}

TEST_CASE("edge light is evaluated once per point and interpolated where it is smooth") {
    // The cut floor: both sides of every cut see one point with one normal.
    const Scene scene = sceneOf({floorMesh(4.0f, 2.0f)});
    LightmapOptions options;
    options.texels_per_metre = 8.0;
    options.max_chart_texels = 12;
    options.atlas_size = 128;
    options.stitch_seams = false;
    const auto stitched = [&](double tolerance) {
        Lightmaps lightmaps = bakeField(scene, options, 2);
        stitchLightmaps(scene, lightmaps, field, options.padding, test::testRunner(), tolerance);
        return lightmaps;
    };
    const Lightmaps exact = stitched(0.0), smooth = stitched(0.2);
    REQUIRE(exact.stitch.seam_samples > 0);
    // Tolerance 0: every seam point once (its two sides share point and normal), and the
    // chart corners where two boundary edges meet once.
    CHECK(exact.stitch.evaluations <= exact.stitch.edge_samples + exact.stitch.seam_samples);
    CHECK(exact.stitch.evaluations > exact.stitch.seam_samples);
    // The field is linear along every axis-aligned edge: the odd samples of an edge take the
    // mean of their neighbours, exactly, so the fit gives the same texels.
    CHECK(smooth.stitch.evaluations < exact.stitch.evaluations * 3 / 4);
    CHECK(smooth.stitch.edge_samples == exact.stitch.edge_samples);
    REQUIRE(smooth.images.size() == 1);
    double worst = 0.0;
    for (size_t k = 0; k < exact.images[0].rgb.size(); ++k)
        worst = std::max(worst, std::fabs(smooth.images[0].rgb[k] - exact.images[0].rgb[k]) /
                                    std::max(1.0, std::fabs(static_cast<double>(exact.images[0].rgb[k]))));
    CHECK(worst < 1e-5);
    // A shadow edge across the chart edges: the light steps, so the samples around the step
    // are evaluated and the edge fit still reaches the light at every sample away from it.
    const auto withField = [&](const IrradianceFunction& f, StitchStats& stats) {
        LightmapLayout layout;
        Diagnostics diagnostics;
        REQUIRE(packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics));
        Lightmaps lightmaps = evaluateLightmaps(std::move(layout), f, options.padding, test::testRunner());
        stats = stitchLightmaps(scene, lightmaps, f, options.padding, test::testRunner(), 0.01);
        return lightmaps;
    };
    StitchStats flat_stats, step_stats;
    withField([](const SurfacePoint&) {  return DVec3(2.0 * kPi); }, flat_stats);
    const Lightmaps stepped = withField([](const SurfacePoint& at) { const DVec3& p = at.p_world;  return kPi * DVec3(p.x < 1.3 ? 2.0 : 0.5); },
                                        step_stats);
    CHECK(step_stats.evaluations > flat_stats.evaluations);  // the samples around the step are evaluated
    CHECK(flat_stats.evaluations < exact.stitch.evaluations * 3 / 4);
    const ChartEdges found = findChartEdges(scene, stepped.layout);
    size_t checked = 0;
    for (const EdgeSample& e : found.edges) {
        if (e.span == 0 || std::fabs(e.p_world.x - 1.3) < 0.3) continue;  // a lookup near the step reads both sides
        CHECK(bilinearLookup(stepped.images[0], e.texel).x == doctest::Approx(e.p_world.x < 1.3 ? 2.0 : 0.5).epsilon(1e-2));  // the fit trades ~0.3% at seam ends
        ++checked;
    }
    CHECK(checked > 20);
}

TEST_CASE("lit box room: the lightmap at each chart corner agrees with the vertex bake") {
    using namespace radbake::test;
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.6f, 0.5f, 0.4f), Vec3(0.0f));
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(5.0f));
    addInwardBox(scene, grey, Vec3(0.0f), Vec3(2.0f, 2.0f, 1.5f));
    // An off-centre lamp under the ceiling, facing down: steep gradients on every wall.
    addQuad(scene, lamp, {0.3f, 0.3f, 1.45f}, {0.3f, 0.8f, 1.45f}, {0.8f, 0.8f, 1.45f}, {0.8f, 0.3f, 1.45f});
    Diagnostics diagnostics;
    SolverOptions solver = SolverOptions::forQuality(Quality::Draft);
    const auto solution = solve(scene, solver, diagnostics);
    REQUIRE(solution);
    const VertexBake vertex_bake =
        bakeVertices(scene, *solution, ReadoutOptions::forQuality(solution->options.quality), test::testRunner());

    LightmapOptions options;
    // 64 x 64 texels on the floor: a texel (3 cm) finer than the walls' 5 cm strip above the
    // lamp's plane, which no direct light reaches (cut off as a root of its own, contact_cuts.h);
    // at 8 texels/m the strip was half a texel and the corners' lookup read 28 % off it.
    options.texels_per_metre = 32.0;
    options.atlas_size = 512;
    const auto cornerGaps = [&](const Lightmaps& lightmaps, size_t& corners) {
        double worst = 0.0;
        corners = 0;
        const std::vector<LightmapMesh> meshes = lightmapMeshes(scene, lightmaps.layout);
        for (size_t m = 0; m < meshes.size(); ++m)
            for (size_t v = 0; v < meshes[m].positions.size(); ++v) {
                const Vec3& w = meshes[m].barycentric[v];
                if (std::max({w.x, w.y, w.z}) < 1.0f - 1e-6f) continue;  // only chart corners at source vertices
                ++corners;
                const LightmapImage& image = lightmaps.images[meshes[m].atlas[v]];
                const DVec2 texel = DVec2(meshes[m].uv[v]) * DVec2(image.width, image.height);
                const DVec3 lookup = bilinearLookup(image, texel);
                const DVec3 expected(interpolateSource(meshes[m], v, vertex_bake.values[m]));
                REQUIRE(expected.x > 0.0);
                worst = std::max(worst, relativeGap(lookup, expected));
            }
        return worst;
    };
    // The lookup is fitted to the same reconstruction the vertex bake uses (probeIrradiance at
    // that point and face normal; one normal per vertex here, each wall its own mesh), so the
    // quality's error does not enter: what remains is the fit's residual (~1e-4, see
    // lightmap_seams.cpp) and float rounding. Tolerance 2e-3 relative.
    options.stitch_seams = false;
    Lightmaps dilated;
    REQUIRE(bakeLightmaps(scene, *solution, ReadoutOptions::forQuality(solution->options.quality),
                          chartLightmaps(scene, options), test::testRunner(), dilated, diagnostics));
    options.stitch_seams = true;
    Lightmaps stitched;
    REQUIRE(bakeLightmaps(scene, *solution, ReadoutOptions::forQuality(solution->options.quality),
                          chartLightmaps(scene, options), test::testRunner(), stitched, diagnostics));
    size_t corners_dilated = 0, corners_stitched = 0;
    const double gap_dilated = cornerGaps(dilated, corners_dilated);
    const double gap_stitched = cornerGaps(stitched, corners_stitched);
    CHECK(corners_stitched == 7 * 4);  // 7 quads, 4 corners each, one chart per quad
    CHECK(corners_dilated == corners_stitched);
    CHECK(gap_dilated > 0.02);  // dilation alone: half a texel of the corner's gradient
    CHECK(gap_stitched < 2e-3);
    CHECK(stitched.stitch.edge_samples > 0);
    CHECK(stitched.stitch.seam_samples == 0);  // no two charts of one surface meet here
    MESSAGE("corner lookup vs vertex bake: dilated ", gap_dilated, ", stitched ", gap_stitched);
}

TEST_CASE("charts of a smooth cylinder meeting at an edge give the same light there") {
    Mesh side;
    side.crease_angle = 0.5f;  // facets 11.25 degrees apart: one smooth surface
    const int facets = 32;
    for (int i = 0; i < facets; ++i) {
        const double theta = 2.0 * kPi * i / facets;
        side.positions.push_back(Vec3(std::cos(theta), 0.0, std::sin(theta)));
        side.positions.push_back(Vec3(std::cos(theta), 2.0, std::sin(theta)));
    }
    for (uint32_t i = 0; i < static_cast<uint32_t>(facets); ++i) {
        const uint32_t b0 = 2 * i, t0 = b0 + 1, b1 = 2 * ((i + 1) % facets), t1 = b1 + 1;
        side.triangles.push_back({b0, t0, t1});
        side.triangles.push_back({b0, t1, b1});
        side.triangle_polygon.push_back(i);
        side.triangle_polygon.push_back(i);
    }
    side.polygon_count = facets;
    const Scene scene = sceneOf({side});
    // Light that depends on the facing (the two faces at a seam see different light) and on height.
    const IrradianceFunction facing = [](const SurfacePoint& at) { const DVec3& p = at.p_world; const DVec3& n = at.normal_world;  return kPi * DVec3(2.0 + n.x + p.y, 2.0 + n.z, 1.0); };
    LightmapOptions options;
    options.texels_per_metre = 10.0;
    options.atlas_size = 256;
    LightmapLayout layout;
    Diagnostics diagnostics;
    REQUIRE(packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics));
    const size_t charts = layout.charts.size();
    CHECK(charts < 10);
    ParallelRunner one_thread(Threading{.threads = 1});
    Lightmaps lightmaps = evaluateLightmaps(std::move(layout), facing, options.padding, one_thread);
    const ChartEdges edges = findChartEdges(scene, lightmaps.layout);
    // Every chart meets two others, along vertical edges the whole height.
    double seam_height = 0.0;
    for (const SeamSample& s : edges.seams) {
        CHECK(s.a.chart != s.b.chart);
        CHECK(glm::length(DVec2(s.a.p_world.x, s.a.p_world.z)) == doctest::Approx(1.0).epsilon(1e-6));
        seam_height = std::max(seam_height, s.a.p_world.y);
    }
    CHECK(seam_height == doctest::Approx(2.0));
    CHECK(edges.seams.size() >= charts * (2 * 20 + 1));  // two samples per texel of 20, ends included
    const StitchStats stats = stitchLightmaps(scene, lightmaps, facing, options.padding, one_thread);
    CHECK(stats.max_seam_before > 0.02);
    for (const SeamSample& s : edges.seams) {
        const DVec3 a = bilinearLookup(lightmaps.images[0], s.a.texel), b = bilinearLookup(lightmaps.images[0], s.b.texel);
        CHECK(relativeGap(a, b) < 1e-3);
    }
    CHECK(stats.max_seam_after < 1e-3);
}
