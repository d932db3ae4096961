// reference_mc: brute-force Monte Carlo probe irradiance, independent of the hierarchy.
//
//   reference_mc SCENE PROBES [--samples N] [--seed S] [--threads T] [--unit-scale U]
//                [--emission-scale E] [--no-nee] [-o OUT.csv]
//                [--sky MODEL] [--sky-radiance L] [--up AXIS] [--sun AZ,EL] [--sun-irradiance E]
//                [--sun-diameter D]
//
// The daylight options mean what `radbake bake`'s do (scene/daylight.h).
//
// --no-nee: pure path tracing (emission counted only where paths hit it; punctual lights,
// which no path can hit, are still sampled at every vertex) instead of the default next-event
// estimation; both are unbiased, the default is far less noisy.
//
// Prints (or writes) a CSV like `radbake bake --probes` writes (x,y,z,nx,ny,nz,r,g,b: H in
// W/m^2) with three more columns, se_r,se_g,se_b: the standard error of each estimate. The
// estimator and its assumptions (area emitters and punctual lights, material reflectance only,
// one- and two-sided surfaces) are described in tools/reference_mc.h.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include "export/probes.h"
#include "io/import.h"
#include "reference_mc.h"

namespace {

int usage() {
    std::fprintf(stderr,
                 "usage: reference_mc SCENE PROBES [--samples N=4096] [--seed S=1] [--threads T=0]\n"
                 "                    [--unit-scale U=1] [--emission-scale E=1] [--no-nee] [-o OUT.csv]\n"
                 "                    [--sky none|uniform|overcast] [--sky-radiance L=1] [--up AXIS=+y]\n"
                 "                    [--sun AZ,EL] [--sun-irradiance E=25] [--sun-diameter D=0.53]\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace radbake;
    std::string scene_path, probes_path, out_path;
    reference::McOptions options;
    ImportOptions import;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        const char* v = nullptr;
        if (arg == "--samples" && (v = value())) options.samples = std::atoi(v);
        else if (arg == "--seed" && (v = value())) options.seed = std::strtoull(v, nullptr, 10);
        else if (arg == "--threads" && (v = value())) options.threads = std::atoi(v);
        else if (arg == "--no-nee") options.next_event = false;
        else if (arg == "--unit-scale" && (v = value())) import.unit_scale = std::strtof(v, nullptr);
        else if (arg == "--emission-scale" && (v = value())) import.emission_scale = std::strtof(v, nullptr);
        else if ((arg == "-o" || arg == "--output") && (v = value())) out_path = v;
        else if (arg == "--sky" && (v = value())) {
            const std::optional<SkyModel> sky = parseSkyModel(v);
            if (!sky) return usage();
            import.daylight.sky = *sky;
            if (*sky == SkyModel::Map) import.daylight.sky_map = v;
        } else if (arg == "--up" && (v = value())) {
            const std::optional<Vec3> up = parseUpAxis(v);
            if (!up) return usage();
            import.daylight.up = *up;
        } else if (arg == "--sun" && (v = value())) {
            import.daylight.sun = parseSunPosition(v);
            if (!import.daylight.sun) return usage();
        } else if (arg == "--sky-radiance" && (v = value())) import.daylight.sky_radiance = std::strtod(v, nullptr);
        else if (arg == "--sun-irradiance" && (v = value())) import.daylight.sun_irradiance = std::strtod(v, nullptr);
        else if (arg == "--sun-diameter" && (v = value())) import.daylight.sun_diameter_degrees = std::strtod(v, nullptr);
        else if (!arg.empty() && arg[0] != '-' && scene_path.empty()) scene_path = arg;
        else if (!arg.empty() && arg[0] != '-' && probes_path.empty()) probes_path = arg;
        else return usage();
    }
    if (scene_path.empty() || probes_path.empty() || options.samples < 1) return usage();

    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic& d) { std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str()); };
    const std::optional<Scene> scene = importScene(scene_path, import, diagnostics);
    if (!scene) return 1;
    const std::optional<std::vector<Probe>> probes = readProbes(probes_path, diagnostics);
    if (!probes) return 1;
    const auto start = std::chrono::steady_clock::now();
    const reference::McBvh bvh(*scene);
    std::vector<reference::McProbe> points;
    for (const Probe& probe : *probes) points.push_back({probe.position * double(import.unit_scale), probe.normal});
    const std::vector<reference::McProbeResult> results = reference::estimateProbes(bvh, points, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::ostringstream csv;
    csv << "x,y,z,nx,ny,nz,r,g,b,se_r,se_g,se_b\n";
    char line[512];
    uint64_t rays = 0;
    for (size_t i = 0; i < results.size(); ++i) {
        const Probe& p = (*probes)[i];
        const reference::McProbeResult& r = results[i];
        rays += r.rays;
        std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.3g,%.3g,%.3g\n",
                      p.position.x, p.position.y, p.position.z, p.normal.x, p.normal.y, p.normal.z,
                      r.irradiance.x, r.irradiance.y, r.irradiance.z, r.standard_error.x, r.standard_error.y,
                      r.standard_error.z);
        csv << line;
    }
    if (out_path.empty()) {
        std::cout << csv.str();
    } else {
        std::ofstream out(out_path + ".tmp", std::ios::binary);
        out << csv.str();
        out.close();
        if (!out || std::rename((out_path + ".tmp").c_str(), out_path.c_str()) != 0) {
            std::fprintf(stderr, "reference_mc: error: cannot write %s\n", out_path.c_str());
            return 1;
        }
    }
    std::fprintf(stderr,
                 "reference_mc: %zu probes, %d paths each (%s), %zu triangles, %zu punctual lights, %llu rays, "
                 "%.3f s\n",
                 results.size(), options.samples, options.next_event ? "next-event estimation" : "pure path tracing",
                 bvh.triangles().size(), bvh.lights().size(), static_cast<unsigned long long>(rays), seconds);
    return 0;
}
