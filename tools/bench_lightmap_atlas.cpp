// Lightmap charts and atlases of a scene: charts, atlases, occupancy, with charts grown across
// smooth edges (the meshes' crease angles) and without (every crease angle set to 0, the
// former one-chart-per-planar-region layout); with --bake, a draft solve and the lightmap
// bake's time (median of --runs) and its edge/seam fit figures. With --tolerance T (implies
// --bake, default layout only): the bake at texel_tolerance 0 and T, dilated and stitched,
// with evaluations, the time ratio, and the max / RMS relative texel difference of T against
// 0 over covered texels (relative to max(|exhaustive|, 1% of the brightest texel)).
// Usage: bench_lightmap_atlas SCENE [--density D] [--runs N] [--bake] [--tolerance T] [--dilated-only]
//        [--unit-scale S]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "bake/lightmap_bake.h"
#include "bake/lightmap_pack.h"
#include "core/progress.h"
#include "geometry/parts.h"
#include "io/import.h"
#include "radiosity/solution.h"
#include "radiosity/solver.h"
#include "scene/two_sided.h"

using namespace radbake;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE [--density D] [--runs N] [--bake] [--tolerance T] [--dilated-only] [--unit-scale S]\n", argv[0]);
        return 2;
    }
    ImportOptions import_options;
    LightmapOptions options;
    int runs = 3;
    bool bake = false;
    double tolerance = -1.0;
    bool dilated_only = false;
    for (int i = 2; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--density") && i + 1 < argc) options.texels_per_metre = std::atof(argv[++i]);
        else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--unit-scale") && i + 1 < argc) import_options.unit_scale = std::strtof(argv[++i], nullptr);
        else if (!std::strcmp(argv[i], "--bake")) bake = true;
        else if (!std::strcmp(argv[i], "--dilated-only")) dilated_only = true;
        else if (!std::strcmp(argv[i], "--tolerance") && i + 1 < argc) bake = true, tolerance = std::atof(argv[++i]);
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    Diagnostics diagnostics;
    std::optional<Scene> imported = importScene(argv[1], import_options, diagnostics);
    if (!imported) {
        std::fprintf(stderr, "cannot import %s\n", argv[1]);
        return 1;
    }
    addBackTwins(*imported);  // as bake() does: each side of a two-sided mesh has its own charts
    size_t triangles = 0;
    for (const Mesh& mesh : imported->meshes) triangles += mesh.triangles.size();
    std::printf("%s: %zu meshes, %zu triangles, density %g texels/m\n", argv[1], imported->meshes.size(), triangles,
                options.texels_per_metre);
    for (bool smooth : {false, true}) {
        Scene scene = *imported;
        if (!smooth)
            for (Mesh& mesh : scene.meshes) mesh.crease_angle = 0.0f;
        LightmapLayout layout;
        std::vector<double> times;
        for (int r = 0; r < runs; ++r) {
            const auto start = std::chrono::steady_clock::now();
            layout = LightmapLayout{};
            if (!packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics)) return 1;
            times.push_back(seconds(start));
        }
        size_t texels = 0;
        for (const LightmapAtlas& atlas : layout.atlases) texels += static_cast<size_t>(atlas.width) * atlas.height;
        std::printf("  %-22s charts %6zu  atlases %zu (%zu texels)  occupancy %.3f  padded %.3f  charts+pack %.4f s\n",
                    smooth ? "smooth-edge charts:" : "planar charts only:", layout.charts.size(), layout.atlases.size(), texels,
                    layout.occupancy, layout.padded_occupancy, median(times));
        if (!bake || (tolerance >= 0.0 && !smooth)) continue;
        const PartSet parts = buildParts(scene, PartOptions{}, diagnostics);
        SolverOptions solver = SolverOptions::forQuality(Quality::Draft);
        Progress progress(false);
        ParallelRunner runner(Threading{});
        const std::optional<Solution> solution = solveRadiosity(scene, parts, solver, runner, progress, diagnostics);
        if (!solution) return 1;
        const std::vector<double> tolerances = tolerance >= 0.0 ? std::vector<double>{0.0, tolerance}
                                                                : std::vector<double>{options.texel_tolerance};
        for (bool stitch : {false, true}) {
            if (stitch && dilated_only) continue;
            std::vector<double> medians;
            std::vector<Lightmaps> results;
            for (double tol : tolerances) {
                LightmapOptions o = options;
                o.stitch_seams = stitch;
                o.texel_tolerance = tol;
                ReadoutOptions readout = ReadoutOptions::forQuality(Quality::Draft);
                readout.gather = tol > 0.0 ? GatherMode::Links : GatherMode::Exhaustive;
                Lightmaps lightmaps;
                std::vector<double> bake_times;
                for (int r = 0; r < runs; ++r) {
                    const auto start = std::chrono::steady_clock::now();
                    if (!bakeLightmaps(scene, *solution, readout, chartLightmaps(scene, o), runner, lightmaps,
                                       diagnostics))
                        return 1;
                    bake_times.push_back(seconds(start));
                }
                medians.push_back(median(bake_times));
                const StitchStats& s = lightmaps.stitch;
                std::printf("    bake %-9s tol %-6g %.3f s median of %d  covered %zu evaluated %zu (edge-bound %zu) interpolated %zu",
                            stitch ? "stitched" : "dilated", tol, medians.back(), runs, lightmaps.covered_texels,
                            lightmaps.evaluated_texels, lightmaps.required_texels, lightmaps.interpolated_texels);
                if (stitch)
                    std::printf("  edge samples %zu  seam samples %zu  light evaluations %zu  fitted texels %zu  CG steps %d  "
                                "seam gap %.2e -> %.2e  edge gap %.2e",
                                s.edge_samples, s.seam_samples, s.evaluations, s.texels, s.iterations, s.max_seam_before,
                                s.max_seam_after, s.max_edge_after);
                std::printf("\n");
                results.push_back(std::move(lightmaps));
            }
            if (results.size() < 2) continue;
            // Texel differences against the exhaustive bake, over covered texels.
            double brightest = 0.0, worst = 0.0, sum_sq = 0.0;
            size_t count = 0, worst_atlas = 0, worst_texel = 0;
            for (const LightmapImage& image : results[0].images)
                for (float v : image.rgb) brightest = std::max(brightest, static_cast<double>(v));
            for (size_t a = 0; a < results[0].images.size(); ++a) {
                const LightmapImage& ref = results[0].images[a];
                const LightmapImage& got = results[1].images[a];
                for (size_t t = 0; t < ref.state.size(); ++t) {
                    if (ref.state[t] != TexelState::Covered) continue;
                    for (int c = 0; c < 3; ++c) {
                        const double r = ref.rgb[3 * t + c], g = got.rgb[3 * t + c];
                        const double rel = std::fabs(g - r) / std::max(std::fabs(r), 1e-2 * brightest);
                        if (rel > worst) worst = rel, worst_atlas = a, worst_texel = 3 * t + c;
                        sum_sq += rel * rel;
                        ++count;
                    }
                }
            }
            const LightmapImage& worst_image = results[0].images[worst_atlas];
            std::printf("    %-9s tol %g vs 0: time ratio %.2fx  max rel diff %.3e (atlas %zu texel %zu,%zu: %.4g vs %.4g)  "
                        "RMS rel diff %.3e\n",
                        stitch ? "stitched" : "dilated", tolerance, medians[0] / medians[1], worst, worst_atlas,
                        worst_texel / 3 % worst_image.width, worst_texel / 3 / worst_image.width,
                        results[1].images[worst_atlas].rgb[worst_texel], worst_image.rgb[worst_texel],
                        count ? std::sqrt(sum_sq / count) : 0.0);
        }
    }
    return 0;
}
