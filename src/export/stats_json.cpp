#include "export/stats_json.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/json.h"
#include "export/output_transaction.h"

namespace radbake {

namespace {
std::string num(double value) {
    if (!std::isfinite(value)) return "null";  // JSON has no inf/nan
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g", value);
    return buffer;
}
}  // namespace

double peakRssMegabytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
    return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

std::string formatStatsJson(const BakeReport& r) {
    // A phase that ran more than once (a stage called in rounds) is one key with its total.
    std::vector<std::pair<std::string, double>> merged;
    for (const auto& [name, seconds] : r.phases) {
        auto it = std::find_if(merged.begin(), merged.end(), [&](const auto& p) { return p.first == name; });
        if (it == merged.end()) merged.emplace_back(name, seconds);
        else it->second += seconds;
    }
    std::string phases = "{";
    for (size_t i = 0; i < merged.size(); ++i)
        phases += (i ? ", " : "") + jsonString(merged[i].first) + ": " + num(merged[i].second);
    phases += "}";
    const SolveStats& s = r.solve;
    std::string out = "{\n";
    out += "  \"generator\": " + jsonString(r.generator) + ",\n";
    out += "  \"scene\": " + jsonString(r.scene) + ",\n";
    out += "  \"seconds\": " + num(r.seconds) + ",\n";
    out += "  \"phases\": " + phases + ",\n";
    out += "  \"elements\": " + std::to_string(s.elements) + ",\n";
    out += "  \"links\": " + std::to_string(s.links) + ",\n";
    out += "  \"shafts\": " + std::to_string(s.shafts) + ",\n";
    out += "  \"occluded_links\": " + std::to_string(s.occluded_links) + ",\n";
    out += "  \"rays\": " + std::to_string(s.rays) + ",\n";
    out += "  \"iterations\": " + std::to_string(s.iterations) + ",\n";
    out += std::string("  \"converged\": ") + (s.converged ? "true" : "false") + ",\n";
    out += "  \"peak_rss_mb\": " + num(r.peak_rss_mb) + ",\n";
    out += "  \"threads\": " + std::to_string(r.threads) + ",\n";
    out += std::string("  \"visibility\": \"") + toString(r.options.visibility) + "\",\n";
    out += std::string("  \"quality\": \"") + toString(r.options.quality) + "\",\n";
    out += "  \"error_threshold\": " + num(r.options.error_threshold) + ",\n";
    out += "  \"local_error_threshold\": " + num(r.options.local_error_threshold) + ",\n";
    out += "  \"min_area\": " + num(r.options.min_element_area) + ",\n";
    out += "  \"tolerance\": " + num(r.options.iteration_tolerance) + ",\n";
    out += "  \"max_iterations\": " + std::to_string(r.options.max_iterations) + ",\n";
    out += "  \"meshes\": " + std::to_string(r.meshes) + ",\n";
    out += "  \"vertices\": " + std::to_string(r.vertices) + ",\n";
    out += "  \"triangles\": " + std::to_string(r.triangles) + ",\n";
    out += "  \"probes\": " + std::to_string(r.probes) + ",\n";
    const LightmapReport& l = r.lightmaps;
    out += std::string("  \"lightmaps\": ") + (l.baked ? "true" : "false") + ",\n";
    if (l.baked) {
        out += "  \"texel_density\": " + num(l.texels_per_unit) + ",\n";
        out += "  \"atlas_size\": " + std::to_string(l.atlas_size) + ",\n";
        out += "  \"padding\": " + std::to_string(l.padding) + ",\n";
        out += "  \"charts\": " + std::to_string(l.charts) + ",\n";
        out += "  \"atlases\": " + std::to_string(l.atlases) + ",\n";
        out += "  \"atlas_texels\": " + std::to_string(l.atlas_texels) + ",\n";
        out += "  \"covered_texels\": " + std::to_string(l.covered_texels) + ",\n";
        out += "  \"interpolated_texels\": " + std::to_string(l.interpolated_texels) + ",\n";
        out += "  \"texel_tolerance\": " + num(l.texel_tolerance) + ",\n";
        out += "  \"occupancy\": " + num(l.occupancy) + ",\n";
    }
    out += "  \"warnings\": " + std::to_string(r.warnings) + "\n";
    return out + "}\n";
}

bool writeStatsJson(const std::filesystem::path& path, const BakeReport& report, Diagnostics& diagnostics) {
    return writeFileBytes(path, formatStatsJson(report), diagnostics);
}

}  // namespace radbake
