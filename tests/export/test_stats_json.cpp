// stats.json: every field the issue asks for, parsed back; phases run in rounds are summed.
#include <doctest/doctest.h>

#include "export/stats_json.h"
#include "mini_json.h"

using namespace radbake;

TEST_CASE("stats.json holds every figure and merges repeated phases") {
    BakeReport report;
    report.generator = "radbake test";
    report.scene = "scenes/a \"quoted\" name.wrl";
    report.seconds = 1.5;
    report.phases = {{"import", 0.25}, {"links", 0.5}, {"solve", 0.125}, {"links", 0.25}, {"write", 0.0625}};
    report.solve.elements = 11;
    report.solve.links = 22;
    report.solve.shafts = 33;
    report.solve.occluded_links = 4;
    report.solve.rays = 55;
    report.solve.iterations = 6;
    report.solve.converged = true;
    report.options = SolverOptions::forQuality(Quality::High);
    report.options.visibility = VisibilityMode::Obb;
    report.threads = 2;
    report.peak_rss_mb = 12.5;
    report.vertices = 7;
    const minijson::Value json = minijson::parse(formatStatsJson(report));

    CHECK(json["scene"].str() == report.scene);
    CHECK(json["seconds"].num() == 1.5);
    CHECK(json["phases"].size() == 4);
    CHECK(json["phases"]["links"].num() == 0.75);
    CHECK(json["phases"]["write"].num() == 0.0625);
    CHECK(json["elements"].num() == 11);
    CHECK(json["links"].num() == 22);
    CHECK(json["shafts"].num() == 33);
    CHECK(json["occluded_links"].num() == 4);
    CHECK(json["rays"].num() == 55);
    CHECK(json["iterations"].num() == 6);
    CHECK(json["converged"].boolean);
    CHECK(json["peak_rss_mb"].num() == 12.5);
    CHECK(json["threads"].num() == 2);
    CHECK(json["visibility"].str() == "obb");
    CHECK(json["quality"].str() == "high");
    CHECK(json["error_threshold"].num() == report.options.error_threshold);
    CHECK(json["local_error_threshold"].num() == report.options.local_error_threshold);
    CHECK(json["min_area"].num() == report.options.min_element_area);
    CHECK(json["tolerance"].num() == report.options.iteration_tolerance);
    CHECK(json["max_iterations"].num() == report.options.max_iterations);
    CHECK(json["vertices"].num() == 7);
}

TEST_CASE("stats.json reports the lightmap stage only when it ran") {
    BakeReport report;
    CHECK_FALSE(minijson::parse(formatStatsJson(report))["lightmaps"].boolean);
    CHECK_FALSE(minijson::parse(formatStatsJson(report)).has("occupancy"));
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
    const minijson::Value json = minijson::parse(formatStatsJson(report));
    CHECK(json["lightmaps"].boolean);
    CHECK(json["texel_density"].num() == 16.0);
    CHECK(json["atlas_size"].num() == 1024);
    CHECK(json["padding"].num() == 2);
    CHECK(json["charts"].num() == 17);
    CHECK(json["atlases"].num() == 2);
    CHECK(json["atlas_texels"].num() == 5000);
    CHECK(json["covered_texels"].num() == 1234);
    CHECK(json["occupancy"].num() == 0.25);
    CHECK(json["interpolated_texels"].num() == 1000);
    CHECK(json["texel_tolerance"].num() == 0.02);
}
