// The Monte Carlo reference (tools/reference_mc.h) against the analytic scenes
// (scenes/analytic/, answers written by tools/analytic_scenes.cpp), and the answers themselves
// against the published closed forms.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "export/probes.h"
#include "io/import.h"
#include "mc_test_support.h"
#include "reference_mc.h"
#include "readout/evaluate_probe.h"
#include "scene/two_sided.h"
#include "../radiosity/test_scenes.h"

namespace {

using namespace radbake;

struct Expected {
    DVec3 position, normal, irradiance;
    double rel_tol = 0.0;
};

std::string analyticPath(const std::string& name) { return std::string(RADBAKE_SOURCE_DIR) + "/scenes/analytic/" + name; }

std::vector<Expected> readExpected(const std::string& name) {
    std::ifstream in(analyticPath(name + ".expected.csv"));
    std::vector<Expected> rows;
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        double v[10] = {};
        std::string field;
        for (int i = 0; i < 10 && std::getline(fields, field, ','); ++i) v[i] = std::stod(field);
        rows.push_back({DVec3(v[0], v[1], v[2]), DVec3(v[3], v[4], v[5]), DVec3(v[6], v[7], v[8]), v[9]});
    }
    return rows;
}

Scene loadScene(const std::string& name) {
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(analyticPath(name + ".wrl"), ImportOptions{}, diagnostics);
    REQUIRE(scene.has_value());
    REQUIRE(diagnostics.warningCount() == 0);
    return std::move(*scene);
}

std::vector<reference::McProbe> readProbeFile(const std::string& name) {
    Diagnostics diagnostics;
    const std::optional<std::vector<Probe>> probes = readProbes(analyticPath(name + ".probes"), diagnostics);
    REQUIRE(probes.has_value());
    std::vector<reference::McProbe> points;
    for (const Probe& p : *probes) points.push_back({p.position, p.normal});
    return points;
}

// Every probe's estimate within 4 standard errors of the exact value (two-sided chance of a
// false alarm 6e-5 per probe; seeds are fixed, so a pass is reproducible), and the standard
// error small enough (below max_rel_se of the value) that the check has teeth.
void checkAgainstExact(const std::string& name, int samples, double max_rel_se, bool next_event) {
    const Scene scene = loadScene(name);
    const std::vector<reference::McProbe> probes = readProbeFile(name);
    const std::vector<Expected> expected = readExpected(name);
    REQUIRE(probes.size() == expected.size());
    const reference::McBvh bvh(scene);
    reference::McOptions options;
    options.samples = samples;
    options.threads = 2;
    options.next_event = next_event;
    const std::vector<reference::McProbeResult> results = reference::estimateProbes(bvh, probes, options);
    double z_sq = 0.0;
    for (size_t i = 0; i < probes.size(); ++i) {
        CAPTURE(name);
        CAPTURE(next_event);
        CAPTURE(i);
        const double exact = expected[i].irradiance.x;
        const double estimate = results[i].irradiance.x, se = results[i].standard_error.x;
        CHECK(glm::length(probes[i].position - expected[i].position) < 1e-12);
        CHECK(se > 0.0);
        CHECK(se < max_rel_se * exact);
        CHECK(std::abs(estimate - exact) < 4.0 * se);
        CHECK(results[i].irradiance.y == estimate);  // grey scenes: every channel follows the same path
        z_sq += (estimate - exact) * (estimate - exact) / (se * se);
    }
    // The printed error is honest: normalised errors have unit variance (chi-square over
    // n probes: mean 1, and with n >= 24 the mean of z^2 lies in [0.4, 1.8] except with
    // probability < 1e-3).
    const double mean_z_sq = z_sq / probes.size();
    CHECK(mean_z_sq > 0.4);
    CHECK(mean_z_sq < 1.8);
}

}  // namespace

TEST_CASE("analytic answers: parallel squares' probe grid converges to the published form factor") {
    const std::vector<Expected> rows = readExpected("parallel_squares");
    REQUIRE(rows.size() == 64);
    double mean = 0.0;
    for (const Expected& r : rows) mean += r.irradiance.x / rows.size();
    // 8x8 midpoint rule on a smooth integrand: error ~ h^2/24 * |laplacian F_point| ~ 5e-4 here.
    CHECK(std::abs(mean - 0.199824895698387383) < 1e-3);
    CHECK(std::abs(mean - 0.199824895698387383) > 1e-5);  // the grid's own error is real, not zero
    CHECK(rows[0].rel_tol == 0.01);
}

TEST_CASE("analytic answers: the point under the corner and the furnaces") {
    const std::vector<Expected> corner = readExpected("corner_point");
    REQUIRE(corner.size() == 25);
    CHECK(corner[0].position == DVec3(0.0));
    CHECK(std::abs(corner[0].irradiance.x - kPi * 0.138531605994892997) < 1e-14);
    for (double rho : {0.5, 0.9, 0.99, 0.999}) {
        std::ostringstream name;
        name << "furnace_rho_" << rho;
        const std::vector<Expected> rows = readExpected(name.str());
        REQUIRE(rows.size() == 24);
        for (const Expected& r : rows) CHECK(std::abs(r.irradiance.x - kPi / (1.0 - rho)) < 1e-12 * r.irradiance.x);
    }
}

TEST_CASE("reference MC (pure path tracing) agrees with analytic scenes within its printed error") {
    checkAgainstExact("parallel_squares", 4096, 0.05, false);
    checkAgainstExact("furnace_rho_0.5", 2048, 0.02, false);
    checkAgainstExact("sphere_patch", 4096, 0.5, false);
}

TEST_CASE("reference MC (next-event estimation) agrees with analytic scenes within its printed error") {
    // Light sampling: a far smaller error for the same paths, so tighter bounds on it.
    checkAgainstExact("parallel_squares", 1024, 0.02, true);
    checkAgainstExact("corner_point", 1024, 0.02, true);
    checkAgainstExact("hinged_120", 1024, 0.08, true);
    checkAgainstExact("furnace_rho_0.9", 1024, 0.05, true);
    checkAgainstExact("sphere_patch", 1024, 0.05, true);
}

TEST_CASE("reference MC: two-sided surfaces reflect and emit on both sides") {
    // The outward solid FALSE cube is a furnace inside (H = 2 pi) only through its backs.
    checkAgainstExact("furnace_two_sided", 2048, 0.02, false);
    checkAgainstExact("furnace_two_sided", 1024, 0.05, true);
    checkAgainstExact("thin_wall_two_sided", 1024, 0.03, true);
    // The thin wall's back sees nothing; the one-sided cube's inside is dark.
    const Scene wall = loadScene("thin_wall_two_sided");
    const reference::McBvh wall_bvh(wall);
    reference::McOptions options;
    options.samples = 256;
    options.threads = 2;
    const std::vector<reference::McProbe> back = {{DVec3(0.5, 0.5, 0.0), DVec3(0, 0, -1)}};
    CHECK(reference::estimateProbes(wall_bvh, back, options)[0].irradiance.x == 0.0);
    Scene cube = loadScene("furnace_two_sided");
    for (Mesh& mesh : cube.meshes) mesh.solid = true;
    const reference::McBvh cube_bvh(cube);
    const std::vector<reference::McProbe> inside = {{DVec3(0.5), DVec3(0, 0, 1)}};
    CHECK(reference::estimateProbes(cube_bvh, inside, options)[0].irradiance.x == 0.0);
}

TEST_CASE("reference MC and radbake agree on a two-sided partition lit from one side") {
    // A closed grey room [0,2] x [0,1] x [0,1] (one-sided, facing in), a two-sided partition at
    // x = 1 up to z = 0.7, and an emitter on the floor of the left half: the partition's left
    // side is lit directly, its right side only by what comes over it.
    using namespace radbake::test;
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.5f), Vec3(0.0f));
    const uint32_t white = addMaterial(scene, Vec3(0.7f), Vec3(0.0f));
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(1.0f));
    addInwardBox(scene, grey, Vec3(0.0f), Vec3(2.0f, 1.0f, 1.0f));
    addQuad(scene, white, {1, 0, 0}, {1, 1, 0}, {1, 1, 0.7f}, {1, 0, 0.7f});  // faces +x
    scene.meshes.back().solid = false;
    addQuad(scene, lamp, {0.2f, 0.2f, 0.001f}, {0.8f, 0.2f, 0.001f}, {0.8f, 0.8f, 0.001f}, {0.2f, 0.8f, 0.001f});
    const std::vector<reference::McProbe> probes = {
        {DVec3(1.0, 0.5, 0.35), DVec3(-1, 0, 0)},  // the partition's lit side
        {DVec3(1.0, 0.5, 0.35), DVec3(1, 0, 0)},   // its back, lit by bounces only
        {DVec3(1.5, 0.5, 0.0), DVec3(0, 0, 1)},    // the dark half's floor
        {DVec3(2.0, 0.5, 0.5), DVec3(-1, 0, 0)},   // its far wall
        {DVec3(0.5, 0.5, 1.0), DVec3(0, 0, -1)}};  // the lit half's ceiling
    const reference::McBvh bvh(scene);  // two-sided natively, no twins
    reference::McOptions mc;
    mc.samples = 8192;
    mc.threads = 2;
    const std::vector<reference::McProbeResult> expected = reference::estimateProbes(bvh, probes, mc);

    Scene twinned = scene;
    REQUIRE(addBackTwins(twinned) == 1);
    Diagnostics diagnostics;
    const PartSet parts = buildParts(twinned, PartOptions{}, diagnostics);
    Progress progress(false);
    ParallelRunner runner(Threading{.threads = 2});
    const std::optional<Solution> solution =
        solveRadiosity(twinned, parts, SolverOptions::forQuality(Quality::Medium), runner, progress, diagnostics);
    REQUIRE(solution.has_value());
    for (size_t i = 0; i < probes.size(); ++i) {
        CAPTURE(i);
        const double h = probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality),
                                         probes[i].position, probes[i].normal)
                             .x;
        const double mean = expected[i].irradiance.x, se = expected[i].standard_error.x;
        MESSAGE("probe " << i << ": radbake " << h << ", reference " << mean << " +- " << se);
        CHECK(mean > 0.0);
        // Light reaches the far half only over the partition (several bounces): there the
        // reference is noisier (about 5-7 % at 8192 paths, 0.7 % on the lit side).
        CHECK(se < (i == 0 || i == 4 ? 0.02 : 0.1) * mean);
        // The reference's noise (4 standard errors) plus the solver's own error at the default quality.
        CHECK(std::abs(h - mean) <= 4.0 * se + 0.03 * mean);
    }
    // The back is lit, but far less than the front.
    CHECK(expected[1].irradiance.x < 0.5 * expected[0].irradiance.x);
}

TEST_CASE("reference MC is deterministic for any thread count") {
    const Scene scene = loadScene("hinged_60");
    const reference::McBvh bvh(scene);
    std::vector<reference::McProbe> probes = readProbeFile("hinged_60");
    probes.resize(8);
    reference::McOptions options;
    options.samples = 256;
    const auto one = mctest::checkSameOnThreadCounts(bvh, probes, options);
    options.seed = 2;
    const auto other = reference::estimateProbes(bvh, probes, options);
    CHECK(other[0].irradiance != one[0].irradiance);
}

TEST_CASE("reference BVH closest hit equals a brute-force loop over every triangle") {
    const Scene scene = loadScene("sphere_furnace");
    const reference::McBvh bvh(scene);
    REQUIRE(bvh.triangles().size() == 224);  // 8 x 16 faces: 96 trapezoids (2 triangles) + 32 pole triangles
    reference::McRandom random(7);
    int hits = 0;
    for (int k = 0; k < 2000; ++k) {
        // Origins anywhere in [-1.5, 1.5]^3 (inside and outside the sphere), uniform directions.
        const DVec3 origin(3.0 * random.uniform() - 1.5, 3.0 * random.uniform() - 1.5, 3.0 * random.uniform() - 1.5);
        const double z = 2.0 * random.uniform() - 1.0, phi = 2.0 * kPi * random.uniform();
        const double r = std::sqrt(1.0 - z * z);
        const DVec3 dir(r * std::cos(phi), r * std::sin(phi), z);
        double best = std::numeric_limits<double>::infinity();
        for (const reference::McTriangle& t : bvh.triangles()) {
            // Plane hit, then barycentric inside test: an independent formulation.
            const double denom = glm::dot(dir, t.normal);
            if (denom == 0.0) continue;
            const double s = glm::dot(t.v0 - origin, t.normal) / denom;
            if (!(s > 0.0) || s >= best) continue;
            const DVec3 q = origin + dir * s - t.v0;
            const double d00 = glm::dot(t.e1, t.e1), d01 = glm::dot(t.e1, t.e2), d11 = glm::dot(t.e2, t.e2);
            const double d20 = glm::dot(q, t.e1), d21 = glm::dot(q, t.e2), det = d00 * d11 - d01 * d01;
            const double v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
            if (v >= -1e-12 && w >= -1e-12 && v + w <= 1.0 + 1e-12) best = s;
        }
        reference::McHit hit;
        const bool found = bvh.closestHit(origin, dir, 0.0, std::numeric_limits<double>::infinity(),
                                          std::numeric_limits<uint32_t>::max(), hit);
        CAPTURE(k);
        REQUIRE(found == std::isfinite(best));
        if (found) {
            ++hits;
            CHECK(std::abs(hit.t - best) < 1e-9);
        }
    }
    // Origins inside the sphere (15% of the cube) always hit, and many outside ones do.
    CHECK(hits > 300);
}
