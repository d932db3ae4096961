// Probe evaluation benchmark: imports and solves a scene, then evaluates probeIrradiance at N
// deterministic points on its surfaces on ONE thread, and prints the median time per
// evaluation over R runs, the rays and form factors per evaluation, and a digest of the answers
// (sum and max over points and channels) so that a change in results is visible.
//   bench_probes [SCENE] [--quality draft|medium|high|reference] [--points N] [--runs R]
//                [--seed S] [--unit-scale S] [--dump FILE] [--compare FILE]
// Points: triangles chosen with probability proportional to their area, a uniform point in
// each, facing the triangle's front; every 8th point is the triangle's first corner instead
// (vertex bakes evaluate there, where the lift off touching surfaces matters).
// --dump writes the answers (%.17g, one point a line); --compare reads such a file and prints
// the largest relative change per point (|a - b| / max(|a|, |b|) over channels, points whose
// answers are both below 1e-12 of the largest answer skipped as zero).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "geometry/parts.h"
#include "io/import.h"
#include "readout/evaluate_probe.h"
#include "radiosity/solution.h"
#include "radiosity/solver.h"
#include "scene/two_sided.h"

using namespace radbake;

namespace {

struct Point {
    DVec3 p, n;
};

// splitmix64: the same sequence on every platform (std distributions are not specified).
struct Random {
    uint64_t state;
    uint64_t next() {
        uint64_t z = (state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

std::vector<Point> samplePoints(const Scene& scene, size_t count, uint64_t seed, double unit_scale) {
    struct Tri {
        DVec3 a, b, c, n;
    };
    std::vector<Tri> tris;
    std::vector<double> cumulative;
    double total = 0.0;
    for (const Mesh& mesh : scene.meshes)
        for (const UVec3& t : mesh.triangles) {
            if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size())
                continue;
            const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
            const DVec3 cr = glm::cross(b - a, c - a);
            const double len = glm::length(cr);
            if (!(len > 0.0) || !std::isfinite(len)) continue;
            total += 0.5 * len;
            tris.push_back({a, b, c, cr / len});
            cumulative.push_back(total);
        }
    std::vector<Point> points;
    if (tris.empty()) return points;
    Random random{seed};
    for (size_t i = 0; i < count; ++i) {
        const double target = random.uniform() * total;
        size_t k = std::lower_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin();
        k = std::min(k, tris.size() - 1);
        const Tri& t = tris[k];
        double u = random.uniform(), v = random.uniform();
        if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
        const DVec3 p = i % 8 == 7 ? t.a : t.a + u * (t.b - t.a) + v * (t.c - t.a);
        points.push_back({p * unit_scale, t.n});
    }
    return points;
}

double threadCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double relativeChange(const DVec3& a, const DVec3& b, double zero) {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double m = std::max(std::abs(a[c]), std::abs(b[c]));
        if (m <= zero) continue;
        worst = std::max(worst, std::abs(a[c] - b[c]) / m);
    }
    return worst;
}

}  // namespace

int main(int argc, char** argv) {
    std::string path = "scenes/cornell_box.wrl";  // run from the repository root
    std::string quality = "medium", dump, compare;
    size_t count = 2000;
    int runs = 5;
    uint64_t seed = 1;
    ImportOptions import_options;
    int first = 1;
    if (argc > 1 && argv[1][0] != '-') path = argv[first++];
    for (int i = first; i < argc; i += 2) {
        const std::string key = argv[i];
        if (i + 1 >= argc) {
            std::fprintf(stderr, "option %s needs a value\n", key.c_str());
            return 2;
        }
        const std::string value = argv[i + 1];
        if (key == "--quality") quality = value;
        else if (key == "--points") count = static_cast<size_t>(std::max(1L, std::atol(value.c_str())));
        else if (key == "--runs") runs = std::max(1, std::atoi(value.c_str()));
        else if (key == "--seed") seed = std::strtoull(value.c_str(), nullptr, 10);
        else if (key == "--unit-scale") import_options.unit_scale = std::strtof(value.c_str(), nullptr);
        else if (key == "--dump") dump = value;
        else if (key == "--compare") compare = value;
        else {
            std::fprintf(stderr,
                         "usage: bench_probes [SCENE] [--quality medium] [--points 2000] [--runs 5] [--seed 1] "
                         "[--unit-scale S] [--dump FILE] [--compare FILE]\n");
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
    SolverOptions options = SolverOptions::forQuality(q);
    const ReadoutOptions readout = ReadoutOptions::forQuality(q);
    Progress progress(false);
    ParallelRunner runner(Threading{});
    const auto solution = solveRadiosity(*scene, parts, options, runner, progress, diagnostics);
    if (!solution) return 1;
    // The scene's positions are already scaled by the import (unit_scale): sample them as they are.
    const std::vector<Point> points = samplePoints(*scene, count, seed, 1.0);
    if (points.empty()) {
        std::fprintf(stderr, "no triangles to sample\n");
        return 1;
    }

    std::vector<DVec3> answers(points.size());
    ProbeCounters counters;
    for (size_t i = 0; i < points.size(); ++i)
        answers[i] = probeIrradianceCounted(*solution, readout, points[i].p, points[i].n, counters);
    std::vector<double> per_eval, cpu_per_eval;
    for (int r = 0; r < runs; ++r) {
        const auto start = std::chrono::steady_clock::now();
        const double cpu_start = threadCpuSeconds();
        DVec3 check(0.0);
        for (const Point& pt : points) check += probeIrradiance(*solution, readout, pt.p, pt.n);
        const double cpu = threadCpuSeconds() - cpu_start;
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        per_eval.push_back(seconds / static_cast<double>(points.size()));
        cpu_per_eval.push_back(cpu / static_cast<double>(points.size()));
        if (r == 0) {
            DVec3 sum(0.0);
            for (const DVec3& a : answers) sum += a;
            if (check != sum) std::fprintf(stderr, "warning: answers differ between runs\n");
        }
    }
    std::vector<double> sorted = per_eval, cpu_sorted = cpu_per_eval;
    std::sort(sorted.begin(), sorted.end());
    std::sort(cpu_sorted.begin(), cpu_sorted.end());

    double digest_sum = 0.0, digest_max = 0.0;
    for (const DVec3& a : answers) {
        digest_sum += a.x + a.y + a.z;
        digest_max = std::max({digest_max, a.x, a.y, a.z});
    }
    const double n = static_cast<double>(points.size());
    std::printf("scene %s quality %s elements %zu roots %u points %zu seed %llu\n", path.c_str(), quality.c_str(),
                solution->elements.size(), solution->root_count, points.size(),
                static_cast<unsigned long long>(seed));
    std::printf("median_ms_per_eval %.4f  (runs:", 1e3 * sorted[sorted.size() / 2]);
    for (double s : per_eval) std::printf(" %.4f", 1e3 * s);
    std::printf(")\n");
    // CPU time of this thread: less disturbed than wall time when other work shares the cores.
    std::printf("median_cpu_ms_per_eval %.4f  (runs:", 1e3 * cpu_sorted[cpu_sorted.size() / 2]);
    for (double s : cpu_per_eval) std::printf(" %.4f", 1e3 * s);
    std::printf(")\n");
    std::printf("rays_per_eval %.1f form_factors_per_eval %.1f pieces_per_eval %.1f\n", counters.rays / n,
                counters.form_factors / n, counters.pieces / n);
    std::printf("digest sum %.17g max %.17g\n", digest_sum, digest_max);

    if (!dump.empty()) {
        FILE* f = std::fopen(dump.c_str(), "w");
        if (!f) {
            std::fprintf(stderr, "cannot write %s\n", dump.c_str());
            return 1;
        }
        for (const DVec3& a : answers) std::fprintf(f, "%.17g %.17g %.17g\n", a.x, a.y, a.z);
        std::fclose(f);
    }
    if (!compare.empty()) {
        FILE* f = std::fopen(compare.c_str(), "r");
        if (!f) {
            std::fprintf(stderr, "cannot read %s\n", compare.c_str());
            return 1;
        }
        std::vector<DVec3> other;
        DVec3 a;
        while (std::fscanf(f, "%lf %lf %lf", &a.x, &a.y, &a.z) == 3) other.push_back(a);
        std::fclose(f);
        if (other.size() != answers.size()) {
            std::fprintf(stderr, "%s holds %zu answers, not %zu\n", compare.c_str(), other.size(), answers.size());
            return 1;
        }
        const double zero = 1e-12 * digest_max;
        double worst = 0.0, mean = 0.0;
        size_t worst_index = 0, identical = 0;
        for (size_t i = 0; i < answers.size(); ++i) {
            const double change = relativeChange(answers[i], other[i], zero);
            mean += change / n;
            if (answers[i] == other[i]) ++identical;
            if (change > worst) worst = change, worst_index = i;
        }
        std::printf("compare: identical %zu/%zu, max_rel_change %.3g at point %zu (%g %g %g), mean_rel_change %.3g\n",
                    identical, answers.size(), worst, worst_index, points[worst_index].p.x, points[worst_index].p.y,
                    points[worst_index].p.z, mean);
    }
    return 0;
}
