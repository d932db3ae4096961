// Where two-sided surfaces' links go: solves a scene as bake() does (back twins, parts,
// medium quality unless told) and prints its links by the kind of their ends (one-sided,
// front of a two-sided mesh, back twin), how much light each kind carries, and the meshes
// that receive the most links.
//   bench_two_sided SCENE [--threads N] [--quality q] [--top K] [--local T]
//                   [--one-sided 1 | --two-sided NAME,NAME,...]
// --one-sided: every mesh one-sided (what main did before two-sided surfaces); --two-sided:
// only the named meshes two-sided; --local: the local error threshold.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "geometry/parts.h"
#include "io/import.h"
#include "radiosity/refine.h"
#include "radiosity/solution.h"
#include "radiosity/solver.h"
#include "scene/two_sided.h"

using namespace radbake;

namespace {

// 0 one-sided, 1 front of a two-sided mesh, 2 back twin.
int kindOf(const Scene& scene, uint32_t mesh) {
    const Mesh& m = scene.meshes[mesh];
    if (m.back) return 2;
    return m.twin != kNoMesh ? 1 : 0;
}

const char* kKind = "OFB";

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_two_sided SCENE [--threads N] [--quality q] [--top K] [--local T] "
                             "[--one-sided 1 | --two-sided NAME,...]\n");
        return 2;
    }
    int threads = 2, top = 20;
    double local = -1.0;
    std::string quality = "medium", two_sided_names;
    bool one_sided = false;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string key = argv[i], value = argv[i + 1];
        if (key == "--threads") threads = std::atoi(value.c_str());
        else if (key == "--quality") quality = value;
        else if (key == "--top") top = std::atoi(value.c_str());
        else if (key == "--local") local = std::atof(value.c_str());
        else if (key == "--one-sided") one_sided = value != "0";
        else if (key == "--two-sided") two_sided_names = value;
        else return 2;
    }
    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic&) {};
    auto scene = importScene(argv[1], ImportOptions{}, diagnostics);
    if (!scene) return 1;
    const size_t original = scene->meshes.size();
    if (one_sided) {
        for (Mesh& m : scene->meshes) m.solid = true;
    } else if (!two_sided_names.empty()) {
        // Only the named meshes stay two-sided: the same scene lit the same way (say, a room
        // whose walls face out) with every other surface one-sided, to tell what the second
        // sides cost from what lighting the scene costs.
        const std::string list = "," + two_sided_names + ",";
        for (Mesh& m : scene->meshes)
            if (list.find("," + m.name + ",") == std::string::npos) m.solid = true;
    }
    addBackTwins(*scene);
    size_t settled = 0;
    for (const Mesh& m : scene->meshes) settled += m.closed_two_sided ? 1 : 0;
    std::printf("meshes %zu, twins %zu, settled closed %zu, covered back polygons %zu\n", original,
                scene->meshes.size() - original, settled, size_t(scene->covered_back_polygons));
    const PartSet parts = buildParts(*scene, PartOptions{}, diagnostics);
    const Quality q = quality == "draft" ? Quality::Draft
                      : quality == "high" ? Quality::High
                      : quality == "reference" ? Quality::Reference
                                              : Quality::Medium;
    SolverOptions options = SolverOptions::forQuality(q);
    if (local >= 0.0) options.local_error_threshold = local;
    Progress progress(false);
    ParallelRunner runner(Threading{.threads = threads, .pin = false});
    const auto s = solveRadiosity(*scene, parts, options, runner, progress, diagnostics);
    if (!s) return 1;
    std::printf("elements %zu, links %zu (element %zu, cluster %zu), iterations %d, rays %zu\n", s->stats.elements,
                s->stats.links, s->stats.element_links, s->stats.cluster_links, s->stats.iterations, s->stats.rays);

    // Roots, elements and the power each kind receives and emits.
    double kind_area[3] = {}, kind_power[3] = {}, kind_gather[3] = {};
    size_t kind_roots[3] = {}, kind_elements[3] = {};
    for (uint32_t i = 0; i < s->elements.size(); ++i) {
        const Element& e = s->elements[i];
        const int k = kindOf(*scene, e.mesh);
        ++kind_elements[k];
        if (i < s->root_count) {
            ++kind_roots[k];
            kind_area[k] += e.area;
            kind_power[k] += e.area * maxChannel(e.radiosity);
        }
    }
    // Element links by kinds of their ends: count and power carried (A_R F B_S).
    size_t pair_links[3][3] = {};
    double pair_power[3][3] = {};
    size_t same_mesh_twin = 0;
    std::vector<size_t> mesh_links(scene->meshes.size(), 0);
    std::vector<double> mesh_gather(scene->meshes.size(), 0.0);
    for (const Link& l : s->links) {
        const Element& r = s->elements[l.receiver];
        const Element& e = s->elements[l.source];
        const int kr = kindOf(*scene, r.mesh), ke = kindOf(*scene, e.mesh);
        ++pair_links[kr][ke];
        const double p = r.area * l.form_factor * maxChannel(e.radiosity);
        pair_power[kr][ke] += p;
        kind_gather[kr] += p * maxChannel(r.reflectance);
        if (kr == 2 && ke == 2 && r.mesh == e.mesh) ++same_mesh_twin;
        ++mesh_links[r.mesh];
        mesh_gather[r.mesh] += p;
    }
    for (int k = 0; k < 3; ++k)
        std::printf("kind %c: roots %zu, elements %zu, area %.4g, power out %.4g\n", kKind[k], kind_roots[k],
                    kind_elements[k], kind_area[k], kind_power[k]);
    std::printf("element links receiver<-source: count, power in\n");
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            std::printf("  %c<-%c %9zu %.4g\n", kKind[a], kKind[b], pair_links[a][b], pair_power[a][b]);
    std::printf("  B<-B within one mesh: %zu\n", same_mesh_twin);

    // Cluster links whose ends are roots, by kind; cluster-cluster by count only.
    size_t cl[4][4] = {};
    for (const ClusterLink& l : s->cluster_links) {
        const int kr = (l.receiver & kClusterNode) ? 3 : kindOf(*scene, s->elements[l.receiver].mesh);
        const int ke = (l.source & kClusterNode) ? 3 : kindOf(*scene, s->elements[l.source].mesh);
        ++cl[kr][ke];
    }
    const char* ck = "OFBC";
    std::printf("cluster links receiver<-source (C: a cluster)\n");
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
            if (cl[a][b]) std::printf("  %c<-%c %9zu\n", ck[a], ck[b], cl[a][b]);

    std::vector<uint32_t> order(scene->meshes.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return mesh_links[a] > mesh_links[b]; });
    std::printf("meshes receiving the most element links: links, power in, name\n");
    for (int i = 0; i < top && i < int(order.size()); ++i)
        std::printf("  %8zu %10.4g %c %s\n", mesh_links[order[i]], mesh_gather[order[i]],
                    kKind[kindOf(*scene, order[i])], scene->meshes[order[i]].name.c_str());
    // Twins whose links bring (almost) nothing.
    size_t dark_twins = 0, dark_twin_links = 0;
    for (uint32_t m = 0; m < scene->meshes.size(); ++m) {
        if (!scene->meshes[m].back) continue;
        if (mesh_gather[m] <= 0.0) {
            ++dark_twins;
            dark_twin_links += mesh_links[m];
        }
    }
    {
        std::map<std::pair<uint32_t, uint32_t>, std::pair<double, size_t>> pairs;
        for (const Link& l : s->links) {
            const Element& r = s->elements[l.receiver];
            const Element& e = s->elements[l.source];
            auto& v = pairs[{r.mesh, e.mesh}];
            v.first += r.area * l.form_factor * maxChannel(e.radiosity);
            ++v.second;
        }
        std::vector<std::pair<double, std::pair<uint32_t, uint32_t>>> list;
        for (const auto& [k, v] : pairs) list.push_back({v.first, k});
        std::sort(list.rbegin(), list.rend());
        std::printf("mesh pairs carrying the most power: power, links, receiver <- source\n");
        for (int i = 0; i < top && i < int(list.size()); ++i)
            std::printf("  %10.4g %7zu %s <- %s\n", list[i].first, pairs[list[i].second].second,
                        scene->meshes[list[i].second.first].name.c_str(), scene->meshes[list[i].second.second].name.c_str());
        std::vector<std::pair<double, uint32_t>> emitters;
        for (uint32_t i = 0; i < s->root_count; ++i) {
            const Element& e = s->elements[i];
            if (maxChannel(e.emission) > 0) emitters.push_back({e.area * maxChannel(e.emission), e.mesh});
        }
        std::map<uint32_t, double> em;
        for (auto& [p, m] : emitters) em[m] += p;
        std::vector<std::pair<size_t, std::pair<uint32_t, uint32_t>>> bycount;
        for (const auto& [k, v] : pairs) bycount.push_back({v.second, k});
        std::sort(bycount.rbegin(), bycount.rend());
        std::printf("mesh pairs with the most element links: links, power, receiver <- source\n");
        for (int i = 0; i < top && i < int(bycount.size()); ++i)
            std::printf("  %7zu %10.4g %s <- %s\n", bycount[i].first, pairs[bycount[i].second].first,
                        scene->meshes[bycount[i].second.first].name.c_str(), scene->meshes[bycount[i].second.second].name.c_str());
        std::printf("emitting meshes (area x emission incl. direct): %zu\n", em.size());
        std::vector<std::pair<double, uint32_t>> el;
        for (auto& [m, p] : em) el.push_back({p, m});
        std::sort(el.rbegin(), el.rend());
        for (int i = 0; i < 10 && i < int(el.size()); ++i) std::printf("  %10.4g %s\n", el[i].first, scene->meshes[el[i].second].name.c_str());
    }
    {
        // Per root: H = (B - E) / rho (area mean); links whose receiver lies in it.
        std::vector<double> h(s->root_count, 0.0);
        std::vector<double> lit;
        for (uint32_t i = 0; i < s->root_count; ++i) {
            const Element& e = s->elements[i];
            const double rho = maxChannel(e.reflectance);
            h[i] = rho > 0 ? maxChannel(e.radiosity - e.emission) / rho : -1.0;
            if (kindOf(*scene, e.mesh) != 2 && h[i] >= 0) lit.push_back(h[i]);
        }
        std::sort(lit.begin(), lit.end());
        const double median = lit.empty() ? 0.0 : lit[lit.size() / 2];
        std::vector<size_t> root_links(s->root_count, 0), root_src_links(s->root_count, 0);
        for (const Link& l : s->links) { ++root_links[s->elements[l.receiver].root]; ++root_src_links[s->elements[l.source].root]; }
        for (const ClusterLink& l : s->cluster_links) {
            if (!(l.receiver & kClusterNode)) ++root_links[l.receiver];
            if (!(l.source & kClusterNode)) ++root_src_links[l.source];
        }
        const double bins[] = {0.0, 1e-4, 1e-3, 1e-2, 1e-1, 1.0, 1e300};
        for (int kind = 0; kind < 3; ++kind) {
            std::printf("kind %c roots by H / median front H (%.4g): count, links in, links out\n", kKind[kind], median);
            for (int b = 0; b + 1 < 7; ++b) {
                size_t n = 0, li = 0, lo = 0;
                for (uint32_t i = 0; i < s->root_count; ++i) {
                    if (kindOf(*scene, s->elements[i].mesh) != kind) continue;
                    if (h[i] < 0.0 || !(median > 0.0)) continue;
                    const double x = h[i] / median;
                    if (x < bins[b] || x >= bins[b + 1]) continue;
                    ++n, li += root_links[i], lo += root_src_links[i];
                }
                std::printf("  [%g, %g): %zu %zu %zu\n", bins[b], bins[b + 1], n, li, lo);
            }
        }
    }
    std::printf("twins gathering nothing through element links: %zu (%zu links)\n", dark_twins, dark_twin_links);
    return 0;
}
