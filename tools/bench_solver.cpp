// Solver benchmark: imports a scene, builds parts, solves it for each visibility mode and
// thread count given, and prints the median wall time of N runs, the stats and peak RSS.
//   bench_solver SCENE [--modes rays,aabb,obb,exact] [--threads 1,2] [--runs 3]
//                [--quality draft|medium|high|reference] [--unit-scale S] [--pin 0|1]
//                [--clustering 0|1] [--read-root DIR]
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/parts.h"
#include "io/import.h"
#include "radiosity/solution.h"
#include "radiosity/solver.h"
#include "scene/two_sided.h"

using namespace radbake;

namespace {

std::vector<std::string> split(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) out.push_back(item);
    return out;
}

double peakRssMb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_solver SCENE [--modes rays,aabb,obb,exact] [--threads 1,2] [--runs 3] "
                             "[--quality medium] [--unit-scale S] [--pin 0|1] [--clustering 0|1] [--read-root DIR]\n");
        return 2;
    }
    std::string path = argv[1], modes = "rays,aabb,obb,exact", threads = "1,2", quality = "medium";
    int runs = 3;
    bool pin = true, clustering = true;
    ImportOptions import_options;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string key = argv[i], value = argv[i + 1];
        if (key == "--modes") modes = value;
        else if (key == "--threads") threads = value;
        else if (key == "--runs") runs = std::max(1, std::atoi(value.c_str()));
        else if (key == "--quality") quality = value;
        else if (key == "--pin") pin = value != "0";
        else if (key == "--clustering") clustering = value != "0";
        else if (key == "--unit-scale") import_options.unit_scale = std::strtof(value.c_str(), nullptr);
        else if (key == "--read-root") import_options.read_roots.push_back(value);
        else {
            std::fprintf(stderr, "unknown option %s\n", key.c_str());
            return 2;
        }
    }
    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic& d) {
        if (d.severity != Severity::Note) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
    };
    auto scene = importScene(path, import_options, diagnostics);
    if (!scene) return 1;
    addBackTwins(*scene);  // as bake() does: both sides of two-sided meshes take part
    const PartSet parts = buildParts(*scene, PartOptions{}, diagnostics);
    const Quality q = qualityNamed(quality);
    std::printf("%-6s %3s %9s %8s %8s %9s %8s %9s %6s %5s %8s\n", "mode", "thr", "median_s", "elements", "leaves",
                "links", "shafts", "occluded", "rays", "iters", "rss_mb");
    for (const std::string& mode_name : split(modes)) {
        const LinkVisibility mode = mode_name == "rays" ? LinkVisibility::Rays
                                    : mode_name == "aabb" ? LinkVisibility::Aabb
                                    : mode_name == "obb" ? LinkVisibility::Obb
                                                         : LinkVisibility::Exact;
        for (const std::string& thread_text : split(threads)) {
            SolverOptions options = SolverOptions::forQuality(q);
            options.visibility = mode;
            const Threading threading{.threads = std::atoi(thread_text.c_str()), .pin = pin};
            options.clustering = clustering;
            std::vector<double> seconds;
            SolveStats stats;
            for (int r = 0; r < runs; ++r) {
                Progress progress(false);
                ParallelRunner runner(threading);
                const auto start = std::chrono::steady_clock::now();
                const auto solution = solveRadiosity(*scene, parts, options, runner, progress, diagnostics);
                seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
                if (!solution) return 1;
                stats = solution->stats;
            }
            std::sort(seconds.begin(), seconds.end());
            std::printf("%-6s %3d %9.3f %8zu %8zu %9zu %8zu %9zu %6zu %5d %8.1f  (runs:", toString(mode),
                        threading.threads, seconds[seconds.size() / 2], stats.elements, stats.leaves, stats.links,
                        stats.shafts, stats.occluded_links, stats.rays, stats.iterations, peakRssMb());
            for (double s : seconds) std::printf(" %.3f", s);
            std::printf("; cluster links %zu, element links %zu, clusters %zu, cluster rays %zu)\n",
                        stats.cluster_links, stats.element_links, stats.clusters, stats.cluster_rays);
            std::fflush(stdout);
        }
    }
    return 0;
}
