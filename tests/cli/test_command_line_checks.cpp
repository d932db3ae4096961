// Careless command lines (issue 32): every numeric option refuses NaN, infinities, empty
// strings and values out of its range, every path option an empty string, with exit 2 and
// a message naming the option, before any work.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <string>
#include <vector>

#include "cli_support.h"

using namespace clitest;

namespace {

// A lit floor: enough for a bake that gets past its command line.
void writeFloorScene(const fs::path& dir) {
    writeText(dir / "floor.mtl", "newmtl light\nKd 0 0 0\nKe 2 2 2\nnewmtl floor\nKd 0.5 0.5 0.5\n");
    writeText(dir / "floor.obj",
              "mtllib floor.mtl\n"
              "v -0.5 1 -0.5\nv 0.5 1 -0.5\nv 0.5 1 0.5\nv -0.5 1 0.5\n"
              "v -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\n"
              "o lamp\nusemtl light\nf 1 2 3 4\no floor\nusemtl floor\nf 5 6 7 8\n");
}

// The longest run of digits in `text`: a range printed in full would be 300 digits long.
size_t longestDigitRun(const std::string& text) {
    size_t longest = 0, run = 0;
    for (const char c : text) {
        run = std::isdigit(static_cast<unsigned char>(c)) ? run + 1 : 0;
        longest = std::max(longest, run);
    }
    return longest;
}

struct BadValue {
    std::string option;
    std::vector<std::string> values;  // shell words, quoted where needed
};

// Runs `prefix OPTION VALUE` for each bad value: exit 2, the option named, no huge number.
void checkRefused(const std::string& prefix, const std::vector<BadValue>& cases) {
    for (const BadValue& bad : cases) {
        for (const std::string& value : bad.values) {
            const RunResult run = runRadbake(prefix + " " + bad.option + " " + value);
            CAPTURE(bad.option);
            CAPTURE(value);
            INFO(run.output);
            CHECK(run.exit_code == 2);
            CHECK(run.output.find(bad.option + ": ") != std::string::npos);
            std::string said = run.output;  // what the program wrote, beside the value it repeats
            for (size_t at = said.find(value); !value.empty() && at != std::string::npos; at = said.find(value))
                said.erase(at, value.size());
            CHECK(longestDigitRun(said) < 12);
        }
    }
}

const std::vector<std::string> kNotFinite = {"nan", "NaN", "-nan", "inf", "-inf", "infinity", "1e999", "''", "abc"};

std::vector<std::string> notFiniteAnd(std::vector<std::string> more) {
    more.insert(more.end(), kNotFinite.begin(), kNotFinite.end());
    return more;
}

}  // namespace

TEST_CASE("bake: every numeric option refuses NaN, infinities, empty strings and out-of-range values with exit 2") {
    TempDir tmp;
    writeFloorScene(tmp.path);
    const fs::path out = tmp.path / "out";
    const std::string prefix = "bake " + quote(tmp.path / "floor.obj") + " -o " + quote(out) + " --quality draft";
    checkRefused(prefix, {
                             {"--threads", notFiniteAnd({"-1", "1025", "10000000", "99999999999999999999", "1.5"})},
                             {"--error-threshold", notFiniteAnd({"0", "-1", "2"})},
                             {"--local-error-threshold", notFiniteAnd({"-0.1", "2"})},
                             {"--min-area", notFiniteAnd({"0", "-1", "2"})},
                             {"--tolerance", notFiniteAnd({"0", "2"})},
                             {"--max-iterations", notFiniteAnd({"0", "-3", "10000001"})},
                             {"--max-memory", notFiniteAnd({"-1", "1e10"})},
                             {"--texel-density", notFiniteAnd({"0", "-16", "1e7"})},
                             {"--atlas-size", notFiniteAnd({"15", "16385", "1024.5"})},
                             {"--padding", notFiniteAnd({"-1", "65"})},
                             {"--texel-tolerance", notFiniteAnd({"-0.1", "1.5"})},
                             {"--max-texels", notFiniteAnd({"0", "-1", "99999999999999999999"})},
                             {"--unit-scale", notFiniteAnd({"0", "-1", "1e-7", "1e7"})},
                             {"--emission-scale", notFiniteAnd({"-1", "1e7"})},
                             {"--sky-radiance", notFiniteAnd({"-1", "1e10"})},
                             {"--sun-irradiance", notFiniteAnd({"-1", "1e10"})},
                             {"--sun-diameter", notFiniteAnd({"-0.1", "91"})},
                             {"--sun", {"10", "10,95", "nan,10", "10,-91", "a,b", "''", "10,20,30"}},
                             {"--sky", {"cloudy", "''", "Uniform"}},
                             {"--up", {"y", "+w", "''", "up"}},
                         });
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("info and compare: numeric options refuse what bake refuses") {
    TempDir tmp;
    writeFloorScene(tmp.path);
    checkRefused("info " + quote(tmp.path / "floor.obj"),
                 {{"--unit-scale", notFiniteAnd({"0", "-1", "1e7"})}, {"--emission-scale", notFiniteAnd({"-1", "1e7"})}});
    const std::string both = quote(tmp.path / "a") + " " + quote(tmp.path / "b");
    checkRefused("compare " + both, {{"--rel-tol", notFiniteAnd({"-1"})}, {"--abs-tol", notFiniteAnd({"-1e-9"})}});
}

TEST_CASE("ranges are printed readably, and an empty path option is refused, not ignored") {
    TempDir tmp;
    writeFloorScene(tmp.path);
    const fs::path out = tmp.path / "out";
    const std::string prefix = "bake " + quote(tmp.path / "floor.obj") + " -o " + quote(out) + " --quality draft";
    const RunResult threads = runRadbake(prefix + " --threads 10000000");
    CHECK(threads.output.find("--threads: '10000000' is not in [0, 1024]") != std::string::npos);
    const RunResult area = runRadbake(prefix + " --min-area nan");
    CHECK(area.output.find("--min-area: 'nan' is not a finite number in (0, 1]") != std::string::npos);
    const RunResult tolerance = runRadbake("compare a b --rel-tol inf");
    CHECK(tolerance.output.find("--rel-tol: 'inf' is not a finite number >= 0") != std::string::npos);
    const RunResult memory = runRadbake(prefix + " --max-memory 1e10");
    CHECK(memory.output.find("--max-memory: '1e10' is not in [0, 1e9]") != std::string::npos);

    for (const std::string option : {"--output", "--probes", "--depfile", "--solution", "--lightmap-scales"}) {
        // Any other option with -o, so that a bake that ignored the empty path writes only there.
        const std::string output = option == "--output" ? "" : " -o " + quote(out);
        const RunResult run = runRadbake("bake " + quote(tmp.path / "floor.obj") + output + " --quality draft " + option + " ''");
        CAPTURE(option);
        INFO(run.output);
        CHECK(run.exit_code == 2);
        CHECK(run.output.find(option + ": an empty path is not a file") != std::string::npos);
    }
    CHECK(runRadbake("bake " + quote(tmp.path / "floor.obj") + " -o ''").exit_code == 2);
    CHECK_FALSE(fs::exists(out));
    CHECK_FALSE(fs::exists(tmp.path / "baked"));
}

TEST_CASE("values at the ends of the ranges bake; a whole number with a leading zero is decimal") {
    TempDir tmp;
    writeFloorScene(tmp.path);
    const fs::path out = tmp.path / "out";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "floor.obj") + " -o " + quote(out) +
                                     " --quality draft --no-lightmaps --threads 010 --emission-scale 0 "
                                     "--max-iterations 1000000 --texel-tolerance 1 --max-memory 0 --unit-scale 1e6");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const nlohmann::json timings = nlohmann::json::parse(readBytes(out / "timings.json"));
    CHECK(timings.at("threads").get<int>() == 10);
}
