// --sky FILE.exr: an equirectangular environment map lights the scene, against closed forms and
// against the brute-force integral of the map's texels (a sun drawn in it and a plate's shadow
// included).
#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/exr_io.h"
#include "daylight_scenes.h"

using namespace daylight_test;

namespace {

// A speck far away: the scene needs a surface, the probes at the origin see the whole sphere.
const std::string kSpeck = quad({{100, 100, 100}, {100, 100, 100.1}, {100.1, 100, 100.1}, {100.1, 100, 100}}, 0.0);

struct TestMap {
    int width = 0, height = 0;
    std::vector<float> rgb;
    DVec3 at(int x, int y) const {
        const float* t = &rgb[(size_t(y) * width + x) * 3];
        return DVec3(t[0], t[1], t[2]);
    }
};

// `width` x width / 2 texels; f(azimuth, elevation) in degrees at each texel's centre, azimuth 0 at
// the centre column (as scene/environment_map.h lays a map out).
TestMap paint(int width, const std::function<DVec3(double, double)>& f) {
    TestMap map{width, width / 2, {}};
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < width; ++x) {
            const DVec3 v = f(360.0 * (x + 0.5) / width - 180.0, 90.0 - 180.0 * (y + 0.5) / map.height);
            map.rgb.insert(map.rgb.end(), {float(v.x), float(v.y), float(v.z)});
        }
    return map;
}

std::string writeMap(const TempDir& dir, const std::string& name, const TestMap& map) {
    RgbImage image;
    image.width = map.width, image.height = map.height, image.rgb = map.rgb, image.half = false;
    Diagnostics diagnostics;
    const std::string path = (dir.path / name).string();
    REQUIRE(writeExr(path, image, ExrWriteOptions{.use_float = true}, diagnostics));
    return path;
}

// Direction of map coordinates (x, y) (texel units) for up +y: azimuth from +x towards +z.
DVec3 direction(const TestMap& map, double x, double y) {
    const double azimuth = 2.0 * kPi * x / map.width - kPi, elevation = 0.5 * kPi - kPi * y / map.height;
    return {std::cos(elevation) * std::cos(azimuth), std::sin(elevation), std::cos(elevation) * std::sin(azimuth)};
}

// The irradiance the map's texels give a point with normal n, by brute force: every texel cut
// into 8 x 8 pieces, each its solid angle times its cosine, unless `blocked` says its direction is.
DVec3 bruteForce(const TestMap& map, const DVec3& n, const std::function<bool(const DVec3&)>& blocked) {
    constexpr int kCuts = 8;
    DVec3 sum(0.0);
    for (int y = 0; y < map.height; ++y)
        for (int sy = 0; sy < kCuts; ++sy) {
            const double top = y + double(sy) / kCuts, bottom = top + 1.0 / kCuts;
            const double e0 = 0.5 * kPi - kPi * top / map.height, e1 = 0.5 * kPi - kPi * bottom / map.height;
            const double omega = 2.0 * kPi / (map.width * kCuts) * (std::sin(e0) - std::sin(e1));
            for (int x = 0; x < map.width; ++x) {
                const DVec3 radiance = map.at(x, y);
                if (radiance == DVec3(0.0)) continue;
                for (int sx = 0; sx < kCuts; ++sx) {
                    const DVec3 d = direction(map, x + (sx + 0.5) / kCuts, 0.5 * (top + bottom));
                    const double c = glm::dot(d, n);
                    if (c > 0.0 && !blocked(d)) sum += radiance * (omega * c);
                }
            }
        }
    return sum;
}

Bake bakeWithMap(const TempDir& dir, const std::string& body, const std::string& map_path,
                 const std::vector<Probe>& probes, double sky_radiance = 1.0, Quality quality = Quality::Medium) {
    DaylightOptions daylight;
    daylight.sky = SkyModel::Map;
    daylight.sky_map = map_path;
    daylight.sky_radiance = sky_radiance;
    return bakeWith(dir, body, daylight, probes, quality);
}

}  // namespace

TEST_CASE("an environment map of a sky over a ground: pi L up, pi L down, their mean sideways, times --sky-radiance") {
    TempDir dir;
    const DVec3 sky(1.0, 0.5, 0.25), ground(0.1, 0.2, 0.3);
    const std::string path =
        writeMap(dir, "halves.exr", paint(128, [&](double, double elevation) { return elevation > 0 ? sky : ground; }));
    const std::vector<Probe> probes = {probe({0, 0, 0}, {0, 1, 0}), probe({0, 0, 0}, {0, -1, 0}),
                                       probe({0, 0, 0}, {1, 0, 0}), probe({0, 0, 0}, {0.3, 0, -1})};
    for (const Quality quality : {Quality::Draft, Quality::Medium, Quality::High}) {
        INFO("quality " << toString(quality));
        const Bake baked = bakeWithMap(dir, kSpeck, path, probes, 2.0, quality);
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c);
            checkWithin(baked.probe_irradiance[0][c], 2.0 * kPi * sky[c], 0.01, "facing up");
            checkWithin(baked.probe_irradiance[1][c], 2.0 * kPi * ground[c], 0.01, "facing down");
            checkWithin(baked.probe_irradiance[2][c], kPi * (sky[c] + ground[c]), 0.01, "facing +x");
            checkWithin(baked.probe_irradiance[3][c], kPi * (sky[c] + ground[c]), 0.01, "facing sideways");
        }
    }
}

TEST_CASE("an environment map with a sun drawn in it: every side of a probe and a plate's shadow against the map's integral") {
    TempDir dir;
    // An overcast-like sky over a dark ground, a green patch low in the west and a sun of 3
    // degrees at azimuth 30, elevation 40, thousands of times the sky.
    const DVec3 sun_towards = sunDirection({30.0, 40.0}, Vec3(0, 1, 0));
    const TestMap map = paint(512, [&](double azimuth, double elevation) {
        const DVec3 d = sunDirection({azimuth, elevation}, Vec3(0, 1, 0));
        if (std::acos(std::min(1.0, glm::dot(d, sun_towards))) < 1.5 * kDegree) return DVec3(2e4, 1.8e4, 1.5e4);
        if (azimuth > -130 && azimuth < -110 && elevation > 5 && elevation < 15) return DVec3(0.0, 2.0, 0.0);
        if (elevation < 0) return DVec3(0.1, 0.08, 0.05);
        return DVec3((1.0 + 2.0 * std::sin(elevation * kDegree)) / 3.0);
    });
    const std::string path = writeMap(dir, "sunny.exr", map);
    // A black plate 0.3 across, a metre from a probe towards the sun, square to it: it shades the
    // probe from the sun and a patch of sky.
    const DVec3 shaded(5, 0, 5);
    DVec3 t, b;
    t = glm::normalize(glm::cross(sun_towards, DVec3(0, 1, 0)));
    b = glm::cross(t, sun_towards);
    const DVec3 centre = shaded + sun_towards;
    const double half = 0.15;
    const std::string plate =
        quad({centre - t * half - b * half, centre + t * half - b * half, centre + t * half + b * half,
              centre - t * half + b * half},
             0.0, true);
    const auto hitsPlate = [&](const DVec3& d) {
        const double along = glm::dot(d, sun_towards);
        if (!(along > 0.0)) return false;
        const DVec3 at = d * (1.0 / along) - sun_towards;
        return std::abs(glm::dot(at, t)) <= half && std::abs(glm::dot(at, b)) <= half;
    };
    const std::vector<DVec3> normals = {{0, 1, 0},  {1, 0, 0},  {-1, 0, 0}, {0, 0, 1},
                                        {0, 0, -1}, {1, 1, 1},  {0, -1, 0}, sun_towards};
    std::vector<Probe> probes;
    for (const DVec3& n : normals) probes.push_back(probe({0, 0, 0}, n));
    probes.push_back(probe(shaded, {0, 1, 0}));
    const Bake baked = bakeWithMap(dir, kSpeck + plate, path, probes);
    const auto open = [](const DVec3&) { return false; };
    for (size_t i = 0; i < probes.size(); ++i) {
        const bool under_plate = i + 1 == probes.size();
        const DVec3 expected = bruteForce(map, probes[i].normal, under_plate ? std::function<bool(const DVec3&)>(hitsPlate)
                                                                             : std::function<bool(const DVec3&)>(open));
        INFO("probe " << i << std::string(under_plate ? " (under the plate)" : ""));
        for (int c = 0; c < 3; ++c) checkWithin(baked.probe_irradiance[i][c], expected[c], 0.01, "channel");
    }
    // The plate takes the sun: the shaded probe gets far less than the open one facing up.
    CHECK(baked.probe_irradiance.back().x < 0.5 * baked.probe_irradiance[0].x);
}

TEST_CASE("an environment map that is missing or holds a NaN is a located error; a negative texel is counted") {
    TempDir dir;
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.lightmaps.enabled = false;
    options.import.daylight.sky = SkyModel::Map;
    const std::string scene = testfs::writeText(dir, "plain.wrl", "#VRML V2.0 utf8\n" + kSpeck);
    const auto bakeSaying = [&](const std::string& map_path, std::string& said) {
        options.import.daylight.sky_map = map_path;
        Progress progress(false);
        Diagnostics diagnostics;
        diagnostics.sink = [&](const Diagnostic& d) { said += formatDiagnostic(d) + "\n"; };
        return bake(scene, options, progress, diagnostics);
    };
    std::string said;
    CHECK(std::string(toString(bakeSaying((dir.path / "absent.exr").string(), said).status)) != "ok");
    CHECK(said.find("absent.exr") != std::string::npos);
    CHECK(said.find("environment map") != std::string::npos);

    TestMap nan = paint(16, [](double, double) { return DVec3(1.0); });
    nan.rgb[3 * 20 + 1] = std::numeric_limits<float>::quiet_NaN();
    said.clear();
    CHECK(std::string(toString(bakeSaying(writeMap(dir, "nan.exr", nan), said).status)) != "ok");
    CHECK(said.find("nan.exr") != std::string::npos);
    CHECK(said.find("texel (4, 1)") != std::string::npos);

    TestMap negative = paint(16, [](double, double) { return DVec3(1.0); });
    negative.rgb[5] = -0.5f, negative.rgb[7] = -0.25f;
    said.clear();
    CHECK(std::string(toString(bakeSaying(writeMap(dir, "negative.exr", negative), said).status)) == "ok");
    CHECK(said.find("2 negative channel values read as 0") != std::string::npos);
}
