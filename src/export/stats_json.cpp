#include "export/stats_json.h"

#include <sys/resource.h>

#include <algorithm>

#include "export/json_detail.h"
#include "export/output_transaction.h"

namespace radbake {

using json_detail::Json;

namespace {

// A phase that ran more than once (a stage called in rounds) is one key with its total.
Json mergedPhases(const std::vector<std::pair<std::string, double>>& phases) {
    std::vector<std::pair<std::string, double>> merged;
    for (const auto& [name, seconds] : phases) {
        auto it = std::find_if(merged.begin(), merged.end(), [&](const auto& p) { return p.first == name; });
        if (it == merged.end()) merged.emplace_back(name, seconds);
        else it->second += seconds;
    }
    Json out = Json::object();
    for (const auto& [name, seconds] : merged) out[name] = seconds;
    return out;
}

}  // namespace

double peakRssMegabytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
    return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

std::string formatStatsJson(const BakeReport& r) {
    const SolveStats& s = r.solve;
    Json out;
    out["generator"] = r.generator;
    out["scene"] = r.scene;
    out["elements"] = s.elements;
    out["links"] = s.links;
    out["element_links"] = s.element_links;
    out["cluster_links"] = s.cluster_links;
    out["clusters"] = s.clusters;
    out["roots"] = s.roots;
    out["contact_cuts"] = s.contact_cuts;
    out["leaves"] = s.leaves;
    out["partial_links"] = s.partial_links;
    out["limited_row_sums"] = s.limited_row_sums;
    out["candidate_links"] = s.candidate_links;
    out["shafts"] = s.shafts;
    out["occluded_links"] = s.occluded_links;
    out["bytes_per_element"] = s.bytes_per_element;
    out["bytes_per_link"] = s.bytes_per_link;
    out["rays"] = s.rays;
    out["iterations"] = s.iterations;
    out["converged"] = s.converged;
    out["visibility"] = toString(r.options.visibility);
    out["quality"] = toString(r.options.quality);
    out["error_threshold"] = r.options.error_threshold;
    out["local_error_threshold"] = r.options.local_error_threshold;
    out["min_area"] = r.options.min_element_area;
    out["tolerance"] = r.options.iteration_tolerance;
    out["max_iterations"] = r.options.max_iterations;
    out["meshes"] = r.meshes;
    out["vertices"] = r.vertices;
    out["hard_edge_vertices"] = r.hard_edge_vertices;
    out["hard_edge_copies"] = r.hard_edge_copies;
    out["triangles"] = r.triangles;
    // Only when there are some: a one-sided scene's stats.json keeps its bytes.
    if (r.two_sided_meshes > 0) out["two_sided_meshes"] = r.two_sided_meshes;
    if (r.two_sided_closed_meshes > 0) out["two_sided_closed_meshes"] = r.two_sided_closed_meshes;
    out["probes"] = r.probes;
    const LightmapReport& l = r.lightmaps;
    out["lightmaps"] = l.baked;
    if (l.baked) {
        out["texel_density"] = l.texels_per_unit;
        out["atlas_size"] = l.atlas_size;
        out["padding"] = l.padding;
        out["charts"] = l.charts;
        out["atlases"] = l.atlases;
        out["atlas_texels"] = l.atlas_texels;
        out["covered_texels"] = l.covered_texels;
        out["interpolated_texels"] = l.interpolated_texels;
        out["hidden_texels"] = l.hidden_texels;
        out["texel_tolerance"] = l.texel_tolerance;
        out["occupancy"] = l.occupancy;
        if (l.realtime_lights > 0) {
            out["realtime_lights"] = l.realtime_lights;
            out["shadowmask_lights_without_channel"] = l.shadowmask_lights_without_channel;
            out["shadowmask_texels_over_channels"] = l.shadowmask_texels_over_channels;
        }
    }
    // Only when the link read-out read them (not the exhaustive gather).
    const auto readout = [&](const char* name, const ReadoutReport& w) {
        if (w.points == 0) return;
        out[std::string(name) + "_reads"] = w.points;
        out[std::string(name) + "_rays"] = w.rays;
        out[std::string(name) + "_form_factors"] = w.form_factors;
    };
    readout("vertex", r.vertex_readout);
    readout("texel", r.texel_readout);
    if (r.refused_inputs > 0) out["refused_inputs"] = r.refused_inputs;  // only then, as two_sided_meshes
    out["warnings"] = r.warnings;
    return json_detail::dump(out, 2) + "\n";
}

bool writeStatsJson(const std::filesystem::path& path, const BakeReport& report, Diagnostics& diagnostics) {
    return writeFileBytes(path, formatStatsJson(report), diagnostics);
}

std::string formatTimingsJson(const BakeReport& r) {
    Json out;
    out["generator"] = r.generator;
    out["scene"] = r.scene;
    out["seconds"] = r.seconds;
    out["phases"] = mergedPhases(r.phases);
    out["peak_rss_mb"] = r.peak_rss_mb;
    out["memory_budget_mb"] = r.solve.memory_budget_mb;  // from the machine's memory unless --max-memory
    out["threads"] = r.threads;
    if (r.ranks > 1) {
        out["ranks"] = r.ranks;
        out["exchanged_mb"] = r.exchanged_mb;
        out["exchanges"] = r.exchanges;
        out["exchange_s"] = r.exchange_seconds;
        out["shared_s"] = r.shared_seconds;
    }
    return json_detail::dump(out, 2) + "\n";
}

bool writeTimingsJson(const std::filesystem::path& path, const BakeReport& report, Diagnostics& diagnostics) {
    return writeFileBytes(path, formatTimingsJson(report), diagnostics);
}

}  // namespace radbake
