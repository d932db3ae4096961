// `radbake bake` end to end on tiny literal scenes written to a temporary directory.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.h"

using namespace clitest;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Irradiance below the corner of an X by Y rectangle at height h emitting radiance L, on a
// receiver facing it (the differential-area-to-parallel-rectangle form factor times pi L).
double cornerIrradiance(double x, double y, double h, double radiance) {
    const double a = x / h, b = y / h;
    const double sa = std::sqrt(1 + a * a), sb = std::sqrt(1 + b * b);
    return radiance * 0.5 * (a / sa * std::atan(b / sa) + b / sb * std::atan(a / sb));
}

// A unit square lamp (L_e = 2, black) facing down at height 1 over a black 4x4 floor:
// no interreflection, so the floor's irradiance is the closed form above. `units` is the
// number of file units per metre (100: the same scene written in centimetres).
void writeLampScene(const fs::path& dir, double units = 1.0) {
    writeText(dir / "lamp.mtl",
              "newmtl light\nKd 0 0 0\nKe 2 2 2\n"
              "newmtl floor\nKd 0 0 0\n");
    std::ostringstream obj, probes;
    obj << "mtllib lamp.mtl\n";
    const double corners[8][3] = {{-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5},
                                  {-2, 0, -2},     {-2, 0, 2},     {2, 0, 2},     {2, 0, -2}};
    for (const auto& c : corners) obj << "v " << c[0] * units << " " << c[1] * units << " " << c[2] * units << "\n";
    obj << "o lamp\nusemtl light\nf 1 2 3 4\n"
           "o floor\nusemtl floor\nf 5 6 7 8\n";
    writeText(dir / "lamp.obj", obj.str());
    probes << "# centre, and below the lamp's corner\n"
           << "0 0 0 0 1 0\n"
           << 0.5 * units << ", 0, " << 0.5 * units << ", 0, 1, 0\n";
    writeText(dir / "probes.txt", probes.str());
}

// The lamp over a grey floor with a grey cube in between: occlusion and interreflection.
void writeOccluderScene(const fs::path& dir) {
    writeText(dir / "box.mtl",
              "newmtl light\nKd 0 0 0\nKe 5 5 5\n"
              "newmtl grey\nKd 0.5 0.6 0.7\n");
    std::ostringstream obj;
    obj << "mtllib box.mtl\n"
           "v -0.5 1 -0.5\nv 0.5 1 -0.5\nv 0.5 1 0.5\nv -0.5 1 0.5\n"
           "v -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\n";
    const double s = 0.2, y0 = 0.4, y1 = 0.6;
    for (double y : {y0, y1})
        obj << "v " << -s << " " << y << " " << -s << "\nv " << s << " " << y << " " << -s << "\nv " << s << " " << y
            << " " << s << "\nv " << -s << " " << y << " " << s << "\n";
    obj << "o lamp\nusemtl light\nf 1 2 3 4\n"
           "o floor\nusemtl grey\nf 5 6 7 8\n"
           "o cube\nusemtl grey\n"
           "f 9 10 11 12\nf 13 16 15 14\nf 12 11 15 16\nf 10 9 13 14\nf 11 10 14 15\nf 9 12 16 13\n";
    writeText(dir / "box.obj", obj.str());
    writeText(dir / "probes.txt", "0 0 0 0 1 0\n1 0 1 0 1 0\n0 0.61 0 0 1 0\n0.3 0.5 0 1 0 0\n");
}

std::set<std::string> filesIn(const fs::path& dir) {
    std::set<std::string> names;
    if (!fs::exists(dir)) return names;
    for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
    return names;
}

std::vector<std::vector<double>> readCsv(const fs::path& path, std::string& header) {
    std::istringstream in(readBytes(path));
    std::getline(in, header);
    std::vector<std::vector<double>> rows;
    for (std::string line; std::getline(in, line);) {
        std::vector<double> row;
        std::istringstream fields(line);
        for (std::string field; std::getline(fields, field, ',');) row.push_back(std::stod(field));
        rows.push_back(row);
    }
    return rows;
}

}  // namespace

TEST_CASE("bake writes glb, ply, probes.csv, stats.json and timings.json; probes match the closed form") {
    TempDir tmp;
    writeLampScene(tmp.path);
    const fs::path out = tmp.path / "out";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "lamp.obj") + " -o " + quote(out) + " --probes " +
                                     quote(tmp.path / "probes.txt") + " --quiet");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    CHECK(filesIn(out) ==
          std::set<std::string>{"lamp.glb", "lamp.ply", "probes.csv", "stats.json", "timings.json", "manifest.json",
                                "lightmaps"});
    CHECK(filesIn(out / "lightmaps") == std::set<std::string>{"lamp_0.exr", "lamp_0.png"});
    // Nothing else beside OUTDIR: the staging directory is gone.
    CHECK(filesIn(tmp.path) == std::set<std::string>{"lamp.mtl", "lamp.obj", "out", "probes.txt"});
    // Quiet: the one-line summary and nothing else.
    CHECK(run.output.find("radbake: baked ") == 0);
    CHECK(std::count(run.output.begin(), run.output.end(), '\n') == 1);

    std::string header;
    const std::vector<std::vector<double>> rows = readCsv(out / "probes.csv", header);
    CHECK(header == "x,y,z,nx,ny,nz,r,g,b");
    REQUIRE(rows.size() == 2);
    const double centre = 4 * cornerIrradiance(0.5, 0.5, 1.0, 2.0);  // 1.50448 W/m^2
    const double corner = cornerIrradiance(1.0, 1.0, 1.0, 2.0);
    for (int k = 6; k < 9; ++k) {
        CHECK(rows[0][k] == doctest::Approx(centre).epsilon(0.01));  // 1 % at the default quality
        CHECK(rows[1][k] == doctest::Approx(corner).epsilon(0.01));
    }
    CHECK(rows[1][0] == 0.5);
    CHECK(rows[1][4] == 1.0);

    const nlohmann::json stats = nlohmann::json::parse(readBytes(out / "stats.json"));
    for (const char* key : {"elements", "links", "shafts", "occluded_links", "rays", "iterations", "error_threshold",
                            "local_error_threshold", "min_area", "tolerance", "max_iterations"})
        CHECK_MESSAGE(stats.at(key).is_number(), key);
    CHECK(stats.at("visibility").get<std::string>() == "aabb");  // the default
    CHECK(stats.at("quality").get<std::string>() == "medium");
    CHECK(stats.at("elements").get<double>() >= 2);
    CHECK(stats.at("converged").is_boolean());
    // What differs from run to run is in timings.json only.
    const nlohmann::json timings = nlohmann::json::parse(readBytes(out / "timings.json"));
    for (const char* key : {"seconds", "phases", "peak_rss_mb", "threads"}) {
        CHECK_MESSAGE(!stats.contains(key), key);
        CHECK_MESSAGE(timings.contains(key), key);
    }
    CHECK(timings.at("seconds").get<double>() > 0);
    CHECK(timings.at("phases").is_object());
    CHECK(timings.at("phases").contains("import"));
    CHECK(timings.at("phases").contains("write"));
    CHECK(timings.at("peak_rss_mb").get<double>() > 0);
    CHECK(timings.at("threads").get<double>() >= 1);
}

TEST_CASE("bake without -o writes into baked/<scene name>/ under the working directory") {
    TempDir tmp;
    writeLampScene(tmp.path);
    const std::string command = "cd " + quote(tmp.path) + " && '" + RADBAKE_EXE + "' bake lamp.obj --quality draft -q >/dev/null";
    CHECK(std::system(command.c_str()) == 0);
    CHECK(filesIn(tmp.path / "baked" / "lamp") ==
          std::set<std::string>{"lamp.glb", "lamp.ply", "stats.json", "timings.json", "manifest.json", "lightmaps"});
    const nlohmann::json stats = nlohmann::json::parse(readBytes(tmp.path / "baked" / "lamp" / "stats.json"));
    CHECK(stats.at("quality").get<std::string>() == "draft");
}

TEST_CASE("bad command lines exit 2") {
    TempDir tmp;
    writeLampScene(tmp.path);
    const fs::path out = tmp.path / "out";
    const std::string scene = quote(tmp.path / "lamp.obj") + " -o " + quote(out);
    CHECK(runRadbake("bake " + scene + " --no-such-option").exit_code == 2);
    CHECK(runRadbake("bake " + scene + " --quality extreme").exit_code == 2);
    CHECK(runRadbake("bake " + scene + " --visibility xray").exit_code == 2);
    CHECK(runRadbake("bake " + scene + " --threads -1").exit_code == 2);
    CHECK(runRadbake("bake " + scene + " --error-threshold 0").exit_code == 2);
    CHECK(runRadbake("bake").exit_code == 2);  // SCENE is required
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("--help shows every knob with its default") {
    const RunResult run = runRadbake("bake --help");
    CHECK(run.exit_code == 0);
    for (const char* option : {"--quality", "--visibility", "--threads", "--probes", "--unit-scale", "--emission-scale",
                               "--error-threshold", "--local-error-threshold", "--min-area", "--tolerance", "--max-iterations", "--strict",
                               "--quiet", "baked/<scene name>/", "--no-lightmaps", "--texel-density", "--atlas-size",
                               "--padding", "--exr-float", "--preview", "--texel-tolerance", "--max-texels"})
        CHECK_MESSAGE(run.output.find(option) != std::string::npos, option);
    CHECK(run.output.find("default: from --quality (draft ") != std::string::npos);
}

TEST_CASE("malformed input: located error, exit 1, no OUTDIR files") {
    TempDir tmp;
    writeLampScene(tmp.path);
    writeText(tmp.path / "bad.wrl",
              "#VRML V2.0 utf8\n"
              "Shape {\n"
              "  geometry IndexedFaceSet {\n"
              "    coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 x ] }\n"
              "    coordIndex [ 0 1 2 -1 ]\n"
              "  }\n"
              "}\n");
    const fs::path new_out = tmp.path / "new" / "out";
    const RunResult bad_scene = runRadbake("bake " + quote(tmp.path / "bad.wrl") + " -o " + quote(new_out));
    INFO(bad_scene.output);
    CHECK(bad_scene.exit_code == 1);
    CHECK(bad_scene.output.find((tmp.path / "bad.wrl").string() + ":4:50: error: ") != std::string::npos);
    CHECK_FALSE(fs::exists(tmp.path / "new"));

    // A bad probe file is an input error too, and an existing OUTDIR keeps its older files.
    const fs::path out = tmp.path / "out";
    fs::create_directory(out);
    writeText(out / "lamp.glb", "older bake");
    writeText(tmp.path / "bad_probes.txt", "0 0 0 0 1 0\n0 0 0 0 0 0\n");
    const RunResult bad_probes = runRadbake("bake " + quote(tmp.path / "lamp.obj") + " -o " + quote(out) +
                                            " --probes " + quote(tmp.path / "bad_probes.txt"));
    INFO(bad_probes.output);
    CHECK(bad_probes.exit_code == 1);
    CHECK(bad_probes.output.find((tmp.path / "bad_probes.txt").string() + ":2:7: error: probe normal is zero") !=
          std::string::npos);
    CHECK(filesIn(out) == std::set<std::string>{"lamp.glb"});
    CHECK(readBytes(out / "lamp.glb") == "older bake");
    CHECK(filesIn(tmp.path) ==
          std::set<std::string>{"bad.wrl", "bad_probes.txt", "lamp.mtl", "lamp.obj", "out", "probes.txt"});
}

TEST_CASE("outputs are byte-identical with 1 and 2 threads") {
    TempDir tmp;
    writeOccluderScene(tmp.path);
    const std::string common = quote(tmp.path / "box.obj") + " --probes " + quote(tmp.path / "probes.txt") + " -q";
    const RunResult one = runRadbake("bake " + common + " --threads 1 -o " + quote(tmp.path / "t1"));
    const RunResult two = runRadbake("bake " + common + " --threads 2 -o " + quote(tmp.path / "t2"));
    INFO(one.output, two.output);
    REQUIRE(one.exit_code == 0);
    REQUIRE(two.exit_code == 0);
    for (const char* name : {"box.glb", "box.ply", "probes.csv", "lightmaps/box_0.exr"}) {
        const std::string a = readBytes(tmp.path / "t1" / name);
        CHECK_MESSAGE(!a.empty(), name);
        CHECK_MESSAGE(a == readBytes(tmp.path / "t2" / name), name);
    }
    const nlohmann::json s1 = nlohmann::json::parse(readBytes(tmp.path / "t1" / "stats.json"));
    const nlohmann::json s2 = nlohmann::json::parse(readBytes(tmp.path / "t2" / "stats.json"));
    CHECK(nlohmann::json::parse(readBytes(tmp.path / "t1" / "timings.json")).at("threads").get<double>() == 1);
    CHECK(nlohmann::json::parse(readBytes(tmp.path / "t2" / "timings.json")).at("threads").get<double>() == 2);
    CHECK(s1.at("links").get<double>() == s2.at("links").get<double>());
    CHECK(s1.at("occluded_links").get<double>() == s2.at("occluded_links").get<double>());
    // The cube shadows the floor's centre: less light there than the unoccluded closed form.
    std::string header;
    const std::vector<std::vector<double>> rows = readCsv(tmp.path / "t1" / "probes.csv", header);
    REQUIRE(rows.size() == 4);
    CHECK(rows[0][6] < 0.5 * 4 * cornerIrradiance(0.5, 0.5, 1.0, 5.0));
}

TEST_CASE("the shipped Cornell Box bakes byte-identically with 1 and 2 threads") {
    const fs::path scene = fs::path(RADBAKE_SOURCE_DIR) / "scenes" / "cornell_box.wrl";
    REQUIRE(fs::exists(scene));
    TempDir tmp;
    writeText(tmp.path / "probes.txt", "0.278 0.01 0.2796 0 1 0\n");  // above the floor centre, facing up
    const std::string common = quote(scene) + " -q --probes " + quote(tmp.path / "probes.txt");
    const RunResult one = runRadbake("bake " + common + " --threads 1 -o " + quote(tmp.path / "t1"));
    const RunResult two = runRadbake("bake " + common + " --threads 2 -o " + quote(tmp.path / "t2"));
    INFO(one.output, two.output);
    REQUIRE(one.exit_code == 0);
    REQUIRE(two.exit_code == 0);
    for (const char* name : {"cornell_box.glb", "cornell_box.ply", "probes.csv", "lightmaps/cornell_box_0.exr"}) {
        const std::string a = readBytes(tmp.path / "t1" / name);
        CHECK_MESSAGE(a.size() > 30, name);
        CHECK_MESSAGE(a == readBytes(tmp.path / "t2" / name), name);
    }
}

TEST_CASE("--unit-scale: a scene and its probes in centimetres give the same irradiance") {
    TempDir tmp;
    writeLampScene(tmp.path, 100.0);
    const RunResult run = runRadbake("bake " + quote(tmp.path / "lamp.obj") + " -q --unit-scale 0.01 -o " +
                                     quote(tmp.path / "out") + " --probes " + quote(tmp.path / "probes.txt"));
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    std::string header;
    const std::vector<std::vector<double>> rows = readCsv(tmp.path / "out" / "probes.csv", header);
    REQUIRE(rows.size() == 2);
    CHECK(rows[1][0] == 50.0);  // positions are echoed in the file's units
    CHECK(rows[0][6] == doctest::Approx(4 * cornerIrradiance(0.5, 0.5, 1.0, 2.0)).epsilon(0.01));
    CHECK(rows[1][7] == doctest::Approx(cornerIrradiance(1.0, 1.0, 1.0, 2.0)).epsilon(0.01));
}

TEST_CASE("a scene with no emitter and no light bakes black, with a warning that says so") {
    TempDir tmp;
    writeText(tmp.path / "dark.wrl", "#VRML V2.0 utf8\nShape { geometry Box {} }\n");
    const RunResult run = runRadbake("bake " + quote(tmp.path / "dark.wrl") + " -q --quality draft -o " + quote(tmp.path / "out"));
    INFO(run.output);
    CHECK(run.exit_code == 0);
    CHECK(run.output.find("dark.wrl: warning: the scene has no emissive surface and no light") != std::string::npos);
    CHECK(run.output.find("1 warning ") != std::string::npos);
    // A lit scene does not get it.
    writeText(tmp.path / "lit.wrl",
              "#VRML V2.0 utf8\nShape { appearance Appearance { material Material { emissiveColor 1 1 1 } }"
              " geometry Box {} }\n");
    const RunResult lit = runRadbake("bake " + quote(tmp.path / "lit.wrl") + " -q --quality draft -o " + quote(tmp.path / "out2"));
    CHECK(lit.exit_code == 0);
    CHECK(lit.output.find("no emissive surface") == std::string::npos);
}

namespace {

// A solve's log lines end with the whole solve's fraction and time left, as
// tools/progress_check.py reads them: "radbake: PHASE ...; the solve N %, about T left", N
// never falling back, only in the solve's phases.
void checkSolveEstimateLines(const std::string& output) {
    const std::regex stage("^radbake: (.+?) (?:\\d+ %|done in).*; the solve (\\d+) %, about (.+) left$");
    std::istringstream lines(output);
    std::string line;
    int last = 0, with_stage = 0;
    bool read_out = false, in_order = true, outside = false;
    while (std::getline(lines, line)) {
        read_out = read_out || line.rfind("radbake: vertices", 0) == 0;
        std::smatch m;
        if (!std::regex_match(line, m, stage)) continue;
        ++with_stage;
        const int percent = std::stoi(m[2].str());
        in_order = in_order && percent >= last && percent <= 100;
        last = percent;
        outside = outside || read_out;
    }
    CHECK(with_stage >= 3);  // the first links phase on
    CHECK(in_order);
    CHECK_FALSE(outside);    // the read-out's lines carry no solve estimate
}

}  // namespace

TEST_CASE("a log gets progress as plain lines, one at each phase's end, the solve's with its fraction and time left; --quiet none") {
    const TempDir tmp;
    const std::string scene = quote(fs::path(RADBAKE_SOURCE_DIR) / "scenes" / "cornell_box.wrl");
    // runRadbake's stderr is a pipe, as a content build's log is.
    const RunResult logged = runRadbake("bake " + scene + " -o " + quote(tmp.path / "a"));
    INFO(logged.output);
    REQUIRE(logged.exit_code == 0);
    for (const char* phase : {"import", "elements", "links", "solve", "vertices", "lightmaps"})
        CHECK(logged.output.find(std::string("radbake: ") + phase + " done in ") != std::string::npos);
    CHECK(logged.output.find('\r') == std::string::npos);  // no terminal redrawing in a log
    checkSolveEstimateLines(logged.output);
    const RunResult quiet = runRadbake("bake " + scene + " -o " + quote(tmp.path / "b") + " --quiet");
    REQUIRE(quiet.exit_code == 0);
    CHECK(quiet.output.find(" done in ") == std::string::npos);
}
