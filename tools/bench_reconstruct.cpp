// Link reconstruction against the exhaustive gather (issue 12): imports and solves a scene
// once, then fills its lightmap texels (no seam fit) and its vertices both ways, and prints
// the time per covered texel and per vertex and the error against the exhaustive gather:
// per channel |fast - exhaustive| / max(exhaustive, 1 % of the brightest), RMS and worst
// over covered texels (vertices).
//   bench_reconstruct [SCENE] [--quality medium] [--texel-density 16] [--threads 0]
//                     [--skip-exhaustive-texels | --skip-exhaustive | --vertices-only] [--worst]
//                     [--repeat N]
// --skip-exhaustive: no exhaustive reference at all (timings only); --vertices-only: the
// vertices, timed, no reference; --worst lists what is more than 30 % off (1 % floor);
// --repeat N bakes the vertices N times (the figures are per bake), so that a profiler sees
// the reconstruction rather than the solve.
// Texels: "links all" evaluates every covered texel with the reconstruction, "links
// adaptive" with the quality's --texel-tolerance as bakes do; both against every texel
// evaluated exhaustively (the --texel-tolerance 0 bake).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "radbake.h"
#include "radiosity/reconstruct.h"

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

Error compareTexels(const Lightmaps& fast, const Lightmaps& ref) {
    std::vector<std::pair<size_t, size_t>> covered;  // (image, texel)
    for (size_t k = 0; k < ref.images.size(); ++k)
        for (size_t t = 0; t < ref.images[k].state.size(); ++t)
            if (ref.images[k].state[t] == TexelState::Covered) covered.emplace_back(k, t);
    if (g_list_worst) {
        double brightest = 0.0;
        for (const auto& [k, t] : covered) brightest = std::max(brightest, double(ref.images[k].rgb[3 * t]));
        for (const auto& [k, t] : covered) {
            const double a = fast.images[k].rgb[3 * t], b = ref.images[k].rgb[3 * t];
            if (!(std::abs(a - b) / std::max(b, 0.01 * brightest) > 0.3)) continue;
            const int x = static_cast<int>(t % ref.images[k].width), y = static_cast<int>(t / ref.images[k].width);
            // The chart holding it: its mesh and the world point of the texel's centre.
            std::string where;
            for (const LightmapChart& c : ref.layout.charts)
                if (c.atlas == static_cast<int>(k) && x >= c.x && x < c.x + c.width && y >= c.y && y < c.y + c.height) {
                    const DVec3 p = c.worldPoint(c.min_plane + (DVec2(x - c.x, y - c.y) + 0.5) / c.texels_per_metre);
                    char text[160];
                    std::snprintf(text, sizeof text, " mesh %u at (%.3g %.3g %.3g) normal (%.2g %.2g %.2g)", c.mesh, p.x, p.y,
                                  p.z, c.normal_world.x, c.normal_world.y, c.normal_world.z);
                    where = text;
                    break;
                }
            std::printf("  texel %zu (%d, %d): %g vs %g%s\n", k, x, y, a, b, where.c_str());
        }
    }
    return compare(covered.size(), [&](size_t i, DVec3& a, DVec3& b) {
        const auto [k, t] = covered[i];
        const float* fa = &fast.images[k].rgb[3 * t];
        const float* fb = &ref.images[k].rgb[3 * t];
        a = DVec3(fa[0], fa[1], fa[2]);
        b = DVec3(fb[0], fb[1], fb[2]);
        return true;
    });
}

}  // namespace

int main(int argc, char** argv) {
    std::string path = "scenes/cornell_box.wrl";
    std::string quality = "medium";
    double density = 16.0;
    int threads = 0, repeat = 1;
    bool exhaustive_texels = true, exhaustive_vertices = true, texels = true;
    int first = 1;
    if (argc > 1 && argv[1][0] != '-') path = argv[first++];
    for (int i = first; i < argc; ++i) {
        const std::string key = argv[i];
        if (key == "--worst") {
            g_list_worst = true;
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
                                 "[--worst] [--repeat N]\n");
            return 2;
        }
        const std::string value = argv[++i];
        if (key == "--quality") quality = value;
        else if (key == "--texel-density") density = std::atof(value.c_str());
        else if (key == "--threads") threads = std::atoi(value.c_str());
        else if (key == "--repeat") repeat = std::max(1, std::atoi(value.c_str()));
        else {
            std::fprintf(stderr, "unknown option %s\n", key.c_str());
            return 2;
        }
    }
    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic& d) {
        if (d.severity == Severity::Error) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
    };
    const auto scene = importScene(path, ImportOptions{}, diagnostics);
    if (!scene) return 1;
    const Quality q = quality == "draft" ? Quality::Draft
                      : quality == "high" ? Quality::High
                      : quality == "reference" ? Quality::Reference
                                              : Quality::Medium;
    const BakeOptions preset = BakeOptions::forQuality(q);
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
    for (int r = 0; r < repeat; ++r) v_links = bakeVertices(*scene, *solution, runner, nullptr, GatherMode::Links);
    const double t_links = seconds(start) / repeat, cpu_links = (cpuSeconds() - cpu) / repeat;
    // Work per vertex: the reconstruction at each vertex with its first face's normal.
    {
        const LinkReconstruction links(*solution, runner);
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
        v_ref = bakeVertices(*scene, *solution, runner, nullptr, GatherMode::Exhaustive);
        t_ref = seconds(start);
    }
    std::vector<std::pair<size_t, size_t>> vertices;
    for (size_t m = 0; m < v_ref.values.size(); ++m)
        for (size_t v = 0; v < v_ref.values[m].size(); ++v) vertices.emplace_back(m, v);
    const Error ev = compare(vertices.size(), [&](size_t i, DVec3& a, DVec3& b) {
        a = DVec3(v_links.values[vertices[i].first][vertices[i].second]);
        b = DVec3(v_ref.values[vertices[i].first][vertices[i].second]);
        return true;
    });
    if (g_list_worst)
        for (const auto& [m, v] : vertices) {
            const double a = v_links.values[m][v].x, b = v_ref.values[m][v].x;
            if (std::abs(a - b) > 0.3 * std::max(b, 0.01))
                std::printf("  vertex %zu/%zu %s (%g %g %g): %g vs %g\n", m, v, scene->meshes[m].name.c_str(),
                            scene->meshes[m].positions[v].x, scene->meshes[m].positions[v].y,
                            scene->meshes[m].positions[v].z, a, b);
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
    const LinkReconstruction links(*solution, runner);
    const IrradianceFunction fast = [&](const SurfacePoint& at) {
        return links.irradiance(at.mesh, at.triangle, at.p_world, at.normal_world);
    };
    const IrradianceFunction exhaustive = [&](const SurfacePoint& at) {
        return probeIrradiance(*solution, at.p_world, at.normal_world);
    };
    start = std::chrono::steady_clock::now();
    cpu = cpuSeconds();
    const Lightmaps all = evaluateLightmaps(layout, fast, options.padding, runner, 0.0);
    const double t_all = seconds(start), cpu_all = cpuSeconds() - cpu;
    start = std::chrono::steady_clock::now();
    cpu = cpuSeconds();
    const Lightmaps adaptive = evaluateLightmaps(layout, fast, options.padding, runner, preset.lightmaps.texel_tolerance);
    const double t_adaptive = seconds(start), cpu_adaptive = cpuSeconds() - cpu;
    const double covered = static_cast<double>(std::max<size_t>(1, all.covered_texels));
    std::printf("texel_density %g covered_texels %zu\n", density, all.covered_texels);
    std::printf("links all:      %.1f us per covered texel (cpu %.1f)\n", 1e6 * t_all / covered, 1e6 * cpu_all / covered);
    std::printf("links adaptive: %.1f us per covered texel (cpu %.1f; tolerance %g, %zu evaluated)\n",
                1e6 * t_adaptive / covered, 1e6 * cpu_adaptive / covered, preset.lightmaps.texel_tolerance,
                adaptive.evaluated_texels);
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
