// Daylight (issue 30): a sky and a sun given on the command line light the scene, against closed
// forms over a black ground (nothing comes from below the horizon).
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "radbake.h"
#include "../export/temp_files.h"
#include "daylight_scenes.h"
#include "reference_mc.h"

using namespace radbake;
using testfs::TempDir;

using namespace daylight_test;

namespace {

// Form factor from a point to a parallel rectangle [0, a] x [0, b] at height c over the point,
// the point under its corner (the standard closed form).
double cornerFormFactor(double a, double b, double c) {
    const double x = a / c, y = b / c, sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
    return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPi);
}

// A two-sided grey (rho 0.6) face from `origin` along du and dv, a 4 x 4 grid of quads.
std::string tiledFace(const DVec3& origin, const DVec3& du, const DVec3& dv) {
    std::string points, indices;
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 4; ++i) {
            const DVec3 p = origin + du * (i / 4.0) + dv * (j / 4.0);
            points += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + ", ";
        }
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const int a = j * 5 + i;
            indices += std::to_string(a) + " " + std::to_string(a + 1) + " " + std::to_string(a + 6) + " " +
                       std::to_string(a + 5) + " -1 ";
        }
    return "Shape { " + material(0.6) + " geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ " + points +
           "] } coordIndex [ " + indices + "] } }\n";
}

// The cube [0, 1]^3 of six separate tiled faces; with a slit, its x = 1 face is two halves
// leaving a vertical gap `slit` wide about z = 0.5.
std::string tiledBox(double slit) {
    std::string box;
    box += tiledFace({0, 0, 0}, {1, 0, 0}, {0, 0, 1});
    box += tiledFace({0, 1, 0}, {1, 0, 0}, {0, 0, 1});
    box += tiledFace({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    box += tiledFace({0, 0, 1}, {1, 0, 0}, {0, 1, 0});
    box += tiledFace({0, 0, 0}, {0, 1, 0}, {0, 0, 1});
    if (slit == 0.0) return box + tiledFace({1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    const double half = 0.5 - 0.5 * slit;
    return box + tiledFace({1, 0, 0}, {0, 1, 0}, {0, 0, half}) + tiledFace({1, 0, 1 - half}, {0, 1, 0}, {0, 0, half});
}

}  // namespace

TEST_CASE("an open uniform sky over a black ground: pi L on a horizontal receiver, pi L / 2 on a vertical one") {
    TempDir dir;
    DaylightOptions daylight;
    daylight.sky = SkyModel::Uniform;
    daylight.sky_radiance = 2.0;
    const std::vector<Probe> probes = {probe({0, 0.5, 0}, {0, 1, 0}), probe({0, 0.5, 0}, {1, 0, 0}),
                                       probe({3, 0.2, -7}, {0, 0, -1}), probe({0, 0.5, 0}, {1, 1, 0})};
    for (const Quality quality : {Quality::Draft, Quality::Medium, Quality::High}) {
        const Bake baked = bakeWith(dir, kBlackGround, daylight, probes, quality);
        INFO("quality " << toString(quality));
        checkWithin(baked.probe_irradiance[0].x, kPi * 2.0, 0.01, "horizontal");
        checkWithin(baked.probe_irradiance[1].x, kPi * 2.0 / 2, 0.01, "vertical");
        checkWithin(baked.probe_irradiance[2].z, kPi * 2.0 / 2, 0.01, "vertical, elsewhere");
        // Tilted 45 degrees up: pi L (1 + cos 45) / 2.
        checkWithin(baked.probe_irradiance[3].y, kPi * 2.0 * (1 + std::sqrt(0.5)) / 2, 0.01, "tilted");
    }
}

TEST_CASE("the CIE overcast sky: 7 pi Lz / 9 on a horizontal receiver, (pi / 6 + 4 / 9) Lz on a vertical one") {
    TempDir dir;
    DaylightOptions daylight;
    daylight.sky = SkyModel::Overcast;
    daylight.sky_radiance = 3.0;
    const Bake baked =
        bakeWith(dir, kBlackGround, daylight, {probe({0, 0.5, 0}, {0, 1, 0}), probe({1, 0.5, 2}, {0, 0, 1})});
    checkWithin(baked.probe_irradiance[0].x, 7 * kPi / 9 * 3.0, 0.01, "horizontal");
    checkWithin(baked.probe_irradiance[1].x, (kPi / 6 + 4.0 / 9) * 3.0, 0.01, "vertical");
}

TEST_CASE("the up axis turns the sky: up +z over a black ground x, y") {
    TempDir dir;
    DaylightOptions daylight;
    daylight.sky = SkyModel::Uniform;
    daylight.up = Vec3(0, 0, 1);
    const std::string ground = quad({{-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0}}, 0.0);
    const Bake baked = bakeWith(dir, ground, daylight, {probe({0, 0, 0.5}, {0, 0, 1}), probe({0, 0, 0.5}, {0, 1, 0})});
    checkWithin(baked.probe_irradiance[0].x, kPi, 0.01, "horizontal");
    checkWithin(baked.probe_irradiance[1].x, kPi / 2, 0.01, "vertical");
}

TEST_CASE("a sun of irradiance E at elevation h: E sin h on open ground, E facing it, its azimuth from +x towards +z") {
    TempDir dir;
    const double elevation = 30.0, azimuth = 90.0, e = 2.0;
    // Towards the sun: azimuth 90 is +z for up +y.
    const DVec3 towards(0.0, std::sin(elevation * kDegree), std::cos(elevation * kDegree));
    for (const double diameter : {0.0, 0.53, 5.0}) {
        DaylightOptions daylight;
        daylight.sun = SunPosition{azimuth, elevation};
        daylight.sun_irradiance = e;
        daylight.sun_diameter_degrees = diameter;
        INFO("sun diameter " << diameter << " degrees");
        const Bake baked = bakeWith(dir, kBlackGround, daylight,
                                    {probe({0, 0.5, 0}, {0, 1, 0}), probe({0, 0.5, 0}, towards),
                                     probe({0, 0.5, 0}, {1, 0, 0}), probe({0, 0.5, 0}, {0, 0, -1})});
        checkWithin(baked.probe_irradiance[0].x, e * std::sin(elevation * kDegree), 0.01, "ground");
        checkWithin(baked.probe_irradiance[1].x, e, 0.01, "facing the sun");
        // A wall facing +x sees the sun edge on (half its disc at most); one facing away none.
        CHECK(baked.probe_irradiance[2].x <= e * std::sin(0.5 * diameter * kDegree) + 1e-12);
        CHECK(baked.probe_irradiance[3].x == 0.0);
    }
}

TEST_CASE("a sun's penumbra: half the light on the shadow line of a straight edge") {
    TempDir dir;
    // The sun at the zenith over a black plate x in [-5, 0] at y = 1: on the ground at x = 0 the
    // plate's edge halves the disc, and the cosine is symmetric about it; the penumbra is
    // 2 tan(1 degree) wide.
    const std::string plate = quad({{-5, 1, -5}, {0, 1, -5}, {0, 1, 5}, {-5, 1, 5}}, 0.0, true);
    DaylightOptions daylight;
    daylight.sun = SunPosition{0.0, 90.0};
    daylight.sun_irradiance = 1.0;
    daylight.sun_diameter_degrees = 2.0;
    const Bake baked = bakeWith(dir, kBlackGround + plate, daylight,
                                {probe({0, 0.001, 0.3}, {0, 1, 0}), probe({-0.1, 0.001, 0}, {0, 1, 0}),
                                 probe({0.1, 0.001, 0}, {0, 1, 0}), probe({-0.01, 0.001, 0}, {0, 1, 0})});
    checkWithin(baked.probe_irradiance[0].x, 0.5, 1e-9, "on the shadow line");
    CHECK(baked.probe_irradiance[1].x == 0.0);
    checkWithin(baked.probe_irradiance[2].x, 1.0, 1e-9, "out of the shadow");
    // In the penumbra: between the two.
    CHECK(baked.probe_irradiance[3].x > 0.0);
    CHECK(baked.probe_irradiance[3].x < 0.5);
}

TEST_CASE("a square opening in a black roof: its form factor times pi L") {
    TempDir dir;
    // A black closed room x, z in [-1, 1], y in [0, 1], with a square hole of side 1.2 in its roof.
    const double h = 0.6;
    std::string room = kBlackGround;
    room += quad({{-1, 0, -1}, {-1, 1, -1}, {-1, 1, 1}, {-1, 0, 1}}, 0.0, true);
    room += quad({{1, 0, -1}, {1, 1, -1}, {1, 1, 1}, {1, 0, 1}}, 0.0, true);
    room += quad({{-1, 0, -1}, {1, 0, -1}, {1, 1, -1}, {-1, 1, -1}}, 0.0, true);
    room += quad({{-1, 0, 1}, {1, 0, 1}, {1, 1, 1}, {-1, 1, 1}}, 0.0, true);
    room += quad({{-1, 1, h}, {1, 1, h}, {1, 1, 1}, {-1, 1, 1}}, 0.0, true);
    room += quad({{-1, 1, -1}, {1, 1, -1}, {1, 1, -h}, {-1, 1, -h}}, 0.0, true);
    room += quad({{-1, 1, -h}, {-h, 1, -h}, {-h, 1, h}, {-1, 1, h}}, 0.0, true);
    room += quad({{h, 1, -h}, {1, 1, -h}, {1, 1, h}, {h, 1, h}}, 0.0, true);
    DaylightOptions daylight;
    daylight.sky = SkyModel::Uniform;
    const double y = 0.25;
    const Bake baked = bakeWith(dir, room, daylight, {probe({0, y, 0}, {0, 1, 0}), probe({0.3, y, 0.2}, {0, 1, 0})});
    const double c = 1.0 - y;
    checkWithin(baked.probe_irradiance[0].x, kPi * 4 * cornerFormFactor(h, h, c), 0.01, "under the centre");
    // Off centre: four corner rectangles around the point's foot.
    const double x0 = 0.3, z0 = 0.2;
    const double off = cornerFormFactor(h - x0, h - z0, c) + cornerFormFactor(h + x0, h - z0, c) +
                       cornerFormFactor(h - x0, h + z0, c) + cornerFormFactor(h + x0, h + z0, c);
    checkWithin(baked.probe_irradiance[1].x, kPi * off, 0.01, "off centre");
}

TEST_CASE("a closed box of separate tiled meshes under a sky and a sun is exactly dark inside at every quality") {
    TempDir dir;
    // Six two-sided faces of a cube [0, 1]^3, each its own 4 x 4 grid of quads.
    const std::string box = tiledBox(0.0);
    DaylightOptions daylight;
    daylight.sky = SkyModel::Overcast;
    daylight.sun = SunPosition{30.0, 50.0};
    const std::vector<Probe> probes = {probe({0.5, 0.5, 0.5}, {0, 1, 0}), probe({0.5, 0.5, 0.5}, {0, -1, 0}),
                                       probe({0.1, 0.05, 0.9}, {1, 1, -1}), probe({0.5, 1.5, 0.5}, {0, 1, 0})};
    for (const Quality quality : {Quality::Draft, Quality::Medium, Quality::High, Quality::Reference}) {
        INFO("quality " << toString(quality));
        const Bake baked = bakeWith(dir, box, daylight, probes, quality);
        for (size_t i = 0; i < 3; ++i) CHECK(baked.probe_irradiance[i] == DVec3(0.0));
        CHECK(baked.probe_irradiance[3].x > 1.0);  // above the box: lit
        // Every vertex of a side facing into the box is 0; the outside is lit.
        const Scene& scene = *baked.scene;
        size_t inside = 0, lit_outside = 0;
        for (size_t m = 0; m < scene.meshes.size(); ++m) {
            const Mesh& mesh = scene.meshes[m];
            const UVec3& t = mesh.triangles.front();
            const DVec3 a(mesh.positions[t.x]), n = glm::cross(DVec3(mesh.positions[t.y]) - a, DVec3(mesh.positions[t.z]) - a);
            const bool faces_in = glm::dot(n, DVec3(0.5) - a) > 0.0;
            for (const Vec3& value : baked.vertices.values[m]) {
                if (faces_in) {
                    CHECK(value == Vec3(0.0f));
                    ++inside;
                } else {
                    lit_outside += value.x > 0.0f ? 1 : 0;
                }
            }
        }
        CHECK(inside == 6 * 25);
        CHECK(lit_outside > 6 * 20);
    }
}

TEST_CASE("the closed box with a 1 cm slit in a wall: probes facing the slit against reference_mc") {
    TempDir dir;
    // The slit is vertical, in the x = 1 wall, 1 cm wide; the sun stands behind the box (azimuth
    // 180, its light travelling towards +x), so only the sky comes in: seen from the box's centre
    // the slit is 1.1 degrees wide, from the far wall 0.6, far below the top samples' spacing.
    // What comes in is 1e-4 of what the outside gets: the interior's bounce must converge too.
    DaylightOptions daylight;
    daylight.sky = SkyModel::Overcast;
    daylight.sun = SunPosition{180.0, 35.0};
    const std::vector<Probe> probes = {probe({0.5, 0.5, 0.5}, {1, 0, 0}), probe({0.02, 0.6, 0.45}, {1, 0, 0})};
    const Bake baked = bakeWith(dir, tiledBox(0.01), daylight, probes);
    // The light through the slit: its area times the vertical irradiance under the overcast sky,
    // (pi / 6 + 4 / 9) Lz, all of it reaching the inside's surfaces.
    double inside = 0.0;
    for (const Element& e : baked.solution->elements)
        if (e.isLeaf() && glm::dot(e.normal, e.centroid - DVec3(0.5)) < 0.0 && glm::all(glm::greaterThan(e.centroid, DVec3(-1e-3))) &&
            glm::all(glm::lessThan(e.centroid, DVec3(1.001))))
            inside += e.area * e.emission.x / e.reflectance.x;
    checkWithin(inside, 0.01 * (kPi / 6 + 4.0 / 9), 0.05, "the power the inside gets");
    reference::McOptions mc;
    mc.samples = 1 << 21;
    mc.threads = 2;
    std::vector<reference::McProbe> points;
    for (const Probe& p : probes) points.push_back({p.position, p.normal});
    const std::vector<reference::McProbeResult> ref = reference::estimateProbes(reference::McBvh(*baked.scene), points, mc);
    for (size_t i = 0; i < probes.size(); ++i) {
        const double got = baked.probe_irradiance[i].x, want = ref[i].irradiance.x, se = ref[i].standard_error.x;
        INFO("probe " << i << ": radbake " << got << ", reference " << want << " +- " << se);
        CHECK(se < 0.02 * want);  // 5 % is then 2.5 standard errors away at least
        CHECK(std::abs(got - want) < 0.05 * want);
    }
}

TEST_CASE("daylight options: parsed, checked and named as the README says") {
    CHECK(parseSkyModel("overcast") == SkyModel::Overcast);
    CHECK(!parseSkyModel("cloudy"));
    CHECK(parseUpAxis("-z") == Vec3(0, 0, -1));
    CHECK(!parseUpAxis("z"));
    CHECK(upAxisName(Vec3(0, -1, 0)) == "-y");
    const std::optional<SunPosition> sun = parseSunPosition("135, 20.5");
    REQUIRE(sun);
    CHECK(sun->azimuth_degrees == 135.0);
    CHECK(sun->elevation_degrees == 20.5);
    CHECK(!parseSunPosition("10,95"));
    CHECK(!parseSunPosition("nan,10"));
    CHECK(!parseSunPosition("10"));
    // Azimuth 0 towards the first axis that is not up, 90 towards the other (negated for a negative up).
    const auto near = [](const DVec3& a, const DVec3& b) { return glm::length(a - b) < 1e-12; };
    CHECK(near(sunDirection({0, 0}, Vec3(0, 1, 0)), DVec3(1, 0, 0)));
    CHECK(near(sunDirection({90, 0}, Vec3(0, 1, 0)), DVec3(0, 0, 1)));
    CHECK(near(sunDirection({90, 0}, Vec3(0, -1, 0)), DVec3(0, 0, -1)));
    CHECK(near(sunDirection({90, 0}, Vec3(0, 0, 1)), DVec3(0, 1, 0)));
    CHECK(near(sunDirection({0, 0}, Vec3(1, 0, 0)), DVec3(0, 1, 0)));
    CHECK(near(sunDirection({0, 90}, Vec3(0, 0, -1)), DVec3(0, 0, -1)));
    DaylightOptions bad;
    bad.sky_radiance = -1;
    CHECK(!checkDaylight(bad).empty());
    CHECK(checkDaylight(DaylightOptions{}).empty());
}

TEST_CASE("a room lit by sky and sun through a window, open and glazed: radbake's probes against reference_mc") {
    TempDir dir;
    // A grey room x, z in [0, 4], y in [0, 2.5], faces inwards, one-sided, each wall tiled; a window
    // z in [1.5, 2.5], y in [0.8, 1.8] in its x = 4 wall.
    const double rho = 0.6;
    auto wall = [&](const std::vector<DVec3>& corners) { return quad(corners, rho); };
    std::string room;
    for (int i = 0; i < 2; ++i)
        for (int k = 0; k < 2; ++k) {
            const double x0 = 2.0 * i, z0 = 2.0 * k;
            room += wall({{x0, 0, z0}, {x0, 0, z0 + 2}, {x0 + 2, 0, z0 + 2}, {x0 + 2, 0, z0}});          // floor, up
            room += wall({{x0, 2.5, z0}, {x0 + 2, 2.5, z0}, {x0 + 2, 2.5, z0 + 2}, {x0, 2.5, z0 + 2}});  // ceiling, down
        }
    room += wall({{0, 0, 0}, {4, 0, 0}, {4, 2.5, 0}, {0, 2.5, 0}});  // z = 0, facing +z
    room += wall({{0, 0, 4}, {0, 2.5, 4}, {4, 2.5, 4}, {4, 0, 4}});  // z = 4, facing -z
    room += wall({{0, 0, 0}, {0, 2.5, 0}, {0, 2.5, 4}, {0, 0, 4}});  // x = 0, facing +x
    // x = 4, facing -x, around the window.
    room += wall({{4, 0, 0}, {4, 0, 4}, {4, 0.8, 4}, {4, 0.8, 0}});
    room += wall({{4, 1.8, 0}, {4, 1.8, 4}, {4, 2.5, 4}, {4, 2.5, 0}});
    room += wall({{4, 0.8, 0}, {4, 0.8, 1.5}, {4, 1.8, 1.5}, {4, 1.8, 0}});
    room += wall({{4, 0.8, 2.5}, {4, 0.8, 4}, {4, 1.8, 4}, {4, 1.8, 2.5}});
    // The glazed window: a pane of transmission 0.7 and reflectance 0.2 (0.06 of what meets it).
    const std::string glass = "Shape { appearance Appearance { material Material { diffuseColor 0.2 0.2 0.2 "
                              "transparency 0.7 } } geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ "
                              "4 0.8 1.5, 4 0.8 2.5, 4 1.8 2.5, 4 1.8 1.5 ] } coordIndex [ 0 1 2 3 -1 ] } }\n";
    DaylightOptions daylight;
    daylight.sky = SkyModel::Overcast;
    daylight.sky_radiance = 10.0;
    daylight.sun = SunPosition{0.0, 25.0};
    daylight.sun_irradiance = 100.0;
    const std::vector<Probe> probes = {
        probe({2.5, 0.01, 2.0}, {0, 1, 0}),  probe({1.0, 0.01, 1.0}, {0, 1, 0}), probe({3.0, 0.01, 0.5}, {0, 1, 0}),
        probe({2.0, 2.49, 2.0}, {0, -1, 0}), probe({0.01, 1.2, 2.0}, {1, 0, 0}), probe({2.0, 1.2, 0.01}, {0, 0, 1}),
        probe({3.99, 2.2, 2.0}, {-1, 0, 0}), probe({2.0, 1.0, 2.0}, {1, 0, 0}),  probe({1.5, 1.3, 3.0}, {0, 1, 0})};
    for (const bool glazed : {false, true}) {
    INFO("glazed: " << glazed);
    const Bake baked = bakeWith(dir, glazed ? room + glass : room, daylight, probes);
    reference::McOptions mc;
    mc.samples = 131072;
    mc.threads = 2;
    std::vector<reference::McProbe> points;
    for (const Probe& p : probes) points.push_back({p.position, p.normal});
    const std::vector<reference::McProbeResult> ref =
        reference::estimateProbes(reference::McBvh(*baked.scene), points, mc);
    double sum_sq = 0.0;
    for (size_t i = 0; i < probes.size(); ++i) {
        const double got = baked.probe_irradiance[i].x, want = ref[i].irradiance.x, se = ref[i].standard_error.x;
        INFO("probe " << i << ": radbake " << got << ", reference " << want << " +- " << se);
        CHECK(se < 0.015 * want);
        CHECK(std::abs(got - want) < 4.0 * se + 0.03 * want);
        sum_sq += (got - want) * (got - want) / (want * want);
    }
    // The reference's own noise is about 1 % a probe.
    CHECK(std::sqrt(sum_sq / probes.size()) < 0.025);
    }
}

TEST_CASE("a black pane of transmission t over every sky direction: t times the open sky and sun") {
    TempDir dir;
    // A glass box x, z in [-1, 1], y in [0, 1] on the black ground: every path to the sky crosses
    // exactly one pane.
    const double t = 0.6;
    std::string box = kBlackGround;
    box += pane({{-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}}, t);
    box += pane({{-1, 0, -1}, {-1, 1, -1}, {-1, 1, 1}, {-1, 0, 1}}, t);
    box += pane({{1, 0, -1}, {1, 1, -1}, {1, 1, 1}, {1, 0, 1}}, t);
    box += pane({{-1, 0, -1}, {1, 0, -1}, {1, 1, -1}, {-1, 1, -1}}, t);
    box += pane({{-1, 0, 1}, {1, 0, 1}, {1, 1, 1}, {-1, 1, 1}}, t);
    DaylightOptions daylight;
    daylight.sky = SkyModel::Uniform;
    daylight.sun = SunPosition{20.0, 35.0};
    daylight.sun_irradiance = 4.0;
    const double open = kPi + 4.0 * std::sin(35.0 * kDegree);
    const Bake baked = bakeWith(dir, box, daylight,
                                {probe({0, 0.3, 0}, {0, 1, 0}), probe({0.5, 0.01, -0.4}, {0, 1, 0}),
                                 probe({0, 3.0, 0}, {0, 1, 0})});
    checkWithin(baked.probe_irradiance[0].x, t * open, 0.01, "under the glass");
    checkWithin(baked.probe_irradiance[1].x, t * open, 0.01, "under the glass, near a corner");
    checkWithin(baked.probe_irradiance[2].x, open, 0.01, "above it");
}

TEST_CASE("--sky background: a VRML97 Background's colour ramps, times --sky-radiance") {
    TempDir dir;
    DaylightOptions daylight;
    daylight.sky = SkyModel::Background;
    daylight.sky_radiance = 2.0;
    // Sky from 0.2 at the zenith to 1.0 at the horizon (linear in the angle): a horizontal receiver
    // gets pi L (a + b) / 2.
    const std::string ramp = "Background { skyColor [ 0.2 0.2 0.2, 1 1 1 ] skyAngle [ 1.5707963 ] }\n";
    const Bake up = bakeWith(dir, ramp + kBlackGround, daylight, {probe({0, 0.5, 0}, {0, 1, 0})});
    checkWithin(up.probe_irradiance[0].x, kPi * 2.0 * (0.2 + 1.0) / 2, 0.01, "ramp, horizontal");
    // A grey sky over a green ground, no ground plane: a vertical receiver gets pi L (sky + ground) / 2.
    const std::string split =
        "Background { skyColor [ 0.5 0.5 0.5 ] groundColor [ 0 0.3 0, 0 0.3 0 ] groundAngle [ 1.5707963 ] }\n";
    const std::string speck = quad({{100, 100, 100}, {100, 100, 100.1}, {100.1, 100, 100.1}, {100.1, 100, 100}}, 0.0);
    const Bake side = bakeWith(dir, split + speck, daylight, {probe({0, 0, 0}, {1, 0, 0}), probe({0, 0, 0}, {0, -1, 0})});
    checkWithin(side.probe_irradiance[0].x, kPi * 2.0 * 0.5 / 2, 0.01, "vertical, red: the sky half");
    checkWithin(side.probe_irradiance[0].y, kPi * 2.0 * (0.5 + 0.3) / 2, 0.01, "vertical, green: both halves");
    checkWithin(side.probe_irradiance[1].y, kPi * 2.0 * 0.3, 0.01, "facing down: the ground");
}

TEST_CASE("--sky background without a Background node is a located error") {
    TempDir dir;
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.import.daylight.sky = SkyModel::Background;
    Progress progress(false);
    Diagnostics diagnostics;
    std::string said;
    diagnostics.sink = [&](const Diagnostic& d) { said += formatDiagnostic(d) + "\n"; };
    const std::string path = testfs::writeText(dir, "plain.wrl", "#VRML V2.0 utf8\n" + kBlackGround);
    const Bake baked = bake(path, options, progress, diagnostics);
    CHECK(std::string(toString(baked.status)) != "ok");
    CHECK(said.find("plain.wrl") != std::string::npos);
    CHECK(said.find("no VRML97 Background") != std::string::npos);
}
