// The Monte Carlo reference's sky and sun (tools/reference_mc.h) against closed forms over a
// black ground: the reference radbake's daylight is checked against must be right on its own.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "mc_test_support.h"
#include "reference_mc.h"
#include "scene/daylight.h"
#include "../radiosity/test_scenes.h"

namespace {

using namespace radbake;
using namespace radbake::test;

// A black ground z = 0, [-10, 10]^2, facing +z, under daylight oriented up +z.
Scene blackGround(const DaylightOptions& daylight) {
    Scene scene;
    addQuad(scene, addMaterial(scene, Vec3(0.0f), Vec3(0.0f)), {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0});
    DaylightOptions oriented = daylight;
    oriented.up = Vec3(0, 0, 1);
    addDaylight(scene, oriented);
    return scene;
}

reference::McProbeResult estimateAt(const Scene& scene, const DVec3& p, const DVec3& n, int samples) {
    reference::McOptions options;
    options.samples = samples;
    options.threads = 2;
    return reference::estimateProbes(reference::McBvh(scene), {{p, glm::normalize(n)}}, options)[0];
}

// Within four standard errors, which themselves are below `precision` of the value.
void checkEstimate(const reference::McProbeResult& r, double expected, double precision) {
    INFO("estimate " << r.irradiance.x << " +- " << r.standard_error.x << ", expected " << expected);
    CHECK(r.standard_error.x <= precision * expected);
    CHECK(std::abs(r.irradiance.x - expected) <= 4.0 * r.standard_error.x + 1e-9 * expected);
}

}  // namespace

TEST_CASE("reference MC daylight: a uniform sky gives pi L facing up, pi L / 2 on a vertical receiver") {
    DaylightOptions daylight;
    daylight.sky = SkyModel::Uniform;
    daylight.sky_radiance = 2.0;
    const Scene scene = blackGround(daylight);
    // Facing up every path leaves for the sky: no variance at all.
    const reference::McProbeResult up = estimateAt(scene, {0, 0, 1}, {0, 0, 1}, 256);
    CHECK(up.irradiance.x == doctest::Approx(2.0 * kPi).epsilon(1e-12));
    checkEstimate(estimateAt(scene, {0, 0, 1}, {1, 0, 0}, 65536), kPi, 0.01);
}

TEST_CASE("reference MC daylight: the CIE overcast sky, 7 pi Lz / 9 facing up") {
    DaylightOptions daylight;
    daylight.sky = SkyModel::Overcast;
    checkEstimate(estimateAt(blackGround(daylight), {0, 0, 1}, {0, 0, 1}, 65536), 7.0 * kPi / 9.0, 0.01);
}

TEST_CASE("reference MC daylight: a sun disc, E sin h on the ground and half of it on a shadow line") {
    DaylightOptions daylight;
    daylight.sun = SunPosition{0.0, 40.0};
    daylight.sun_irradiance = 3.0;
    daylight.sun_diameter_degrees = 4.0;
    Scene scene = blackGround(daylight);
    const double open = 3.0 * std::sin(40.0 * kPi / 180.0);
    checkEstimate(estimateAt(scene, {0, 0, 1e-3}, {0, 0, 1}, 4096), open, 0.01);
    // The sun at the zenith over a black plate x in [-5, 0] at z = 1: on the ground at x = 0, the
    // plate's edge halves the disc, and the cosine is symmetric about it.
    daylight.sun = SunPosition{0.0, 90.0};
    scene = blackGround(daylight);
    addQuad(scene, scene.meshes[0].material, {-5, -5, 1}, {0, -5, 1}, {0, 5, 1}, {-5, 5, 1});
    scene.meshes.back().solid = false;
    checkEstimate(estimateAt(scene, {0, 0, 1e-3}, {0, 0, 1}, 65536), 0.5 * 3.0, 0.01);
    CHECK(estimateAt(scene, {-0.1, 0, 1e-3}, {0, 0, 1}, 1024).irradiance.x == 0.0);
    CHECK(estimateAt(scene, {0.1, 0, 1e-3}, {0, 0, 1}, 1024).irradiance.x == doctest::Approx(3.0).epsilon(1e-3));
}

TEST_CASE("reference MC daylight: a black pane of transmission t over every sky direction passes t of the sky") {
    DaylightOptions daylight;
    daylight.sky = SkyModel::Uniform;
    Scene scene = blackGround(daylight);
    // A glass box x, y in [-1, 1], z in [0, 1] on the ground: a path to the sky crosses one pane.
    const uint32_t glass = addMaterial(scene, Vec3(0.0f), Vec3(0.0f));
    scene.materials[glass].transparency = 0.6f;
    addQuad(scene, glass, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1});
    addQuad(scene, glass, {-1, -1, 0}, {1, -1, 0}, {1, -1, 1}, {-1, -1, 1});
    addQuad(scene, glass, {-1, 1, 0}, {1, 1, 0}, {1, 1, 1}, {-1, 1, 1});
    addQuad(scene, glass, {-1, -1, 0}, {-1, 1, 0}, {-1, 1, 1}, {-1, -1, 1});
    addQuad(scene, glass, {1, -1, 0}, {1, 1, 0}, {1, 1, 1}, {1, -1, 1});
    for (size_t m = 1; m < scene.meshes.size(); ++m) scene.meshes[m].solid = false;
    checkEstimate(estimateAt(scene, {0, 0, 0.3}, {0, 0, 1}, 65536), 0.6 * kPi, 0.01);
    // A sun's shadow segment keeps t of it, deterministically.
    daylight.sky = SkyModel::None;
    daylight.sun = SunPosition{0.0, 60.0};
    daylight.sun_diameter_degrees = 0.0;
    Scene sunny = blackGround(daylight);
    sunny.materials = scene.materials;
    for (size_t m = 1; m < scene.meshes.size(); ++m) sunny.meshes.push_back(scene.meshes[m]);
    const reference::McProbeResult lit = estimateAt(sunny, {0, 0, 0.3}, {0, 0, 1}, 64);
    CHECK(lit.irradiance.x == doctest::Approx(0.6 * 25.0 * std::sin(kPi / 3)).epsilon(1e-6));
}

TEST_CASE("reference MC daylight: a Background's sky ramp, pi L (zenith + horizon) / 2 facing up") {
    Scene scene = blackGround({});
    scene.sky.model = SkyModel::Background;
    scene.sky.up = Vec3(0, 0, 1);
    scene.sky.radiance = Vec3(2.0f);
    scene.sky.background.sky_color = {Vec3(0.2f), Vec3(1.0f)};
    scene.sky.background.sky_angle = {1.5707963f};
    checkEstimate(estimateAt(scene, {0, 0, 1}, {0, 0, 1}, 65536), kPi * 2.0 * 0.6, 0.01);
}
