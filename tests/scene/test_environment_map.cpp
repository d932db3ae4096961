// Environment maps (scene/environment_map.h): the orientation the README states, averages that
// keep a constant map constant, and suns taken out without losing or adding light.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "scene/daylight.h"
#include "scene/environment_map.h"

using namespace radbake;

namespace {

// A map of `width` x width / 2 texels of radiance f(x, y) (texel indices).
template <class F>
EnvironmentMap mapOf(int width, F f) {
    const int height = width / 2;
    std::vector<float> rgb;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const DVec3 value = f(x, y);
            rgb.insert(rgb.end(), {float(value.x), float(value.y), float(value.z)});
        }
    return makeEnvironmentMap(width, height, std::move(rgb), "test.exr");
}

}  // namespace

TEST_CASE("an environment map's orientation: top row the zenith, centre column azimuth 0, azimuth to the right") {
    // Each texel holds its own indices.
    const EnvironmentMap map = mapOf(36, [](int x, int y) { return DVec3(x, y, 0); });
    for (const Vec3 up : {Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(-1, 0, 0)}) {
        const MapFrame frame = mapFrame(up);
        INFO("up " << upAxisName(up));
        CHECK(mapRadiance(map, frame, DVec3(up)).y == 0.0);
        CHECK(mapRadiance(map, frame, -DVec3(up)).y == 17.0);
        // --sun's azimuth and elevation land in the texel of the same angles.
        for (const double azimuth : {-175.0, -93.0, 3.0, 7.0, 97.0, 171.0})
            for (const double elevation : {-63.0, -5.0, 5.0, 42.0}) {
                const DVec3 at = mapRadiance(map, frame, sunDirection({azimuth, elevation}, up));
                CHECK(at.x == std::floor((azimuth + 180.0) / 10.0));
                CHECK(at.y == std::floor((90.0 - elevation) / 10.0));
            }
    }
}

TEST_CASE("an environment map's patch averages: a constant map reads its constant; a half-lit map splits at the horizon") {
    const EnvironmentMap constant = mapOf(64, [](int, int) { return DVec3(0.25, 0.5, 4.0); });
    const MapFrame frame = mapFrame(Vec3(0, 1, 0));
    for (const double solid_angle : {1e-6, 0.01, 0.3, 3.0, 4.0 * kPi})
        for (const DVec3& d : {DVec3(0, 1, 0), DVec3(0.3, 0.9, 0.1), DVec3(1, 0, 0), DVec3(-1, -0.01, 0), DVec3(0, -1, 0)}) {
            const DVec3 mean = mapRadianceOver(constant, frame, glm::normalize(d), solid_angle);
            CHECK(glm::length(mean - DVec3(0.25, 0.5, 4.0)) < 1e-8);
        }
    CHECK(glm::length(mapTotal(constant) - 4.0 * kPi * DVec3(0.25, 0.5, 4.0)) < 1e-9);
    // Lit above the horizon only: a patch centred on the horizon reads half.
    const EnvironmentMap half = mapOf(64, [](int, int y) { return DVec3(y < 16 ? 1.0 : 0.0); });
    CHECK(mapRadianceOver(half, frame, DVec3(1, 0, 0), 0.01).x == doctest::Approx(0.5).epsilon(1e-6));
    CHECK(mapRadianceOver(half, frame, DVec3(0, 1, 0), 0.01).x == doctest::Approx(1.0));
    CHECK(mapTotal(half).x == doctest::Approx(2.0 * kPi));
}

TEST_CASE("suns drawn in an environment map are taken out whole: map and suns hold what the map held") {
    const MapFrame frame = mapFrame(Vec3(0, 1, 0));
    // A sky brightening towards the zenith, a small sun (4 x 3 texels) at azimuth about 30,
    // elevation about 40, and a broad bright patch that is not a sun.
    EnvironmentMap map = mapOf(360, [](int x, int y) {
        if (x >= 209 && x < 213 && y >= 49 && y < 52) return DVec3(5e4, 4e4, 3e4);
        if (x >= 10 && x < 60 && y >= 60 && y < 80) return DVec3(3.0);
        return y < 90 ? DVec3(0.2 + 0.8 * (90 - y) / 90.0) : DVec3(0.05);
    });
    const DVec3 before = mapTotal(map);
    const std::vector<MapSun> suns = extractSuns(map, frame);
    REQUIRE(suns.size() == 1);
    CHECK(suns[0].texels == 12);
    const DVec3 after = mapTotal(map) + suns[0].irradiance;
    for (int c = 0; c < 3; ++c) CHECK(after[c] == doctest::Approx(before[c]).epsilon(1e-9));
    // Towards the texels' centre: columns 209 to 212 about 211 (azimuth 211 - 180), rows 49 to 51
    // about 50.5 (elevation 90 - 50.5).
    const DVec3 expected = sunDirection({31.0, 39.5}, Vec3(0, 1, 0));
    CHECK(std::acos(std::min(1.0, glm::dot(suns[0].direction, expected))) < 0.2 * kPi / 180.0);
    // A disc of the texels' solid angle: about 3.5 degrees across.
    CHECK(suns[0].angular_diameter == doctest::Approx(3.5 * kPi / 180.0).epsilon(0.1));
    // Its colour kept: what is left in the texels is the sun's colour too.
    CHECK(suns[0].irradiance.y / suns[0].irradiance.x == doctest::Approx(0.8));
    // The broad patch stays in the map, brighter than the sky around it.
    CHECK(mapRadiance(map, frame, sunDirection({-145.0, 20.0}, Vec3(0, 1, 0))).x == doctest::Approx(3.0));
    // Nothing left to take.
    CHECK(extractSuns(map, frame).empty());
}
