// Reads a VRML file several times and prints the read speed (median MB/s), the time
// validateScene takes on what was read (median seconds, and its ratio to the read time) and
// peak memory. Times are wall clock and, steadier on a shared machine, this process's CPU time.
// usage: bench_vrml_read FILE [RUNS=3]     (generate a big file with tools/gen_vrml_bench.py)
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "io/vrml/vrml_reader.h"
#include "scene/validate.h"

namespace {

double cpuSeconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE [RUNS]\n", argv[0]);
        return 2;
    }
    const std::string path = argv[1];
    const int runs = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
    const double megabytes = double(std::filesystem::file_size(path)) / 1e6;
    std::vector<double> rates, read_seconds, validate_seconds, read_cpu, validate_cpu;
    size_t warnings = 0;
    size_t triangles = 0, polygons = 0;
    for (int run = 0; run < runs; ++run) {
        radbake::Scene scene;
        radbake::Diagnostics diagnostics;
        const auto start = std::chrono::steady_clock::now();
        const double cpu_start = cpuSeconds();
        const bool ok = radbake::readVrml(path, {}, scene, diagnostics);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        read_cpu.push_back(cpuSeconds() - cpu_start);
        if (!ok) {
            for (const auto& d : diagnostics.all()) std::fprintf(stderr, "%s\n", radbake::formatDiagnostic(d).c_str());
            return 1;
        }
        const auto validate_start = std::chrono::steady_clock::now();
        const double validate_cpu_start = cpuSeconds();
        radbake::Diagnostics validate_diagnostics;
        radbake::validateScene(scene, validate_diagnostics);
        const double validate = std::chrono::duration<double>(std::chrono::steady_clock::now() - validate_start).count();
        validate_cpu.push_back(cpuSeconds() - validate_cpu_start);
        warnings = validate_diagnostics.warningCount();
        read_seconds.push_back(seconds);
        validate_seconds.push_back(validate);
        triangles = polygons = 0;
        for (const auto& mesh : scene.meshes) {
            triangles += mesh.triangles.size();
            polygons += mesh.polygon_count;
        }
        rates.push_back(megabytes / seconds);
        std::printf("run %d: read %.2f s, %.1f MB/s; validate %.3f s\n", run + 1, seconds, megabytes / seconds,
                    validate);
    }
    auto median = [](std::vector<double> values) {
        std::sort(values.begin(), values.end());
        return values[values.size() / 2];
    };
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const double peak_mb = double(usage.ru_maxrss) / 1024.0;
    std::printf("file %.1f MB, %zu polygons, %zu triangles\n", megabytes, polygons, triangles);
    std::printf("median %.1f MB/s over %d runs; peak RSS %.0f MB = %.2f x file size\n", median(rates), runs,
                peak_mb, peak_mb / megabytes);
    std::printf("validate: median %.3f s over %d runs = %.2f x the median read time (%zu warnings)\n",
                median(validate_seconds), runs, median(validate_seconds) / median(read_seconds), warnings);
    std::printf("CPU time: read median %.3f s, validate median %.3f s = %.2f x\n", median(read_cpu),
                median(validate_cpu), median(validate_cpu) / median(read_cpu));
    return 0;
}
