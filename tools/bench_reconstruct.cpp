// Link reconstruction against the exhaustive gather (issue 12): imports and solves a scene
// once, then fills its lightmap texels (no seam fit) and its vertices both ways, and prints
// the time per covered texel and per vertex and the error against the exhaustive gather:
// per channel |fast - exhaustive| / max(exhaustive, 1 % of the brightest), RMS and worst
// over covered texels (vertices).
//   bench_reconstruct [SCENE] [--quality medium] [--texel-density 16] [--threads 0]
//                     [--skip-exhaustive-texels | --skip-exhaustive | --vertices-only] [--worst]
//                     [--repeat N] [--edge-correction off|shared|on] [--vertex-csv FILE] [--error-threshold E] [--no-clustering]
// --skip-exhaustive: no exhaustive reference at all (timings only); --vertices-only: the
// vertices, timed, no reference; --worst lists the 30 worst vertices (1 % floor), and
// for texels each mesh's RMS and share of the squared error, and the 30 worst texels (5 a mesh);
// --repeat N bakes the vertices N times (the figures are per bake), so that a profiler sees
// the reconstruction rather than the solve.
// Texels: "links all" evaluates every covered texel with the reconstruction, "links
// adaptive" with the quality's --texel-tolerance as bakes do; both against every texel
// evaluated exhaustively (the --texel-tolerance 0 bake).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "radbake.h"
#include "readout/reconstruct.h"

using namespace radbake;

namespace {

bool g_list_worst = false;  // --worst: list the vertices and texels more than 30 % off

// CPU seconds of the whole process (every thread): less disturbed than wall time when other
// work shares the cores.
double cpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

struct Error {
    double rms = 0.0, worst = 0.0;
    size_t count = 0;
};

template <class Get>
Error compare(size_t n, Get get) {
    double brightest = 0.0;
    for (size_t i = 0; i < n; ++i) {
        DVec3 fast, ref;
        if (!get(i, fast, ref)) continue;
        brightest = std::max({brightest, ref.x, ref.y, ref.z});
    }
    Error e;
    double sum2 = 0.0;
    for (size_t i = 0; i < n; ++i) {
        DVec3 fast, ref;
        if (!get(i, fast, ref)) continue;
        for (int c = 0; c < 3; ++c) {
            const double r = std::abs(fast[c] - ref[c]) / std::max(ref[c], 0.01 * brightest);
            sum2 += r * r;
            e.worst = std::max(e.worst, r);
        }
        ++e.count;
    }
    if (e.count > 0) e.rms = std::sqrt(sum2 / (3.0 * static_cast<double>(e.count)));
    return e;
}

// The chart holding texel (x, y) of atlas k, or null.
const LightmapChart* chartAt(const LightmapLayout& layout, size_t k, int x, int y) {
    for (const LightmapChart& c : layout.charts)
        if (c.atlas == static_cast<int>(k) && x >= c.x && x < c.x + c.width && y >= c.y && y < c.y + c.height) return &c;
    return nullptr;
}

Error compareTexels(const Lightmaps& fast, const Lightmaps& ref) {
    std::vector<std::pair<size_t, size_t>> covered;  // (image, texel)
    for (size_t k = 0; k < ref.images.size(); ++k)
        for (size_t t = 0; t < ref.images[k].state.size(); ++t)
            if (ref.images[k].state[t] == TexelState::Covered) covered.emplace_back(k, t);
    const auto get = [&](size_t i, DVec3& a, DVec3& b) {
        const auto [k, t] = covered[i];
        const float* fa = &fast.images[k].rgb[3 * t];
        const float* fb = &ref.images[k].rgb[3 * t];
        a = DVec3(fa[0], fa[1], fa[2]);
        b = DVec3(fb[0], fb[1], fb[2]);
        return true;
    };
    if (g_list_worst) {
        double brightest = 0.0;
        for (const auto& [k, t] : covered) brightest = std::max(brightest, double(ref.images[k].rgb[3 * t]));
        // Per mesh: count, RMS of the red channel's error and its share of the whole sum of squares;
        // then the 30 worst texels (at most 5 a mesh) with the world point of their centre.
        struct Texel {
            double error;
            size_t index;
            uint32_t mesh;
            DVec3 p, n;
        };
        std::vector<Texel> all;
        std::vector<double> sum2_of_mesh;
        std::vector<size_t> count_of_mesh;
        double sum2 = 0.0;
        for (size_t i = 0; i < covered.size(); ++i) {
            const auto [k, t] = covered[i];
            const double a = fast.images[k].rgb[3 * t], b = ref.images[k].rgb[3 * t];
            const double r = std::abs(a - b) / std::max(b, 0.01 * brightest);
            const int x = static_cast<int>(t % ref.images[k].width), y = static_cast<int>(t / ref.images[k].width);
            const LightmapChart* c = chartAt(fast.layout, k, x, y);
            if (!c) continue;
            const DVec3 p = c->worldPoint(c->min_plane + (DVec2(x - c->x, y - c->y) + 0.5) / c->texels_per_metre);
            all.push_back({r, i, c->mesh, p, c->normal_world});
            if (c->mesh >= sum2_of_mesh.size()) sum2_of_mesh.resize(c->mesh + 1), count_of_mesh.resize(c->mesh + 1);
            sum2_of_mesh[c->mesh] += r * r;
            count_of_mesh[c->mesh] += 1;
            sum2 += r * r;
        }
        for (size_t m = 0; m < sum2_of_mesh.size(); ++m)
            if (count_of_mesh[m] > 0)
                std::printf("  mesh %zu: %zu texels rms %.4f share %.3f\n", m, count_of_mesh[m],
                            std::sqrt(sum2_of_mesh[m] / count_of_mesh[m]), sum2 > 0 ? sum2_of_mesh[m] / sum2 : 0.0);
        std::sort(all.begin(), all.end(), [](const Texel& a, const Texel& b) { return a.error > b.error || (a.error == b.error && a.index < b.index); });
        std::vector<size_t> listed_of_mesh(sum2_of_mesh.size(), 0);
        for (size_t i = 0, listed = 0; i < all.size() && listed < 30; ++i) {
            if (listed_of_mesh[all[i].mesh]++ >= 5) continue;  // at most 5 a mesh
            ++listed;
            DVec3 a, b;
            get(all[i].index, a, b);
            std::printf("  texel %.3f: %g vs %g mesh %u at (%.4g %.4g %.4g) normal (%.2g %.2g %.2g)\n", all[i].error, a.x,
                        b.x, all[i].mesh, all[i].p.x, all[i].p.y, all[i].p.z, all[i].n.x, all[i].n.y, all[i].n.z);
        }
    }
    return compare(covered.size(), get);
}

}  // namespace

int main(int argc, char** argv) {
    std::string path = "scenes/cornell_box.wrl";
    std::string quality = "medium";
    double density = 16.0;
    int threads = 0, repeat = 1;
    std::string edge_correction;  // "": the quality's choice
    bool exhaustive_texels = true, exhaustive_vertices = true, texels = true;
    std::string vertex_csv;  // --vertex-csv FILE: every vertex's two readings
    double error_threshold = 0.0;  // --error-threshold E: the quality's otherwise
    bool no_clustering = false;
    int first = 1;
    if (argc > 1 && argv[1][0] != '-') path = argv[first++];
    for (int i = first; i < argc; ++i) {
        const std::string key = argv[i];
        if (key == "--worst") {
            g_list_worst = true;
            continue;
        }
        if (key == "--no-clustering") {
            no_clustering = true;
            continue;
        }
        if (key == "--skip-exhaustive-texels" || key == "--skip-exhaustive" || key == "--vertices-only") {
            exhaustive_texels = false;
            exhaustive_vertices = key == "--skip-exhaustive-texels";
            texels = key != "--vertices-only";
            continue;
        }
        if (i + 1 >= argc) {
            std::fprintf(stderr, "usage: bench_reconstruct [SCENE] [--quality medium] [--texel-density 16] "
                                 "[--threads 0] [--skip-exhaustive-texels|--skip-exhaustive|--vertices-only] "
                                 "[--worst] [--repeat N] [--edge-correction off|shared|on] [--vertex-csv FILE] [--error-threshold E] [--no-clustering]\n");
            return 2;
        }
        const std::string value = argv[++i];
        if (key == "--quality") quality = value;
        else if (key == "--texel-density") density = std::atof(value.c_str());
        else if (key == "--threads") threads = std::atoi(value.c_str());
        else if (key == "--repeat") repeat = std::max(1, std::atoi(value.c_str()));
        else if (key == "--edge-correction") edge_correction = value;
        else if (key == "--vertex-csv") vertex_csv = value;
        else if (key == "--error-threshold") error_threshold = std::atof(value.c_str());
        else {
            std::fprintf(stderr, "unknown option %s\n", key.c_str());
            return 2;
        }
    }
    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic& d) {
        if (d.severity == Severity::Error) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
    };
    auto scene = importScene(path, ImportOptions{}, diagnostics);
    if (!scene) return 1;
    addBackTwins(*scene);  // as bake() does: both sides of two-sided meshes take part
    const Quality q = qualityNamed(quality);
    BakeOptions preset = BakeOptions::forQuality(q);
    if (!edge_correction.empty())
        preset.readout.edge_correction = edge_correction == "on"       ? EdgeCorrection::On
                                         : edge_correction == "shared" ? EdgeCorrection::Shared
                                                                       : EdgeCorrection::Off;
    if (error_threshold > 0.0) preset.solver.error_threshold = error_threshold;
    if (no_clustering) preset.solver.clustering = false;
    const ReadoutOptions& readout = preset.readout;
    ReadoutOptions exhaustive_readout = readout;
    exhaustive_readout.gather = GatherMode::Exhaustive;
    Progress progress(false);
    ParallelRunner runner(Threading{.threads = threads});
    const PartSet parts = buildParts(*scene, PartOptions{}, diagnostics);
    auto start = std::chrono::steady_clock::now();
    const auto solution = solveRadiosity(*scene, parts, preset.solver, runner, progress, diagnostics);
    if (!solution) return 1;
    std::printf("scene %s quality %s threads %d elements %zu links %zu cluster_links %zu solve_s %.3f\n", path.c_str(),
                quality.c_str(), runner.threads(), solution->elements.size(), solution->links.size(),
                solution->cluster_links.size(), seconds(start));

    // Vertices.
    start = std::chrono::steady_clock::now();
    double cpu = cpuSeconds();
    VertexBake v_links;
    for (int r = 0; r < repeat; ++r) v_links = bakeVertices(*scene, *solution, readout, runner);
    const double t_links = seconds(start) / repeat, cpu_links = (cpuSeconds() - cpu) / repeat;
    // Work per vertex: the reconstruction at each vertex with its first face's normal.
    {
        const LinkReconstruction links(*solution, readout, runner);
        ProbeCounters counters;
        size_t n = 0;
        size_t fallback[4] = {0, 0, 0, 0}, fallback_rays[4] = {0, 0, 0, 0};
        for (uint32_t m = 0; m < scene->meshes.size(); ++m) {
            const Mesh& mesh = scene->meshes[m];
            for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
                const DVec3 a(mesh.positions[mesh.triangles[t].x]), b(mesh.positions[mesh.triangles[t].y]),
                    c(mesh.positions[mesh.triangles[t].z]);
                const DVec3 cr = glm::cross(b - a, c - a);
                if (!(glm::length(cr) > 0.0)) continue;
                const size_t before = counters.rays;
                links.irradianceCounted(m, t, a, glm::normalize(cr), counters);
                ++n;
                const uint32_t leaf = links.leafAt(m, t, a);
                const int why = leaf == kNoElement ? 0
                                : glm::dot(solution->elements[leaf].normal, glm::normalize(cr)) <= 0.5 ? 1
                                : !(std::max({solution->elements[leaf].reflectance.x, solution->elements[leaf].reflectance.y, solution->elements[leaf].reflectance.z}) > 0.0) ? 2 : 3;
                fallback[why] += 1;
                fallback_rays[why] += counters.rays - before;
            }
        }
        const double dn = static_cast<double>(std::max<size_t>(n, 1));
        std::printf("corners: no leaf %zu (rays %zu), back %zu (%zu), black %zu (%zu), links %zu (%zu)\n", fallback[0],
                    fallback_rays[0], fallback[1], fallback_rays[1], fallback[2], fallback_rays[2], fallback[3], fallback_rays[3]);
        std::printf("per corner evaluation: rays %.1f form_factors %.1f pieces %.1f\n", counters.rays / dn,
                    counters.form_factors / dn, counters.pieces / dn);
    }
    VertexBake v_ref = v_links;
    double t_ref = 0.0;
    if (exhaustive_vertices) {
        start = std::chrono::steady_clock::now();
        v_ref = bakeVertices(*scene, *solution, exhaustive_readout, runner);
        t_ref = seconds(start);
    }
    std::vector<std::pair<size_t, size_t>> vertices;
    for (size_t m = 0; m < v_ref.values.size(); ++m)
        for (size_t v = 0; v < v_ref.values[m].size(); ++v) vertices.emplace_back(m, v);
    if (!vertex_csv.empty()) {
        // Both readings of every vertex (W/m^2 as the bake writes them), to score each against
        // a reference at the vertices (tools/vertex_probes keeps mesh and vertex per probe).
        std::FILE* f = std::fopen(vertex_csv.c_str(), "w");
        if (f == nullptr) {
            std::fprintf(stderr, "bench_reconstruct: cannot write %s\n", vertex_csv.c_str());
            return 1;
        }
        std::fprintf(f, "mesh,vertex,links_r,links_g,links_b,exhaustive_r,exhaustive_g,exhaustive_b\n");
        for (const auto& [m, v] : vertices) {
            const auto& a = v_links.values[m][v];
            const auto& b = v_ref.values[m][v];
            std::fprintf(f, "%zu,%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", m, v, a.x, a.y, a.z, b.x, b.y, b.z);
        }
        std::fclose(f);
    }
    const Error ev = compare(vertices.size(), [&](size_t i, DVec3& a, DVec3& b) {
        a = DVec3(v_links.values[vertices[i].first][vertices[i].second]);
        b = DVec3(v_ref.values[vertices[i].first][vertices[i].second]);
        return true;
    });
    if (g_list_worst) {
        // The 30 worst vertices (red channel, the 1 % floor of the error figures).
        double brightest = 0.0;
        for (const auto& [m, v] : vertices) brightest = std::max(brightest, double(v_ref.values[m][v].x));
        std::vector<std::pair<double, size_t>> order;
        for (size_t i = 0; i < vertices.size(); ++i) {
            const auto [m, v] = vertices[i];
            const double a = v_links.values[m][v].x, b = v_ref.values[m][v].x;
            order.emplace_back(std::abs(a - b) / std::max(b, 0.01 * brightest), i);
        }
        std::sort(order.begin(), order.end(), [](const auto& x, const auto& y) { return x.first > y.first || (x.first == y.first && x.second < y.second); });
        for (size_t k = 0; k < std::min<size_t>(order.size(), 30); ++k) {
            const auto [m, v] = vertices[order[k].second];
            std::printf("  vertex %.3f %zu/%zu %s (%g %g %g): %g vs %g\n", order[k].first, m, v,
                        scene->meshes[m].name.c_str(), scene->meshes[m].positions[v].x,
                        scene->meshes[m].positions[v].y, scene->meshes[m].positions[v].z, v_links.values[m][v].x,
                        v_ref.values[m][v].x);
        }
    }
    const double nv = static_cast<double>(std::max<size_t>(1, vertices.size()));
    std::printf("vertices %zu links_us_per_vertex %.1f (cpu %.1f) exhaustive_us_per_vertex %.1f rms %.4f worst %.4f\n",
                vertices.size(), 1e6 * t_links / nv, 1e6 * cpu_links / nv, 1e6 * t_ref / nv, ev.rms, ev.worst);

    if (!texels) return 0;
    // Texels.
    LightmapOptions options;
    options.texels_per_metre = density;
    LightmapLayout layout;
    if (!packLightmapCharts(buildLightmapCharts(*scene, options), options, layout, diagnostics)) return 1;
    const LinkReconstruction links(*solution, readout, runner);
    // Work done, deterministic where times are not (a shared machine): rays and point form
    // factors over every evaluated texel.
    std::atomic<size_t> texel_rays{0}, texel_form_factors{0};
    const IrradianceFunction fast = [&](const SurfacePoint& at) {
        ProbeCounters counters;
        const DVec3 h = links.irradianceCounted(at.mesh, at.triangle, at.p_world, at.normal_world, counters,
                                                LinkReconstruction::Reading::Texel);
        texel_rays += counters.rays;
        texel_form_factors += counters.form_factors;
        return h;
    };
    const IrradianceFunction exhaustive = [&](const SurfacePoint& at) {
        return probeIrradiance(*solution, readout, at.p_world, at.normal_world, at.mesh);
    };
    start = std::chrono::steady_clock::now();
    cpu = cpuSeconds();
    const Lightmaps all = evaluateLightmaps(layout, fast, options.padding, runner, 0.0);
    const double t_all = seconds(start), cpu_all = cpuSeconds() - cpu;
    const double rays_all = static_cast<double>(texel_rays), form_factors_all = static_cast<double>(texel_form_factors);
    start = std::chrono::steady_clock::now();
    cpu = cpuSeconds();
    const Lightmaps adaptive = evaluateLightmaps(layout, fast, options.padding, runner, preset.lightmaps.texel_tolerance);
    const double t_adaptive = seconds(start), cpu_adaptive = cpuSeconds() - cpu;
    const double rays_adaptive = static_cast<double>(texel_rays) - rays_all,
                 form_factors_adaptive = static_cast<double>(texel_form_factors) - form_factors_all;
    const double covered = static_cast<double>(std::max<size_t>(1, all.covered_texels));
    std::printf("texel_density %g covered_texels %zu\n", density, all.covered_texels);
    std::printf("links all:      %.1f us per covered texel (cpu %.1f; rays %.1f, form factors %.1f)\n",
                1e6 * t_all / covered, 1e6 * cpu_all / covered, rays_all / covered, form_factors_all / covered);
    std::printf("links adaptive: %.1f us per covered texel (cpu %.1f; tolerance %g, %zu evaluated; rays %.1f, form "
                "factors %.1f)\n",
                1e6 * t_adaptive / covered, 1e6 * cpu_adaptive / covered, preset.lightmaps.texel_tolerance,
                adaptive.evaluated_texels, rays_adaptive / covered, form_factors_adaptive / covered);
    if (!exhaustive_texels) return 0;
    start = std::chrono::steady_clock::now();
    const Lightmaps ref = evaluateLightmaps(layout, exhaustive, options.padding, runner, 0.0);
    const double t_ref_texels = seconds(start);
    std::printf("exhaustive:     %.1f us per covered texel\n", 1e6 * t_ref_texels / covered);
    const Error e_all = compareTexels(all, ref), e_adaptive = compareTexels(adaptive, ref);
    std::printf("error links all:      rms %.4f worst %.4f\n", e_all.rms, e_all.worst);
    std::printf("error links adaptive: rms %.4f worst %.4f\n", e_adaptive.rms, e_adaptive.worst);
    return 0;
}
