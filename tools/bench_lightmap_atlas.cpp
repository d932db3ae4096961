// Lightmap charts and atlases of a scene: charts, atlases, occupancy, with charts grown across
// smooth edges (the meshes' crease angles) and without (every crease angle set to 0, the
// former one-chart-per-planar-region layout); with --bake, a draft solve and the lightmap
// bake's time (median of --runs) and its edge/seam fit figures.
// Usage: bench_lightmap_atlas SCENE [--density D] [--runs N] [--bake] [--unit-scale S]
#include <algorithm>
#include <chrono>
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
        std::fprintf(stderr, "usage: %s SCENE [--density D] [--runs N] [--bake] [--unit-scale S]\n", argv[0]);
        return 2;
    }
    ImportOptions import_options;
    LightmapOptions options;
    int runs = 3;
    bool bake = false;
    for (int i = 2; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--density") && i + 1 < argc) options.texel_density = std::atof(argv[++i]);
        else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--unit-scale") && i + 1 < argc) import_options.unit_scale = std::strtof(argv[++i], nullptr);
        else if (!std::strcmp(argv[i], "--bake")) bake = true;
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
    size_t triangles = 0;
    for (const Mesh& mesh : imported->meshes) triangles += mesh.triangles.size();
    std::printf("%s: %zu meshes, %zu triangles, density %g texels/m\n", argv[1], imported->meshes.size(), triangles,
                options.texel_density);
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
        if (!bake) continue;
        const PartSet parts = buildParts(scene, PartOptions{}, diagnostics);
        SolverOptions solver = SolverOptions::forQuality(Quality::Draft);
        Progress progress(false);
        const std::optional<Solution> solution = solveRadiosity(scene, parts, solver, progress, diagnostics);
        if (!solution) return 1;
        for (bool stitch : {false, true}) {
            LightmapOptions o = options;
            o.stitch_seams = stitch;
            Lightmaps lightmaps;
            std::vector<double> bake_times;
            for (int r = 0; r < runs; ++r) {
                const auto start = std::chrono::steady_clock::now();
                if (!bakeLightmaps(scene, *solution, o, lightmaps, diagnostics)) return 1;
                bake_times.push_back(seconds(start));
            }
            const StitchStats& s = lightmaps.stitch;
            std::printf("    bake %-9s %.3f s median of %d  texels %zu", stitch ? "stitched" : "dilated", median(bake_times), runs,
                        lightmaps.evaluated_texels);
            if (stitch)
                std::printf("  edge samples %zu  seam samples %zu  fitted texels %zu  CG steps %d  seam gap %.2e -> %.2e  edge gap %.2e",
                            s.edge_samples, s.seam_samples, s.texels, s.iterations, s.max_seam_before, s.max_seam_after,
                            s.max_edge_after);
            std::printf("\n");
        }
    }
    return 0;
}
