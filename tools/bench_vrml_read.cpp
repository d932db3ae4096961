// Reads a VRML file several times and prints the read speed (median MB/s) and peak memory.
// usage: bench_vrml_read FILE [RUNS=3]     (generate a big file with tools/gen_vrml_bench.py)
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/vrml/vrml_reader.h"

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE [RUNS]\n", argv[0]);
        return 2;
    }
    const std::string path = argv[1];
    const int runs = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
    const double megabytes = double(std::filesystem::file_size(path)) / 1e6;
    std::vector<double> rates;
    size_t triangles = 0, polygons = 0;
    for (int run = 0; run < runs; ++run) {
        radbake::Scene scene;
        radbake::Diagnostics diagnostics;
        const auto start = std::chrono::steady_clock::now();
        const bool ok = radbake::readVrml(path, {}, scene, diagnostics);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!ok) {
            for (const auto& d : diagnostics.all()) std::fprintf(stderr, "%s\n", radbake::formatDiagnostic(d).c_str());
            return 1;
        }
        triangles = polygons = 0;
        for (const auto& mesh : scene.meshes) {
            triangles += mesh.triangles.size();
            polygons += mesh.polygon_count;
        }
        rates.push_back(megabytes / seconds);
        std::printf("run %d: %.2f s, %.1f MB/s\n", run + 1, seconds, megabytes / seconds);
    }
    std::sort(rates.begin(), rates.end());
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const double peak_mb = double(usage.ru_maxrss) / 1024.0;
    std::printf("file %.1f MB, %zu polygons, %zu triangles\n", megabytes, polygons, triangles);
    std::printf("median %.1f MB/s over %d runs; peak RSS %.0f MB = %.2f x file size\n", rates[rates.size() / 2], runs,
                peak_mb, peak_mb / megabytes);
    return 0;
}
