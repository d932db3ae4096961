// Ray caster throughput on one thread, per CPU second (see cpuSeconds): segmentBlocked() rays per second, visibleFraction()
// evaluations per second, and the candidate-list variant, on a generated scene of random
// boxes, or on a real scene file (segments and triangle pairs between random points of its
// triangles; also a robustness run of the Embree boundary). Prints the median (and min/max)
// over repeated runs; the machine is shared, so compare medians only.
//
//   bench_rays [--boxes N] [--scene FILE] [--runs R] [--seconds-per-run S]
#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "io/import.h"
#include "visibility/ray_caster.h"

using namespace radbake;

namespace {

// A closed axis-aligned box as one mesh of 12 triangles (6 polygons), inside [0, 10]^3.
Mesh randomBox(std::mt19937& random) {
    std::uniform_real_distribution<float> place(0.0f, 9.0f), size(0.1f, 1.0f);
    const Vec3 lo(place(random), place(random), place(random));
    const Vec3 hi = lo + Vec3(size(random), size(random), size(random));
    Mesh mesh;
    for (int k = 0; k < 8; ++k)
        mesh.positions.push_back(Vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z));
    const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (uint32_t f = 0; f < 6; ++f) {
        mesh.triangles.push_back(UVec3(faces[f][0], faces[f][1], faces[f][2]));
        mesh.triangles.push_back(UVec3(faces[f][0], faces[f][2], faces[f][3]));
        mesh.triangle_polygon.push_back(f);
        mesh.triangle_polygon.push_back(f);
    }
    mesh.polygon_count = 6;
    return mesh;
}

// A random point of a random usable triangle of the scene (uniform over triangles, then
// over the triangle), and that triangle's corners.
struct TrianglePick {
    std::vector<DVec3> corners;
    DVec3 point;
};
TrianglePick randomTrianglePoint(const Scene& scene, std::mt19937& random) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (;;) {
        const Mesh& mesh = scene.meshes[random() % scene.meshes.size()];
        if (mesh.triangles.empty()) continue;
        const UVec3 t = mesh.triangles[random() % mesh.triangles.size()];
        if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size()) continue;
        TrianglePick pick;
        pick.corners = {DVec3(mesh.positions[t.x]), DVec3(mesh.positions[t.y]), DVec3(mesh.positions[t.z])};
        double u = unit(random), v = unit(random);
        if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
        pick.point = pick.corners[0] + u * (pick.corners[1] - pick.corners[0]) + v * (pick.corners[2] - pick.corners[0]);
        return pick;
    }
}

// A random quad (a parallelogram) of side ~0.3 to 1.5 somewhere in the scene's cube.
std::vector<DVec3> randomQuad(std::mt19937& random) {
    std::uniform_real_distribution<double> place(0.0, 10.0), side(-1.0, 1.0);
    const DVec3 origin(place(random), place(random), place(random));
    const DVec3 a(side(random), side(random), side(random)), b(side(random), side(random), side(random));
    return {origin, origin + a, origin + a + b, origin + b};
}

// CPU seconds of this thread (queries) or process (build): on a shared, loaded machine these
// measure the work, where wall time would mostly measure the other processes.
double cpuSeconds(clockid_t clock) {
    timespec t{};
    clock_gettime(clock, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Runs `batch` (which performs `per_batch` operations) until `seconds` of this thread's CPU
// time have elapsed and returns operations per CPU second.
double rate(double seconds, size_t per_batch, const std::function<void()>& batch) {
    size_t operations = 0;
    const double start = cpuSeconds(CLOCK_THREAD_CPUTIME_ID);
    double elapsed = 0.0;
    do {
        batch();
        operations += per_batch;
        elapsed = cpuSeconds(CLOCK_THREAD_CPUTIME_ID) - start;
    } while (elapsed < seconds);
    return static_cast<double>(operations) / elapsed;
}

struct Summary {
    double median, low, high;
};

Summary summarize(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return {values[values.size() / 2], values.front(), values.back()};
}

void print(const char* what, const char* unit, const std::vector<double>& values) {
    const Summary s = summarize(values);
    std::printf("%-46s median %12.0f %s per CPU s  (min %.0f, max %.0f, %zu runs)\n", what, s.median, unit, s.low, s.high,
                values.size());
}

}  // namespace

int main(int argc, char** argv) {
    int boxes = 300, runs = 5;
    double seconds = 0.5;
    std::string scene_path;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--boxes")) boxes = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--scene")) scene_path = argv[i + 1];
        else if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--seconds-per-run")) seconds = std::atof(argv[i + 1]);
        else {
            std::fprintf(stderr, "usage: bench_rays [--boxes N] [--scene FILE] [--runs R] [--seconds-per-run S]\n");
            return 2;
        }
    }
    std::mt19937 random(42);
    Diagnostics diagnostics;
    Scene scene;
    if (!scene_path.empty()) {
        std::optional<Scene> imported = importScene(scene_path, {}, diagnostics);
        if (!imported) {
            for (const Diagnostic& d : diagnostics.all())
                if (d.severity == Severity::Error) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
            return 1;
        }
        scene = std::move(*imported);
        if (summarize(scene).triangles == 0) {
            std::fprintf(stderr, "%s: no triangles\n", scene_path.c_str());
            return 1;
        }
    } else {
        scene.materials.push_back({});
        for (int b = 0; b < boxes; ++b) scene.meshes.push_back(randomBox(random));
    }

    std::vector<double> build_ms;
    std::unique_ptr<RayCaster> caster;
    for (int r = 0; r < runs; ++r) {
        const double start = cpuSeconds(CLOCK_PROCESS_CPUTIME_ID);
        caster = RayCaster::build(scene, diagnostics, 1);
        build_ms.push_back(1e3 * (cpuSeconds(CLOCK_PROCESS_CPUTIME_ID) - start));
        if (!caster) {
            for (const Diagnostic& d : diagnostics.all()) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
            return 1;
        }
    }
    if (scene_path.empty())
        std::printf("scene: %d random boxes, %zu triangles, extent %.3f, epsilon %.3g\n", boxes,
                    caster->triangleCount(), caster->sceneExtent(), caster->epsilon());
    else
        std::printf("scene: %s, %zu triangles, extent %.6g, epsilon %.3g\n", scene_path.c_str(),
                    caster->triangleCount(), caster->sceneExtent(), caster->epsilon());
    std::printf("%-46s median %12.2f ms\n", "build (1 thread), CPU", summarize(build_ms).median);

    // Fixed workloads, generated once: inside the boxes' cube, or between points of the
    // scene's triangles (triangle pairs as the polygons).
    std::uniform_real_distribution<double> place(0.0, 10.0);
    std::vector<std::pair<DVec3, DVec3>> segments(4096);
    std::vector<std::pair<std::vector<DVec3>, std::vector<DVec3>>> pairs(256);
    if (scene_path.empty()) {
        for (auto& s : segments)
            s = {DVec3(place(random), place(random), place(random)), DVec3(place(random), place(random), place(random))};
        for (auto& p : pairs) p = {randomQuad(random), randomQuad(random)};
    } else {
        for (auto& s : segments) s = {randomTrianglePoint(scene, random).point, randomTrianglePoint(scene, random).point};
        for (auto& p : pairs) p = {randomTrianglePoint(scene, random).corners, randomTrianglePoint(scene, random).corners};
    }
    // Candidate lists: up to 12 triangles of 8 random meshes (a typical shaft's potential occluders).
    std::vector<TriangleRef> candidates;
    for (int k = 0; k < 8; ++k) {
        const uint32_t mesh = random() % scene.meshes.size();
        const uint32_t count = static_cast<uint32_t>(std::min<size_t>(12, scene.meshes[mesh].triangles.size()));
        for (uint32_t t = 0; t < count; ++t) candidates.push_back({mesh, t});
    }

    size_t sink = 0;  // keeps the work observable
    std::vector<double> ray_rates, fraction4, fraction8, among4;
    size_t blocked_total = 0;
    for (const auto& s : segments) blocked_total += caster->segmentBlocked(s.first, s.second);
    for (int r = 0; r < runs; ++r) {
        ray_rates.push_back(rate(seconds, segments.size(), [&] {
            for (const auto& s : segments) sink += caster->segmentBlocked(s.first, s.second);
        }));
        fraction4.push_back(rate(seconds, pairs.size(), [&] {
            for (const auto& p : pairs) sink += caster->visibleFraction(p.first, p.second, 4) > 0.5;
        }));
        fraction8.push_back(rate(seconds, pairs.size(), [&] {
            for (const auto& p : pairs) sink += caster->visibleFraction(p.first, p.second, 8) > 0.5;
        }));
        among4.push_back(rate(seconds, pairs.size(), [&] {
            for (const auto& p : pairs) sink += caster->visibleFractionAmong(p.first, p.second, 4, candidates) > 0.5;
        }));
    }
    std::printf("random segments blocked: %.1f %%\n", 100.0 * blocked_total / segments.size());
    print("segmentBlocked", "rays/s", ray_rates);
    print("visibleFraction n=4 (16 rays)", "evals/s", fraction4);
    print("visibleFraction n=8 (64 rays)", "evals/s", fraction8);
    std::printf("candidate triangles for the Among variant: %zu\n", candidates.size());
    print("visibleFractionAmong n=4", "evals/s", among4);
    if (diagnostics.errorCount() > 0 || caster->reportLateErrors(diagnostics) > 0) {
        std::fprintf(stderr, "Embree reported errors:\n");
        for (const Diagnostic& d : diagnostics.all()) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
        return 1;
    }
    std::printf("(checksum %zu)\n", sink);
    return 0;
}
