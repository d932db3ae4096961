// The solver at the default quality (medium, exact visibility) against the analytic scenes'
// exact answers (scenes/analytic/*.expected.csv, each probe with its own relative tolerance):
// issue 6's "the analytic scenes pass at the default quality".
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/progress.h"
#include "export/probes.h"
#include "geometry/parts.h"
#include "io/import.h"
#include "radiosity/solution.h"
#include "radiosity/solver.h"
#include "readout/evaluate_probe.h"
#include "scene/two_sided.h"

namespace {

using namespace radbake;

std::string analyticFile(const std::string& name) { return std::string(RADBAKE_SOURCE_DIR) + "/scenes/analytic/" + name; }

// Returns how many probes miss their tolerance; every miss is reported with its values.
int solveAndCompare(const std::string& name) {
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(analyticFile(name + ".wrl"), ImportOptions{}, diagnostics);
    REQUIRE(scene.has_value());
    addBackTwins(*scene);  // as bake() does: two-sided scenes take part on both sides
    const std::optional<std::vector<Probe>> probes = readProbes(analyticFile(name + ".probes"), diagnostics);
    REQUIRE(probes.has_value());
    const PartSet parts = buildParts(*scene, PartOptions{}, diagnostics);
    SolverOptions options = SolverOptions::forQuality(Quality::Medium);
    Progress progress(false);
    ParallelRunner runner(Threading{.threads = 2});
    const auto start = std::chrono::steady_clock::now();
    const std::optional<Solution> solution = solveRadiosity(*scene, parts, options, runner, progress, diagnostics);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    REQUIRE(solution.has_value());
    // Printed, never asserted: speed is measured by tools/, not by tests.
    if (name.starts_with("furnace"))
        MESSAGE(name << ": solved in " << seconds << " s (medium, 2 threads, " << solution->stats.iterations
                     << " iterations)");
    REQUIRE_FALSE(diagnostics.hasErrors());

    std::ifstream expected(analyticFile(name + ".expected.csv"));
    std::string line;
    std::getline(expected, line);  // header
    int misses = 0;
    size_t i = 0;
    for (; std::getline(expected, line); ++i) {
        std::istringstream fields(line);
        std::string field;
        double v[10] = {};
        for (int k = 0; k < 10 && std::getline(fields, field, ','); ++k) v[k] = std::stod(field);
        REQUIRE(i < probes->size());
        const DVec3 h = probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality),
                                        (*probes)[i].position, (*probes)[i].normal);
        const double rel = std::abs(h.x - v[6]) / v[6];
        if (rel > v[9]) {
            ++misses;
            MESSAGE(name << " probe " << i << ": H = " << h.x << ", exact " << v[6] << ", relative error " << rel
                         << " > " << v[9]);
        }
    }
    CHECK(i == probes->size());
    return misses;
}

}  // namespace

TEST_CASE("analytic scenes pass at the default quality") {
    for (const char* name : {"parallel_squares", "perpendicular_squares", "hinged_60", "hinged_120", "coaxial_disks",
                             "corner_point", "furnace_rho_0.5", "furnace_rho_0.9", "furnace_rho_0.99",
                             "sphere_furnace", "sphere_patch", "furnace_two_sided", "thin_wall_two_sided"}) {
        CAPTURE(name);
        CHECK(solveAndCompare(name) == 0);
    }
}

// At rho = 0.999 a form-factor row-sum error e shows as e / (1 - rho) = 1000 e in the answer:
// this once read 3.7 % low (adjacent-element quadrature and a centre-only leaf correction).
TEST_CASE("analytic scenes: the rho = 0.999 furnace at the default quality") {
    CHECK(solveAndCompare("furnace_rho_0.999") == 0);
}
