// stats.json and timings.json: every field parsed back, each in its own file; phases run in
// rounds are summed.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "export/stats_json.h"

using namespace radbake;

namespace {

BakeReport fullReport() {
    BakeReport report;
    report.generator = "radbake test";
    report.scene = "scenes/a \"quoted\" name.wrl";
    report.seconds = 1.5;
    report.phases = {{"import", 0.25}, {"links", 0.5}, {"solve", 0.125}, {"links", 0.25}, {"elements", 0.5}, {"write", 0.0625}};
    report.solve.elements = 11;
    report.solve.links = 22;
    report.solve.shafts = 33;
    report.solve.occluded_links = 4;
    report.solve.rays = 55;
    report.solve.iterations = 6;
    report.solve.converged = true;
    report.options = SolverOptions::forQuality(Quality::High);
    report.options.visibility = LinkVisibility::Obb;
    report.threads = 2;
    report.peak_rss_mb = 12.5;
    report.vertices = 7;
    return report;
}

}  // namespace

TEST_CASE("stats.json holds every count and knob, and nothing that differs from run to run") {
    const BakeReport report = fullReport();
    const nlohmann::json json = nlohmann::json::parse(formatStatsJson(report));

    CHECK(json.at("generator").get<std::string>() == "radbake test");
    CHECK(json.at("scene").get<std::string>() == report.scene);
    CHECK(json.at("elements").get<double>() == 11);
    CHECK(json.at("links").get<double>() == 22);
    CHECK(json.at("shafts").get<double>() == 33);
    CHECK(json.at("occluded_links").get<double>() == 4);
    CHECK(json.at("rays").get<double>() == 55);
    CHECK(json.at("iterations").get<double>() == 6);
    CHECK(json.at("converged").get<bool>());
    CHECK(json.at("visibility").get<std::string>() == "obb");
    CHECK(json.at("quality").get<std::string>() == "high");
    CHECK(json.at("error_threshold").get<double>() == report.options.error_threshold);
    CHECK(json.at("local_error_threshold").get<double>() == report.options.local_error_threshold);
    CHECK(json.at("min_area").get<double>() == report.options.min_element_area);
    CHECK(json.at("tolerance").get<double>() == report.options.iteration_tolerance);
    CHECK(json.at("max_iterations").get<double>() == report.options.max_iterations);
    CHECK(json.at("vertices").get<double>() == 7);
    for (const char* key : {"seconds", "phases", "peak_rss_mb", "threads"}) CHECK_MESSAGE(!json.contains(key), key);

    // The run's figures do not reach it: another run of the same bake gives the same bytes.
    BakeReport other = report;
    other.seconds = 99.0;
    other.phases = {{"import", 3.0}};
    other.threads = 7;
    other.peak_rss_mb = 1000.0;
    CHECK(formatStatsJson(other) == formatStatsJson(report));
}

TEST_CASE("timings.json holds the wall time, phases, peak memory and threads, and merges repeated phases") {
    const BakeReport report = fullReport();
    const nlohmann::json json = nlohmann::json::parse(formatTimingsJson(report));
    CHECK(json.at("generator").get<std::string>() == "radbake test");
    CHECK(json.at("scene").get<std::string>() == report.scene);
    CHECK(json.at("seconds").get<double>() == 1.5);
    REQUIRE(json.at("phases").size() == 5);
    CHECK(json.at("phases").at("links").get<double>() == 0.75);
    CHECK(json.at("phases").at("write").get<double>() == 0.0625);
    // In the order the phases first ran (not sorted).
    const nlohmann::ordered_json in_order = nlohmann::ordered_json::parse(formatTimingsJson(report));
    std::vector<std::string> order;
    for (const auto& phase : in_order.at("phases").items()) order.push_back(phase.key());
    CHECK(order == std::vector<std::string>{"import", "links", "solve", "elements", "write"});
    CHECK(json.at("peak_rss_mb").get<double>() == 12.5);
    CHECK(json.at("threads").get<double>() == 2);
    CHECK(json.at("memory_budget_mb").get<double>() == report.solve.memory_budget_mb);
    CHECK(json.size() == 7);
}

TEST_CASE("stats.json reports the lightmap stage only when it ran") {
    BakeReport report;
    CHECK_FALSE(nlohmann::json::parse(formatStatsJson(report)).at("lightmaps").get<bool>());
    CHECK_FALSE(nlohmann::json::parse(formatStatsJson(report)).contains("occupancy"));
    report.lightmaps.baked = true;
    report.lightmaps.texels_per_unit = 16.0;
    report.lightmaps.atlas_size = 1024;
    report.lightmaps.padding = 2;
    report.lightmaps.charts = 17;
    report.lightmaps.atlases = 2;
    report.lightmaps.atlas_texels = 5000;
    report.lightmaps.covered_texels = 1234;
    report.lightmaps.occupancy = 0.25;
    report.lightmaps.interpolated_texels = 1000;
    report.lightmaps.texel_tolerance = 0.02;
    const nlohmann::json json = nlohmann::json::parse(formatStatsJson(report));
    CHECK(json.at("lightmaps").get<bool>());
    CHECK(json.at("texel_density").get<double>() == 16.0);
    CHECK(json.at("atlas_size").get<double>() == 1024);
    CHECK(json.at("padding").get<double>() == 2);
    CHECK(json.at("charts").get<double>() == 17);
    CHECK(json.at("atlases").get<double>() == 2);
    CHECK(json.at("atlas_texels").get<double>() == 5000);
    CHECK(json.at("covered_texels").get<double>() == 1234);
    CHECK(json.at("occupancy").get<double>() == 0.25);
    CHECK(json.at("interpolated_texels").get<double>() == 1000);
    CHECK(json.at("texel_tolerance").get<double>() == 0.02);
}
