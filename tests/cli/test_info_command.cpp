// `radbake info --json`: one JSON object a script can read, counting what was read and naming
// every input file.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <string>

#include "cli_support.h"

using namespace clitest;

TEST_CASE("info --json counts the scene and names every file read, the Inline'd one too") {
    const TempDir tmp;
    writeText(tmp.path / "part.wrl", "#VRML V2.0 utf8\nShape { geometry IndexedFaceSet {\n"
                                     "  coord Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0] } coordIndex [0 1 2 3 -1] } }\n");
    writeText(tmp.path / "top \"quoted\".wrl",
              "#VRML V2.0 utf8\nInline { url \"part.wrl\" }\nTransform { translation 0 0 2 children Inline { url "
              "\"part.wrl\" } }\nViewpoint { position 0 0 5 }\n");
    const RunResult run = runRadbake("info " + quote(tmp.path / "top \"quoted\".wrl") + " --json");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const nlohmann::json info = nlohmann::json::parse(run.output.substr(run.output.find('{')));
    CHECK(info["name"] == "top \"quoted\"");
    CHECK(info["triangles"] == 4);
    CHECK(info["polygons"] == 2);
    CHECK(info["cameras"] == 1);
    CHECK(info["bounds"]["max"][2].get<double>() == doctest::Approx(2.0));
    REQUIRE(info["input_files"].size() == 2);  // the Inline'd file once, though used twice
    CHECK(info["input_files"][0].get<std::string>().ends_with("top \"quoted\".wrl"));
    CHECK(info["input_files"][1].get<std::string>().ends_with("part.wrl"));
}

TEST_CASE("info counts the vertices split at hard edges") {
    const TempDir tmp;
    writeText(tmp.path / "box.wrl", "#VRML V2.0 utf8\nShape { geometry Box { } }\nShape { geometry Sphere { } }\n");
    const RunResult run = runRadbake("info " + quote(tmp.path / "box.wrl") + " --json");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const nlohmann::json info = nlohmann::json::parse(run.output.substr(run.output.find('{')));
    CHECK(info["vertices"] == 24 + 482);  // the Box's 8 corners split three ways, the Sphere smooth
    CHECK(info["hard_edge_vertices"] == 8);
    CHECK(info["hard_edge_copies"] == 16);
    const RunResult text = runRadbake("info " + quote(tmp.path / "box.wrl"));
    CHECK(text.output.find("vertices   506 (8 split at hard edges, 16 copies)") != std::string::npos);
}
