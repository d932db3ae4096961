// Builds convex parts for a scene file and prints counts, time (median of repeated runs) and
// OBB tightness. Usage: bench_parts SCENE [--unit-scale S] [--runs N] [--no-merge] [--worst K]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "geometry/box.h"
#include "geometry/parts.h"
#include "io/import.h"
#include "scene/two_sided.h"

using namespace radbake;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE [--unit-scale S] [--runs N] [--no-merge] [--worst K]\n", argv[0]);
        return 2;
    }
    ImportOptions import_options;
    PartOptions options;
    int runs = 5, worst = 0;
    for (int i = 2; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--unit-scale") && i + 1 < argc) {
            import_options.unit_scale = std::strtof(argv[++i], nullptr);
        } else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) {
            runs = std::max(1, std::atoi(argv[++i]));
        } else if (!std::strcmp(argv[i], "--worst") && i + 1 < argc) {
            worst = std::atoi(argv[++i]);
        } else if (!std::strcmp(argv[i], "--no-merge")) {
            options.merge_coplanar = false;
        } else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    Diagnostics import_diagnostics;
    std::optional<Scene> scene = importScene(argv[1], import_options, import_diagnostics);
    if (!scene) {
        for (const Diagnostic& d : import_diagnostics.all())
            if (d.severity == Severity::Error) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
        return 1;
    }
    addBackTwins(*scene);  // as bake() does: a two-sided mesh is never a closed solid
    const SceneSummary summary = summarize(*scene);
    std::printf("scene        %s\nmeshes       %zu\npolygons     %zu\ntriangles    %zu\n", argv[1],
                scene->meshes.size(), summary.polygons, summary.triangles);

    // Wall time and this process's CPU time: the machine is shared, and CPU time is the
    // steadier figure when other jobs compete for the cores.
    auto cpuMs = [] {
        timespec t;
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
        return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
    };
    std::vector<double> ms, cpu;
    PartSet set;
    int warnings = 0, errors = 0;
    for (int r = 0; r < runs; ++r) {
        Diagnostics diagnostics;
        const auto start = std::chrono::steady_clock::now();
        const double cpu_start = cpuMs();
        set = buildParts(*scene, options, diagnostics);
        cpu.push_back(cpuMs() - cpu_start);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        warnings = diagnostics.warningCount();
        errors = diagnostics.errorCount();
    }
    std::sort(ms.begin(), ms.end());
    std::sort(cpu.begin(), cpu.end());
    const PartStats& s = set.stats;
    std::printf("parts        %zu (closed %zu, flat %zu; closed meshes %zu)\n", s.parts, s.closed_parts, s.flat_parts,
                s.closed_meshes);
    std::printf("degenerate   %zu polygons, %zu solids; %d warnings, %d errors\n", s.degenerate_polygons,
                s.degenerate_solids, warnings, errors);
    std::printf("time         median %.2f ms wall (min %.2f, max %.2f), median %.2f ms CPU, over %d runs\n",
                ms[ms.size() / 2], ms.front(), ms.back(), cpu[cpu.size() / 2], runs);
    std::printf("OBB/hull     volume ratio mean %.4f max %.4f (closed)\n", s.mean_obb_volume_ratio,
                s.max_obb_volume_ratio);
    std::printf("OBB/polygon  area ratio mean %.4f max %.4f (flat)\n", s.mean_obb_area_ratio, s.max_obb_area_ratio);
    // Compare with PCA boxes on the same parts, to show what the refinement buys.
    double pca_volume = 0.0, pca_area = 0.0, obb_volume = 0.0, obb_area = 0.0;
    for (const ConvexPart& part : set.parts) {
        const Obb pca = pcaObb(part.vertices);
        if (part.closed) {
            pca_volume += obbVolume(pca) / part.volume;
            obb_volume += obbTightness(part);
        } else {
            pca_area += obbLargestFaceArea(pca) / part.area;
            obb_area += obbTightness(part);
        }
    }
    if (s.closed_parts)
        std::printf("PCA boxes    volume ratio mean %.4f (tight %.4f)\n", pca_volume / double(s.closed_parts),
                    obb_volume / double(s.closed_parts));
    if (s.flat_parts)
        std::printf("PCA boxes    area ratio mean %.4f (tight %.4f)\n", pca_area / double(s.flat_parts),
                    obb_area / double(s.flat_parts));
    if (worst > 0) {
        std::vector<std::pair<double, size_t>> order;
        for (size_t i = 0; i < set.parts.size(); ++i) order.push_back({obbTightness(set.parts[i]), i});
        std::sort(order.rbegin(), order.rend());
        for (int k = 0; k < worst && k < int(order.size()); ++k) {
            const ConvexPart& part = set.parts[order[k].second];
            std::printf("worst %2d     ratio %.4f %s mesh %u '%s' vertices %zu polygons %zu\n", k, order[k].first,
                        part.closed ? "closed" : "flat", part.mesh, scene->meshes[part.mesh].name.c_str(),
                        part.vertices.size(), part.polygons.size());
        }
    }
    return 0;
}
