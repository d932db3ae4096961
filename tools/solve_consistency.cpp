// solve_consistency: does the solve's link structure carry the light the solved radiosities
// imply? Solves SCENE as bake() does, then for a sample of leaves compares the irradiance the
// solve gave each leaf ((B - E) / rho) with the exhaustive gather at its centroid from the
// same radiosities. A link structure that loses light reads below 1. Prints the ratio per kind
// of surface (one-sided, front and back of two-sided meshes), the leaves losing the most light
// (area x H), and the element links reaching the worst of them with their form factor and
// visibility beside the leaf's own (its Gauss-averaged form factor, 8 x 8 rays).
//   solve_consistency SCENE [--quality draft|medium|high] [--threads N] [--every K=17] [--explain R=0]
// K: every K-th leaf of reflectance above 0.05 is read; R: the rank, by lost light, of the leaf
// whose links are listed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "radbake.h"
#include "radiosity/elements.h"
#include "radiosity/form_factor.h"
#include "radiosity/refine.h"
#include "visibility/ray_caster.h"
#include "readout/evaluate_probe.h"

using namespace radbake;

int main(int argc, char** argv) {
    if (argc < 2) return 2;
    std::string quality = "medium";
    int threads = 0;
    size_t every = 17, explain = 0;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string key = argv[i];
        if (key == "--quality") quality = argv[i + 1];
        else if (key == "--threads") threads = std::atoi(argv[i + 1]);
        else if (key == "--every") every = std::strtoul(argv[i + 1], nullptr, 10);
        else if (key == "--explain") explain = std::strtoul(argv[i + 1], nullptr, 10);
    }
    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic&) {};
    auto scene = importScene(argv[1], ImportOptions{}, diagnostics);
    if (!scene) return 1;
    addBackTwins(*scene);
    const PartSet parts = buildParts(*scene, PartOptions{}, diagnostics);
    const Quality q = quality == "draft" ? Quality::Draft : quality == "high" ? Quality::High : Quality::Medium;
    SolverOptions options = SolverOptions::forQuality(q);
    Progress progress(false);
    ParallelRunner runner(Threading{.threads = threads, .pin = false});
    const auto s = solveRadiosity(*scene, parts, options, runner, progress, diagnostics);
    if (!s) return 1;
    const ReadoutOptions readout = ReadoutOptions::forQuality(q);
    std::vector<uint32_t> sample;
    for (uint32_t i = 0, k = 0; i < s->elements.size(); ++i) {
        const Element& e = s->elements[i];
        if (!e.isLeaf() || !(maxChannel(e.reflectance) > 0.05)) continue;
        if (k++ % every == 0) sample.push_back(i);
    }
    std::vector<double> solved(sample.size()), gathered(sample.size());
    runner.forEach(sample.size(), 4, [&](size_t j) {
        const Element& e = s->elements[sample[j]];
        double hs = 0.0;
        int n = 0;
        for (int c = 0; c < 3; ++c)
            if (e.reflectance[c] > 0.05) hs += (e.radiosity[c] - e.emission[c]) / e.reflectance[c], ++n;
        solved[j] = hs / n;
        const DVec3 p = e.centroid + 1e-6 * s->scene_extent * e.normal;
        const DVec3 h = probeIrradiance(*s, readout, p, e.normal, e.mesh);
        double hg = 0.0;
        for (int c = 0; c < 3; ++c)
            if (e.reflectance[c] > 0.05) hg += h[c];
        gathered[j] = hg / n;
    });
    // Kinds: 0 one-sided, 1 front of a two-sided mesh, 2 back twin.
    double sum_s[3] = {}, sum_g[3] = {};
    size_t count[3] = {};
    std::vector<double> ratios;
    double brightest = 0.0;
    for (double g : gathered) brightest = std::max(brightest, g);
    for (size_t j = 0; j < sample.size(); ++j) {
        const Element& e = s->elements[sample[j]];
        const Mesh& m = scene->meshes[e.mesh];
        const int kind = m.back ? 2 : (m.twin != kNoMesh ? 1 : 0);
        sum_s[kind] += e.area * solved[j];
        sum_g[kind] += e.area * gathered[j];
        ++count[kind];
        if (gathered[j] > 0.05 * brightest) ratios.push_back(solved[j] / gathered[j]);
    }
    std::vector<size_t> order(sample.size());
    for (size_t j = 0; j < order.size(); ++j) order[j] = j;
    const auto loss = [&](size_t j) { return s->elements[sample[j]].area * (gathered[j] - solved[j]); };
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return loss(a) > loss(b); });
    double total_loss = 0.0;
    for (size_t j = 0; j < order.size(); ++j) total_loss += loss(j);
    std::printf("total loss (area x H) %.4g\n", total_loss);
    for (size_t k = 0; k < std::min<size_t>(25, order.size()); ++k) {
        const size_t j = order[k];
        const Element& e = s->elements[sample[j]];
        const Mesh& m = scene->meshes[e.mesh];
        std::printf("  loss %.3g  solved %.4g gathered %.4g  area %.4f  mesh %u '%s'%s  at %.3f %.3f %.3f n %.2f %.2f %.2f\n",
                    loss(j), solved[j], gathered[j], e.area, e.mesh, m.name.c_str(), m.back ? " (back)" : "",
                    e.centroid.x, e.centroid.y, e.centroid.z, e.normal.x, e.normal.y, e.normal.z);
    }
    // The links reaching the leaf of rank `explain` and its ancestors: F, V, and the exact
    // average with 8 x 8 rays.
    if (explain < order.size()) {
        const uint32_t leaf = sample[order[explain]];
        const Element& le = s->elements[leaf];
        std::vector<size_t> begin(s->elements.size() + 1, 0);
        for (const Link& link : s->links) ++begin[link.receiver + 1];
        for (size_t i = 0; i < s->elements.size(); ++i) begin[i + 1] += begin[i];
        double sum_h = 0.0, sum_exact = 0.0;
        for (uint32_t a = leaf; a != kNoElement; a = s->elements[a].parent) {
            for (size_t l = begin[a]; l < begin[a + 1]; ++l) {
                const Link& link = s->links[l];
                const Element& src = s->elements[link.source];
                const PolygonView sp = polygonOf(*s, src), rp = polygonOf(*s, le);
                const double avg = gaussAveragedFormFactor(rp.vertices, le.normal, sp.vertices, src.normal);
                const double vis = s->rays->visibleFraction(sp.vertices, rp.vertices, 8);
                const double b = (src.radiosity.x + src.radiosity.y + src.radiosity.z) / 3;
                sum_h += link.form_factor * link.visibility * b;
                sum_exact += avg * vis * b;
                if (b * link.form_factor > 1e-4 || b * avg > 1e-3)
                    std::printf("   at %u: from %u '%s' B %.3g  F %.4g V %.3f%s  | leaf avg F %.4g  V8 %.3f\n", a, link.source,
                                scene->meshes[src.mesh].name.c_str(), b, link.form_factor, link.visibility,
                                link.by_rays ? " rays" : "", avg, vis);
            }
        }
        std::printf("  element links: hier %.4g exact %.4g\n", sum_h, sum_exact);
    }
    std::sort(ratios.begin(), ratios.end());
    const char* names[3] = {"one-sided", "front", "back"};
    for (int k = 0; k < 3; ++k)
        std::printf("%-9s leaves %6zu  area-weighted solved / gathered %.4f\n", names[k], count[k],
                    sum_g[k] > 0 ? sum_s[k] / sum_g[k] : 0.0);
    if (!ratios.empty())
        std::printf("bright leaves %zu: ratio p05 %.3f p25 %.3f median %.3f p75 %.3f p95 %.3f\n", ratios.size(),
                    ratios[ratios.size() / 20], ratios[ratios.size() / 4], ratios[ratios.size() / 2],
                    ratios[3 * ratios.size() / 4], ratios[19 * ratios.size() / 20]);
    return 0;
}
