// Where a solve's links and bytes go: counts of element and cluster links by kind (root or
// cluster ends, pairwise or separable, visibility), by cluster level, and, with --cell C,
// whether both ends lie in one cell of a C x C grid in x and z (a generated building's
// rooms: tools/gen_building.py's pitch is 4.2 m), plus the bytes each structure holds.
//   link_census SCENE [--threads N] [--quality Q] [--cell C]
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "geometry/parts.h"
#include "io/import.h"
#include "radiosity/cluster_nodes.h"
#include "radiosity/solution.h"
#include "radiosity/solver.h"

using namespace radbake;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: link_census SCENE [--threads N] [--quality Q] [--cell C]\n");
        return 2;
    }
    const std::string path = argv[1];
    int threads = 2;
    double cell = 0.0;
    std::string quality = "medium";
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string key = argv[i], value = argv[i + 1];
        if (key == "--threads") threads = std::atoi(value.c_str());
        else if (key == "--cell") cell = std::atof(value.c_str());
        else if (key == "--quality") quality = value;
        else return 2;
    }
    Diagnostics diagnostics;
    const auto scene = importScene(path, ImportOptions{}, diagnostics);
    if (!scene) return 1;
    const PartSet parts = buildParts(*scene, PartOptions{}, diagnostics);
    const Quality q = qualityNamed(quality);
    SolverOptions options = SolverOptions::forQuality(q);
    Progress progress(false);
    ParallelRunner runner(Threading{.threads = threads, .pin = true});
    const auto start = std::chrono::steady_clock::now();
    const auto solution = solveRadiosity(*scene, parts, options, runner, progress, diagnostics);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!solution) return 1;
    const Solution& s = *solution;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::printf("solve %.2f s, peak rss %.1f MB, parts %zu, roots %u, elements %zu, clusters %zu\n", seconds,
                usage.ru_maxrss / 1024.0, parts.parts.size(), s.root_count, s.elements.size(), s.clusters.size());
    const SolveStats& st = s.stats;
    std::printf("links %zu (element %zu, cluster %zu), candidates %zu, split %zu, occluded %zu, dropped %zu, reopened %zu, "
                "shafts %zu, rays %zu (cluster %zu)\n",
                st.links, st.element_links, st.cluster_links, st.candidate_links, st.split_links, st.occluded_links,
                st.dropped_links, st.reopened_links, st.shafts, st.rays, st.cluster_rays);

    // A node's cell, or -1 when its box spans cells.
    auto cellOf = [&](const Aabb& box) -> long {
        if (!(cell > 0.0)) return -1;
        const long x0 = long(std::floor(box.min.x / cell)), x1 = long(std::floor(box.max.x / cell - 1e-9));
        const long z0 = long(std::floor(box.min.z / cell)), z1 = long(std::floor(box.max.z / cell - 1e-9));
        if (x0 != x1 || z0 != z1) return -1;
        return x0 * 100000 + z0;
    };
    std::vector<long> root_cell(s.root_count), cluster_cell(s.clusters.size());
    for (uint32_t r = 0; r < s.root_count; ++r) {
        Aabb box;
        const Element& e = s.elements[r];
        for (uint32_t v = 0; v < e.vertex_count; ++v) box.add(s.vertices[e.first_vertex + v]);
        root_cell[r] = cellOf(box);
    }
    std::vector<int> cluster_level(s.clusters.size(), 0);
    for (size_t c = 0; c < s.clusters.size(); ++c) {
        cluster_cell[c] = cellOf(s.clusters[c].box);
        if (s.clusters[c].parent != kNoElement) cluster_level[c] = cluster_level[s.clusters[c].parent] + 1;
    }
    auto nodeCell = [&](uint32_t node) { return isCluster(node) ? cluster_cell[clusterOf(node)] : root_cell[node]; };
    auto where = [&](long a, long b) -> const char* {
        if (!(cell > 0.0)) return "";
        if (a < 0 || b < 0) return " multi-cell";
        return a == b ? " same-cell" : " cross-cell";
    };

    std::map<std::string, size_t> counts;
    size_t partial = 0, dark = 0;
    for (const Link& l : s.links) {
        const uint32_t ra = s.elements[l.receiver].root, rb = s.elements[l.source].root;
        const char* vis = l.visibility <= 0.0f ? " invisible" : l.visibility < 1.0f ? " partial" : " visible";
        counts[std::string("element") + vis + where(root_cell[ra], root_cell[rb])]++;
        partial += l.by_rays;
        dark += l.visibility <= 0.0f;
    }
    std::map<int, size_t> by_level;
    size_t kernel_links = 0;
    for (const ClusterLink& l : s.cluster_links) {
        const char* kind = isCluster(l.receiver) ? (isCluster(l.source) ? "cc" : "cr") : "rc";
        const char* form = l.kernel != kNoKernel ? " pairwise" : " separable";
        const char* vis = l.visibility < 0.0f ? " deferred" : l.visibility == 0.0f ? " blocked" : " open";
        counts[std::string("cluster ") + kind + form + vis + where(nodeCell(l.receiver), nodeCell(l.source))]++;
        kernel_links += l.kernel != kNoKernel;
        const int level = std::max(isCluster(l.receiver) ? cluster_level[clusterOf(l.receiver)] : 99,
                                   isCluster(l.source) ? cluster_level[clusterOf(l.source)] : 99);
        by_level[std::min(level, isCluster(l.receiver) && isCluster(l.source)
                                     ? std::min(cluster_level[clusterOf(l.receiver)], cluster_level[clusterOf(l.source)])
                                     : level)]++;
    }
    std::printf("\n%-52s %12s\n", "kind", "links");
    for (const auto& [k, n] : counts) std::printf("%-52s %12zu\n", k.c_str(), n);
    std::printf("\ncluster links by the shallower cluster end's level:");
    for (const auto& [lv, n] : by_level) std::printf(" %d:%zu", lv, n);
    std::printf("\n\nbytes: elements %.1f MB (%zu x %zu), vertices %.1f MB, links %.1f MB (%zu x %zu), cluster links %.1f MB "
                "(%zu x %zu), cluster kernels %.1f MB (%zu floats over %zu links)\n",
                s.elements.size() * sizeof(Element) / 1e6, s.elements.size(), sizeof(Element),
                s.vertices.size() * sizeof(DVec3) / 1e6, s.links.size() * sizeof(Link) / 1e6, s.links.size(),
                sizeof(Link), s.cluster_links.size() * sizeof(ClusterLink) / 1e6, s.cluster_links.size(),
                sizeof(ClusterLink), s.cluster_kernel.size() * sizeof(float) / 1e6, s.cluster_kernel.size(),
                kernel_links);
    size_t zeros = 0;
    for (const float k : s.cluster_kernel) zeros += k == 0.0f ? 1 : 0;
    std::printf("partial element links %zu, invisible element links %zu, zero kernel entries %zu of %zu\n", partial,
                dark, zeros, s.cluster_kernel.size());
    return 0;
}
