// Probe files: accepted syntax, located errors for every kind of bad line, and the CSV.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "export/probes.h"

using namespace radbake;

namespace {
std::vector<std::string> messages(const Diagnostics& diagnostics) {
    std::vector<std::string> out;
    for (const Diagnostic& d : diagnostics.all()) out.push_back(formatDiagnostic(d));
    return out;
}
}  // namespace

TEST_CASE("probe files: spaces, commas, tabs, comments, blank lines and CRLF") {
    const std::string text =
        "# probes for the test room\n"
        "\n"
        "1 2 3 0 0 1\n"
        "  -1.5, 0.25,1e-3 ,0,2,0   # a comment after the numbers\r\n"
        "\t+4\t5\t6\t3\t0\t4\n"
        "   \n"
        "0,0,0,0,0,-7";  // no final newline
    Diagnostics diagnostics;
    const std::vector<Probe> probes = parseProbes(text, "p.txt", diagnostics);
    CHECK(diagnostics.all().empty());
    REQUIRE(probes.size() == 4);
    CHECK(probes[0].position == DVec3(1, 2, 3));
    CHECK(probes[0].normal == DVec3(0, 0, 1));
    CHECK(probes[0].location.line == 3);
    CHECK(probes[1].position == DVec3(-1.5, 0.25, 1e-3));
    CHECK(probes[1].normal == DVec3(0, 1, 0));  // normalised
    CHECK(probes[1].location.line == 4);
    CHECK(probes[1].location.column == 3);
    CHECK(probes[2].position == DVec3(4, 5, 6));
    CHECK(probes[2].normal.x == doctest::Approx(0.6).epsilon(1e-15));
    CHECK(probes[2].normal.z == doctest::Approx(0.8).epsilon(1e-15));
    CHECK(probes[3].normal == DVec3(0, 0, -1));
    CHECK(probes[3].location.line == 7);
}

TEST_CASE("probe files: each bad line is a located error and the good lines still parse") {
    const std::string text =
        "1 2 3 0 0 1\n"          // 1: good
        "1 2 3 0 0\n"            // 2: five fields
        "1 2 x 0 0 1\n"          // 3: not a number at column 5
        "1 2 3 0 0 0\n"          // 4: zero normal, reported at nx (column 7)
        "1,,2,3,0,0\n"           // 5: empty field at the second comma (column 3)
        "1 2 3 0 0 1 9\n"        // 6: seventh field at column 13
        "1 2 3 0 1 0,\n"         // 7: trailing comma at column 12
        "1 2 nan 0 1 0\n"        // 8: not finite
        "1 2 3 0 1e999 0\n"      // 9: overflows to infinity
        "4 5 6 1 0 0\n";         // 10: good
    Diagnostics diagnostics;
    const std::vector<Probe> probes = parseProbes(text, "probes.txt", diagnostics);
    REQUIRE(probes.size() == 2);
    CHECK(probes[1].position == DVec3(4, 5, 6));
    const std::vector<std::string> expected = {
        "probes.txt:2:1: error: expected 6 numbers (x y z nx ny nz), found 5 fields",
        "probes.txt:3:5: error: not a finite number: 'x'",
        "probes.txt:4:7: error: probe normal is zero",
        "probes.txt:5:3: error: empty field: expected a number before this comma",
        "probes.txt:6:13: error: expected 6 numbers (x y z nx ny nz), found 7 fields",
        "probes.txt:7:12: error: trailing comma: expected a number after it",
        "probes.txt:8:5: error: not a finite number: 'nan'",
        "probes.txt:9:9: error: not a finite number: '1e999'",
    };
    CHECK(messages(diagnostics) == expected);
}

TEST_CASE("probe file that cannot be read") {
    Diagnostics diagnostics;
    CHECK_FALSE(readProbes("/nonexistent/probes.txt", diagnostics).has_value());
    CHECK(messages(diagnostics) == std::vector<std::string>{"/nonexistent/probes.txt: error: cannot open probe file: no such file"});
}

TEST_CASE("probes.csv: header, input order, round-tripping digits") {
    Diagnostics diagnostics;
    const std::vector<Probe> probes = parseProbes("0.1 2 3 0 0 5\n-4 5 6 0 -1 0\n", "p", diagnostics);
    const std::vector<DVec3> irradiance = {DVec3(1.0 / 3.0, 2.5, 0.0), DVec3(1e-20, 123456789.0, 7.0)};
    const std::string csv = formatProbesCsv(probes, irradiance);
    CHECK(csv ==
          "x,y,z,nx,ny,nz,r,g,b\n"
          "0.1,2,3,0,0,1,0.333333333,2.5,0\n"
          "-4,5,6,0,-1,0,1e-20,123456789,7\n");
}
