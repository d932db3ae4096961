// The Monte Carlo reference's punctual lights (tools/reference_mc.h): direct light against
// closed forms, one bounce against a form factor and against conservation of energy, and a lit
// room against radbake's own solve.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "readout/evaluate_probe.h"
#include "mc_test_support.h"
#include "reference_mc.h"
#include "../radiosity/test_scenes.h"

namespace {

using namespace radbake;
using namespace radbake::test;

// A black plane z = 0, [-10, 10]^2, facing +z: nothing reflects, so a probe reads the lights'
// direct irradiance alone, with no noise.
Scene blackPlane() {
    Scene scene;
    const uint32_t black = addMaterial(scene, Vec3(0.0f), Vec3(0.0f));
    addQuad(scene, black, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0});
    return scene;
}

Light pointLight(Vec3 position, float intensity, Vec3 color = Vec3(1.0f)) {
    Light light;
    light.type = LightType::Point;
    light.position = position;
    light.intensity = intensity;
    light.color = color;
    return light;
}

Light spotLight(Vec3 position, Vec3 direction, float beam_width, float cut_off_angle) {
    Light light = pointLight(position, 1.0f);
    light.type = LightType::Spot;
    light.direction = direction;
    light.beam_width = beam_width;
    light.cut_off_angle = cut_off_angle;
    return light;
}

Light directionalLight(Vec3 direction, float intensity) {
    Light light;
    light.type = LightType::Directional;
    light.direction = direction;
    light.intensity = intensity;
    light.radius = INFINITY;
    return light;
}

std::vector<reference::McProbeResult> estimate(const Scene& scene, const std::vector<reference::McProbe>& probes,
                                               int samples = 16, bool next_event = true) {
    reference::McOptions options;
    options.samples = samples;
    options.threads = 2;
    options.next_event = next_event;
    return reference::estimateProbes(reference::McBvh(scene), probes, options);
}

DVec3 directAt(const Scene& scene, const DVec3& p, const DVec3& n = DVec3(0, 0, 1)) {
    const reference::McProbeResult result = estimate(scene, {{p, n}})[0];
    // No bounce, no randomness: every path reads the same (what remains is the variance sum's
    // cancellation, about the square root of the double epsilon).
    for (int c = 0; c < 3; ++c) CHECK(result.standard_error[c] <= 1e-7 * result.irradiance[c]);
    return result.irradiance;
}

// Within the relative error the probe's origin offset (1e-6 of the scene's diagonal) makes.
void checkExact(const DVec3& got, const DVec3& want) {
    for (int c = 0; c < 3; ++c) CHECK(got[c] == doctest::Approx(want[c]).epsilon(2e-4));
}

// The form factor from a point at height h to a parallel a x b rectangle beside the foot of its
// normal, with that foot at a corner (Howell's catalogue, B-3).
double cornerFormFactor(double a, double b, double h) {
    const double ra = std::sqrt(a * a + h * h), rb = std::sqrt(b * b + h * h);
    return (a / ra * std::atan(b / ra) + b / rb * std::atan(a / rb)) / (2.0 * kPi);
}

}  // namespace

TEST_CASE("reference MC punctual lights: a point light over a black plane, I h / (h^2 + x^2)^1.5") {
    Scene scene = blackPlane();
    scene.lights.push_back(pointLight({0, 0, 2}, 3.0f, {1.0f, 0.5f, 0.25f}));
    const DVec3 intensity(3.0, 1.5, 0.75);
    for (double x : {0.0, 1.0, 3.0}) {
        CAPTURE(x);
        checkExact(directAt(scene, {x, 0, 0}), intensity * (2.0 / std::pow(4.0 + x * x, 1.5)));
    }
    CHECK(directAt(scene, {1, 0, 0}, {0, 0, -1}) == DVec3(0.0));  // facing away
}

TEST_CASE("reference MC punctual lights: a spot light's beam, its linear fall-off and its cut-off") {
    // Beam 0.3, cut-off 0.6 rad, pointing down from h = 2: a probe at angle t from the axis sits
    // at x = h tan t and reads I cos^3 t / h^2 times the spot factor.
    Scene scene = blackPlane();
    scene.lights.push_back(spotLight({0, 0, 2}, {0, 0, -1}, 0.3f, 0.6f));
    const auto expected = [](double t, double factor) { return DVec3(std::pow(std::cos(t), 3) / 4.0 * factor); };
    checkExact(directAt(scene, {2 * std::tan(0.2), 0, 0}), expected(0.2, 1.0));   // in the beam
    checkExact(directAt(scene, {0, 2 * std::tan(0.45), 0}), expected(0.45, 0.5));  // halfway out
    checkExact(directAt(scene, {2 * std::tan(0.55), 0, 0}), expected(0.55, 1.0 / 6.0));
    CHECK(directAt(scene, {2 * std::tan(0.7), 0, 0}) == DVec3(0.0));  // beyond the cut-off
    // A beam wider than the cut-off ends there (VRML97): full light up to it, none beyond.
    scene.lights[0].beam_width = 1.0f;
    checkExact(directAt(scene, {2 * std::tan(0.45), 0, 0}), expected(0.45, 1.0));
    CHECK(directAt(scene, {2 * std::tan(0.7), 0, 0}) == DVec3(0.0));
}

TEST_CASE("reference MC punctual lights: VRML attenuation on top of the inverse square, and the radius") {
    Scene scene = blackPlane();
    scene.lights.push_back(pointLight({0, 0, 3}, 1.0f));
    scene.lights[0].attenuation = Vec3(0, 0, 1);
    checkExact(directAt(scene, {0, 0, 0}), DVec3(1.0 / 9.0 / 9.0));
    scene.lights[0].attenuation = Vec3(1, 1, 0);
    checkExact(directAt(scene, {0, 0, 0}), DVec3(1.0 / 9.0 / 4.0));
    // Below 1 the factor is 1: max(a0 + a1 d + a2 d^2, 1).
    scene.lights[0].position = Vec3(0, 0, 0.5f);
    scene.lights[0].attenuation = Vec3(0, 0, 1);
    checkExact(directAt(scene, {0, 0, 0}), DVec3(4.0));
    // Radius 2.5 from h = 2: lit at d = sqrt(5), dark at d = sqrt(8).
    scene.lights[0] = pointLight({0, 0, 2}, 1.0f);
    scene.lights[0].radius = 2.5f;
    checkExact(directAt(scene, {1, 0, 0}), DVec3(2.0 / std::pow(5.0, 1.5)));
    CHECK(directAt(scene, {2, 0, 0}) == DVec3(0.0));
}

TEST_CASE("reference MC punctual lights: a directional light, E cos theta") {
    Scene scene = blackPlane();
    const double theta = 0.5;
    scene.lights.push_back(directionalLight(Vec3(std::sin(theta), 0, -std::cos(theta)), 2.0f));
    checkExact(directAt(scene, {3, 1, 0}), DVec3(2.0 * std::cos(theta)));
    checkExact(directAt(scene, {3, 1, 1}, {-1, 0, 0}), DVec3(2.0 * std::sin(theta)));  // facing the light's side
    CHECK(directAt(scene, {3, 1, 1}, {1, 0, 0}) == DVec3(0.0));
}

TEST_CASE("reference MC punctual lights: shadows, lights switched off, scopes") {
    Scene scene = blackPlane();
    const uint32_t black = scene.meshes[0].material;
    addQuad(scene, black, {-0.5f, -0.5f, 1}, {-0.5f, 0.5f, 1}, {0.5f, 0.5f, 1}, {0.5f, -0.5f, 1});  // faces down
    scene.lights.push_back(pointLight({0, 0, 2}, 1.0f));
    CHECK(directAt(scene, {0, 0, 0}) == DVec3(0.0));                        // behind the blocker
    checkExact(directAt(scene, {3, 0, 0}), DVec3(2.0 / std::pow(13.0, 1.5)));  // its ray passes beside it
    scene.lights[0].on = false;
    CHECK(directAt(scene, {3, 0, 0}) == DVec3(0.0));
    // A probe belongs to no mesh: every light lights it, scoped or not.
    scene.lights[0].on = true;
    scene.lights[0].scoped = true;
    scene.lights[0].scope = {1};
    checkExact(directAt(scene, {3, 0, 0}), DVec3(2.0 / std::pow(13.0, 1.5)));
}

TEST_CASE("reference MC punctual lights: one bounce off a floor lit by a scoped directional light") {
    // A grey floor [-1, 1]^2 (rho 0.5) lit straight down, E = 2, and a probe at h = 0.5 above its
    // centre facing it: H = rho E F, F the form factor to the floor (four corner rectangles).
    // Light that reaches only a mesh outside the light's scope is not there.
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.5f), Vec3(0.0f));
    addQuad(scene, grey, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    addQuad(scene, grey, {5, 5, 1}, {6, 5, 1}, {6, 6, 1}, {5, 6, 1});  // faces up, out of the probe's sight
    Light sun = directionalLight(Vec3(0, 0, -1), 2.0f);
    sun.scoped = true;
    sun.scope = {0};
    scene.lights.push_back(sun);
    const std::vector<reference::McProbe> probe = {{DVec3(0, 0, 0.5), DVec3(0, 0, -1)}};
    const double exact = 0.5 * 2.0 * 4.0 * cornerFormFactor(1.0, 1.0, 0.5);
    for (bool next_event : {true, false}) {
        CAPTURE(next_event);
        const reference::McProbeResult lit = estimate(scene, probe, 16384, next_event)[0];
        CHECK(lit.standard_error.x < 0.02 * exact);
        CHECK(std::abs(lit.irradiance.x - exact) < 4.0 * lit.standard_error.x);
    }
    scene.lights[0].scope = {1};
    CHECK(estimate(scene, probe, 1024)[0].irradiance == DVec3(0.0));
    // A two-sided floor lit from below reflects downwards only; a one-sided one, facing up, not at all.
    scene.lights[0] = directionalLight(Vec3(0, 0, 1), 2.0f);
    CHECK(estimate(scene, probe, 1024)[0].irradiance == DVec3(0.0));
    const std::vector<reference::McProbe> below = {{DVec3(0, 0, -0.5), DVec3(0, 0, 1)}};
    CHECK(estimate(scene, below, 1024)[0].irradiance == DVec3(0.0));
    scene.meshes[0].solid = false;
    const reference::McProbeResult under = estimate(scene, below, 16384)[0];
    CHECK(std::abs(under.irradiance.x - exact) < 4.0 * under.standard_error.x);
    CHECK(estimate(scene, probe, 1024)[0].irradiance == DVec3(0.0));
}

TEST_CASE("reference MC punctual lights: a closed grey box absorbs all a point light emits") {
    // Inside a closed box of reflectance rho every watt the light emits (4 pi I) is absorbed,
    // (1 - rho) H per unit area, so the area mean of H is 4 pi I / ((1 - rho) A), wherever the
    // light is. Its direct part, I cos / d^2 (nothing hides the light in a box), averages to
    // 4 pi I / A; the rest, rho / (1 - rho) of it, is what bounces. Probes uniform over the
    // walls make the mean of (H - direct) an unbiased estimate of the bounced part, whose spread
    // over the probes gives its standard error.
    Scene scene;
    const double rho = 0.5, intensity = 1.0;
    const DVec3 size(2.0, 1.5, 1.0), light(0.7, 0.6, 0.45);
    addInwardBox(scene, addMaterial(scene, Vec3(float(rho)), Vec3(0.0f)), Vec3(0.0f), Vec3(size));
    scene.lights.push_back(pointLight(Vec3(light), float(intensity)));
    const double area = 2.0 * (size.x * size.y + size.x * size.z + size.y * size.z);
    const double bounced = 4.0 * kPi * intensity / area * rho / (1.0 - rho);

    std::vector<reference::McProbe> probes;
    std::vector<double> direct;
    reference::McRandom random(11);
    for (int i = 0; i < 1024; ++i) {
        DVec3 p(random.uniform() * size.x, random.uniform() * size.y, random.uniform() * size.z);
        // A face chosen by area: pin p to it.
        const double pick = random.uniform() * area / 2.0;
        const int axis = pick < size.x * size.y ? 2 : pick < size.x * size.y + size.x * size.z ? 1 : 0;
        const bool high = random.uniform() < 0.5;
        p[axis] = high ? size[axis] : 0.0;
        DVec3 n(0.0);
        n[axis] = high ? -1.0 : 1.0;
        probes.push_back({p, n});
        const DVec3 to = light - p;
        direct.push_back(intensity * glm::dot(n, to) / std::pow(glm::dot(to, to), 1.5));
    }
    for (bool next_event : {true, false}) {
        CAPTURE(next_event);
        const std::vector<reference::McProbeResult> results = estimate(scene, probes, 256, next_event);
        double sum = 0.0, sum_sq = 0.0;
        for (size_t i = 0; i < probes.size(); ++i) {
            const double b = results[i].irradiance.x - direct[i];
            sum += b;
            sum_sq += b * b;
        }
        const double n = double(probes.size()), mean = sum / n;
        const double se = std::sqrt((sum_sq - sum * sum / n) / (n - 1.0) / n);
        MESSAGE("bounced irradiance: mean over the walls " << mean << " +- " << se << ", exact " << bounced);
        CHECK(se < 0.01 * bounced);
        CHECK(std::abs(mean - bounced) < 4.0 * se);
    }
}

TEST_CASE("reference MC punctual lights: the same answer for any thread count") {
    Scene scene;
    addInwardBox(scene, addMaterial(scene, Vec3(0.6f), Vec3(0.0f)), Vec3(0.0f), Vec3(2.0f, 1.5f, 1.0f));
    scene.lights.push_back(pointLight({0.7f, 0.6f, 0.45f}, 1.0f));
    scene.lights.push_back(spotLight({1.5f, 1.0f, 0.9f}, {0, 0, -1}, 0.3f, 0.6f));
    const std::vector<reference::McProbe> probes = {
        {DVec3(1, 0.75, 0), DVec3(0, 0, 1)}, {DVec3(0, 0.5, 0.5), DVec3(1, 0, 0)}, {DVec3(1.9, 1.5, 0.2), DVec3(0, -1, 0)}};
    reference::McOptions options;
    options.samples = 256;
    mctest::checkSameOnThreadCounts(reference::McBvh(scene), probes, options);
}

TEST_CASE("reference MC and radbake agree on a room lit by a point light and a spot light") {
    // Agreement, not an oracle: radbake's probes (what `radbake bake --probes` reads, at high
    // quality) against the reference, each within the reference's noise plus a few percent of
    // the solver's own error. Both take the direct light exactly; they differ in the bounces.
    // A grey room [0,4] x [0,3] x [0,2.5], a darker block on its floor, a white point light
    // and a tinted spot light aimed down at the block's top.
    Scene scene;
    addInwardBox(scene, addMaterial(scene, Vec3(0.6f), Vec3(0.0f)), Vec3(0.0f), Vec3(4.0f, 3.0f, 2.5f));
    addOutwardBox(scene, addMaterial(scene, Vec3(0.4f), Vec3(0.0f)), Vec3(2.4f, 1.0f, 0.0f), Vec3(3.2f, 1.8f, 0.8f));
    scene.lights.push_back(pointLight({1.0f, 1.5f, 2.0f}, 2.0f));
    scene.lights.push_back(spotLight({2.8f, 1.4f, 2.4f}, {0, 0, -1}, 0.35f, 0.6f));
    scene.lights.back().intensity = 6.0f;
    scene.lights.back().color = Vec3(1.0f, 0.8f, 0.6f);
    const std::vector<reference::McProbe> probes = {
        {DVec3(1.0, 1.5, 0.0), DVec3(0, 0, 1)},    // the floor under the point light
        {DVec3(0.5, 0.5, 0.0), DVec3(0, 0, 1)},    // the floor in a corner
        {DVec3(3.6, 1.4, 0.0), DVec3(0, 0, 1)},    // the floor in the block's shadow from the point light
        {DVec3(2.8, 2.4, 0.0), DVec3(0, 0, 1)},    // the floor at the spot's fall-off
        {DVec3(2.8, 1.4, 0.8), DVec3(0, 0, 1)},    // the block's top, in the beam
        {DVec3(2.4, 1.4, 0.4), DVec3(-1, 0, 0)},   // its side facing the point light
        {DVec3(3.2, 1.4, 0.4), DVec3(1, 0, 0)},    // its side facing away
        {DVec3(0.0, 1.5, 1.2), DVec3(1, 0, 0)},    // the wall beside the point light
        {DVec3(4.0, 1.5, 1.2), DVec3(-1, 0, 0)},   // the far wall
        {DVec3(2.0, 3.0, 1.0), DVec3(0, -1, 0)},   // the back wall
        {DVec3(1.0, 1.5, 2.5), DVec3(0, 0, -1)},   // the ceiling right above the point light
        {DVec3(3.5, 2.5, 2.5), DVec3(0, 0, -1)}};  // the ceiling in a corner
    reference::McOptions mc;
    mc.samples = 16384;
    mc.threads = 2;
    const std::vector<reference::McProbeResult> expected = reference::estimateProbes(reference::McBvh(scene), probes, mc);

    Diagnostics diagnostics;
    const std::optional<Solution> solution = solve(scene, SolverOptions::forQuality(Quality::High), diagnostics);
    REQUIRE(solution.has_value());
    const ReadoutOptions readout = ReadoutOptions::forQuality(Quality::High);
    for (size_t i = 0; i < probes.size(); ++i) {
        CAPTURE(i);
        const DVec3 h = probeIrradiance(*solution, readout, probes[i].position, probes[i].normal);
        MESSAGE("probe " << i << ": radbake " << h.x << " " << h.z << ", reference " << expected[i].irradiance.x
                         << " " << expected[i].irradiance.z << " +- " << expected[i].standard_error.x);
        for (int c = 0; c < 3; ++c) {
            const double mean = expected[i].irradiance[c], se = expected[i].standard_error[c];
            REQUIRE(mean > 0.0);
            CHECK(se < 0.02 * mean);
            CHECK(std::abs(h[c] - mean) <= 4.0 * se + 0.03 * mean);
        }
    }
}

TEST_CASE("radbake reads the scoped one-bounce floor as the reference and the form factor do") {
    // The floor case above, solved by radbake: rho E F above the floor when the sun's scope
    // holds it, nothing when it does not (a probe is lit by every light, but this one faces
    // away from the sun).
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.5f), Vec3(0.0f));
    addQuad(scene, grey, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    addQuad(scene, grey, {5, 5, 1}, {6, 5, 1}, {6, 6, 1}, {5, 6, 1});
    Light sun = directionalLight(Vec3(0, 0, -1), 2.0f);
    sun.scoped = true;
    sun.scope = {0};
    scene.lights.push_back(sun);
    const double exact = 0.5 * 2.0 * 4.0 * cornerFormFactor(1.0, 1.0, 0.5);
    const auto radbakeAbove = [](const Scene& s) {
        Diagnostics diagnostics;
        const std::optional<Solution> solution = solve(s, SolverOptions::forQuality(Quality::High), diagnostics);
        REQUIRE(solution.has_value());
        return probeIrradiance(*solution, ReadoutOptions::forQuality(Quality::High), DVec3(0, 0, 0.5), DVec3(0, 0, -1)).x;
    };
    CHECK(radbakeAbove(scene) == doctest::Approx(exact).epsilon(1e-3));
    scene.lights[0].scope = {1};
    CHECK(radbakeAbove(scene) == 0.0);
}
