// Mixed lighting (issue 33, --realtime-lights): lights the engine draws keep their bounce in the
// bake but not their direct light, and the shadowmask holds their visible share per texel.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "daylight_scenes.h"
#include "reference_mc.h"

using namespace radbake;
using daylight_test::quad;
using testfs::TempDir;

namespace {

Bake bakeMixed(const TempDir& dir, const std::string& body, const DaylightOptions& daylight,
               const std::vector<std::string>& realtime, const std::vector<Probe>& probes, double density) {
    BakeOptions options = BakeOptions::forQuality(Quality::Medium);
    options.import.daylight = daylight;
    options.lightmaps.texels_per_unit = density;
    options.probes = probes;
    options.threading.threads = 2;
    for (const std::string& name : realtime) options.realtime_lights.push_back({name, {}});
    Progress progress(false);
    Diagnostics diagnostics;
    Bake baked = bake(testfs::writeText(dir, "mixed.wrl", "#VRML V2.0 utf8\n" + body), options, progress, diagnostics);
    REQUIRE(std::string(toString(baked.status)) == "ok");
    REQUIRE(baked.lightmaps);
    return baked;
}

// A black quad emitting radiance `radiance`, its geometry named `name` (the name
// --realtime-lights gives an emissive mesh by).
std::string emitter(const std::string& name, const std::vector<DVec3>& corners, double radiance) {
    std::string points;
    for (const DVec3& c : corners)
        points += std::to_string(c.x) + " " + std::to_string(c.y) + " " + std::to_string(c.z) + ", ";
    const std::string l = std::to_string(radiance);
    return "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor " + l + " " + l + " " +
           l + " } } geometry DEF " + name + " IndexedFaceSet { coord Coordinate { point [ " + points +
           "] } coordIndex [ 0 1 2 3 -1 ] } }\n";
}

// Lambert's closed form: the form factor from a point (normal n) to a polygon wholly above its
// horizon, (1 / 2 pi) sum over edges of the angle they subtend times its plane's cosine to n.
double pointPolygonFormFactor(const DVec3& x, const DVec3& n, const std::vector<DVec3>& polygon) {
    double sum = 0.0;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const DVec3 a = glm::normalize(polygon[i] - x), b = glm::normalize(polygon[(i + 1) % polygon.size()] - x);
        sum += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(n, glm::normalize(glm::cross(a, b)));
    }
    return std::abs(sum) / (2.0 * kPi);
}

// A floor and a white wall lit by `light` (named `name`), baked with everything baked and with
// that light drawn by the engine: at three floor probes the second keeps reference_mc's total
// less the closed-form direct light `direct(probe)`, the bounce, and lacks that direct light
// (within `direct_tolerance` of it); the lightmap drops by the same.
template <class Direct>
void checkBounceOnly(const std::string& light, const std::string& name, Direct&& direct, double direct_tolerance) {
    TempDir dir;
    const std::string body = light + quad({{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}}, 0.5) +
                             quad({{-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}}, 0.8);
    const std::vector<Probe> probes = {daylight_test::probe({0, 0, 0.5}, {0, 1, 0}), daylight_test::probe({0.5, 0, -0.5}, {0, 1, 0}),
                                       daylight_test::probe({-0.5, 0, 0}, {0, 1, 0})};
    const Bake all = bakeMixed(dir, body, {}, {}, probes, 16);
    const Bake mixed = bakeMixed(dir, body, {}, {name}, probes, 16);
    reference::McOptions mc;
    mc.samples = 65536;
    mc.threads = 2;
    std::vector<reference::McProbe> at;
    for (const Probe& p : probes) at.push_back({p.position, p.normal});
    const std::vector<reference::McProbeResult> total = reference::estimateProbes(reference::McBvh(*all.scene), at, mc);
    for (size_t i = 0; i < probes.size(); ++i) {
        CAPTURE(probes[i].position);
        const double e = direct(probes[i]);
        const double bounce = total[i].irradiance.x - e;
        const double baked = mixed.probe_irradiance[i].x;
        MESSAGE("bounce only " << baked << ", reference total " << total[i].irradiance.x << " +- "
                               << total[i].standard_error.x << " less the direct " << e);
        REQUIRE(bounce > 0.02);
        CHECK(total[i].standard_error.x < 0.1 * bounce);
        CHECK(std::abs(baked - bounce) < 0.15 * bounce);  // with the light: several times the bounce
        CHECK(std::abs(all.probe_irradiance[i].x - baked - e) < 1e-6 + direct_tolerance * e);  // the direct light gone
    }
    // The floor's texels hold the bounce, a fraction of the light.
    double sum_all = 0.0, sum_mixed = 0.0;
    for (const float v : all.lightmaps->lightmaps.images[0].rgb) sum_all += v;
    for (const float v : mixed.lightmaps->lightmaps.images[0].rgb) sum_mixed += v;
    CHECK(sum_mixed < 0.5 * sum_all);
    CHECK(sum_mixed > 0.0);
    REQUIRE(mixed.lightmaps->shadowmask.lights.size() == 1);
    CHECK(mixed.lightmaps->shadowmask.lights[0].name == name);
    CHECK(mixed.lightmaps->shadowmask.lights[0].channel == 0);
    CHECK(all.lightmaps->shadowmask.images.empty());
}

// Calls f(point, mask value) for every texel of mesh `floor`'s charts within 1.5 m of the origin
// in x and z (away from the floor's and the occluding plane's ends).
template <class F>
void forFloorMask(const Bake& baked, uint32_t floor, F&& f) {
    const Shadowmask& mask = baked.lightmaps->shadowmask;
    for (const LightmapChart& chart : baked.lightmaps->lightmaps.layout.charts) {
        if (chart.mesh != floor) continue;
        for (int ty = chart.y; ty < chart.y + chart.height; ++ty)
            for (int tx = chart.x; tx < chart.x + chart.width; ++tx) {
                const DVec2 centre = chart.min_plane + (DVec2(tx - chart.x, ty - chart.y) + 0.5) / chart.texels_per_metre;
                const DVec3 p = chart.worldPoint(centre);
                if (std::abs(p.x) > 1.5 || std::abs(p.z) > 1.5) continue;
                const size_t atlas = static_cast<size_t>(chart.atlas);
                f(p, mask.images[atlas][4 * (static_cast<size_t>(ty) * mask.widths[atlas] + tx)] / 255.0,
                  chart.texels_per_metre);
            }
    }
}

}  // namespace

// A point lamp: its direct light is the closed form I cos / d^2 (I = 1), which the read-out
// leaves out exactly.
TEST_CASE("--realtime-lights: a point light's direct light leaves the bake, its bounce stays (against reference_mc)") {
    checkBounceOnly("DEF Lamp PointLight { location 0 1 0 intensity 1 }\n", "Lamp", [](const Probe& p) {
        const DVec3 to_lamp = DVec3(0, 1, 0) - p.position;
        return to_lamp.y / glm::length(to_lamp) / glm::dot(to_lamp, to_lamp);
    }, 1e-3);
}

// An emissive panel (a mesh, named by its geometry's DEF name): its direct light is pi L times
// Lambert's point-to-polygon form factor, which the read-out's own gather meets within 1 %.
TEST_CASE("--realtime-lights: an emissive mesh's direct light leaves the bake, its bounce stays (against reference_mc)") {
    const std::vector<DVec3> panel = {{-0.25, 1, -0.25}, {0.25, 1, -0.25}, {0.25, 1, 0.25}, {-0.25, 1, 0.25}};
    const double radiance = 10.0;
    checkBounceOnly(emitter("Panel", panel, radiance), "Panel", [&](const Probe& p) {
        return kPi * radiance * pointPolygonFormFactor(p.position, p.normal, panel);
    }, 0.01);
}

// A 1 x 1 m emissive panel 2 m over a floor, half of the floor under a plane 1 m up whose
// straight edge runs along x = 0: from a floor point at x, the panel is seen where x' > -x (the
// ray crosses the plane's height at their midpoint), so the mask holds the form factor of that
// part of the panel over the whole one's (Lambert's formula both), 0.5 under the edge.
TEST_CASE("the shadowmask of an emissive panel under a straight edge: the panel's visible share, 0.5 under the edge") {
    TempDir dir;
    const std::vector<DVec3> panel = {{-0.5, 2, -0.5}, {0.5, 2, -0.5}, {0.5, 2, 0.5}, {-0.5, 2, 0.5}};
    const std::string body = emitter("Panel", panel, 1.0) + quad({{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}, 0.5) +
                             quad({{-3, 1, -3}, {-3, 1, 3}, {0, 1, 3}, {0, 1, -3}}, 0.0, true);
    const Bake baked = bakeMixed(dir, body, {}, {"Panel"}, {}, 64);
    const Shadowmask& mask = baked.lightmaps->shadowmask;
    REQUIRE(mask.lights.size() == 1);
    size_t penumbra = 0, lit = 0, dark = 0;
    double worst = 0.0;
    forFloorMask(baked, 1, [&](const DVec3& p, double got, double texels_per_metre) {
        const DVec3 up(0, 1, 0);
        const double seen_from = std::clamp(-p.x, -0.5, 0.5);
        const double whole = pointPolygonFormFactor(p, up, panel);
        const double expected =
            seen_from >= 0.5 ? 0.0
                             : pointPolygonFormFactor(p, up, {{seen_from, 2, -0.5}, {0.5, 2, -0.5}, {0.5, 2, 0.5},
                                                               {seen_from, 2, 0.5}}) / whole;
        CAPTURE(p);
        CAPTURE(expected);
        CHECK(std::abs(got - expected) < 0.04);  // 16 x 16 samples over the panel
        worst = std::max(worst, std::abs(got - expected));
        if (std::abs(p.x) < 0.5 / texels_per_metre + 1e-9) CHECK(got == doctest::Approx(0.5).epsilon(0.05));
        penumbra += expected > 0.05 && expected < 0.95;
        lit += expected == 1.0 && got == 1.0;
        dark += expected == 0.0 && got == 0.0;
    });
    MESSAGE("worst " << worst << " over " << penumbra << " penumbra texels");
    CHECK(penumbra >= 1000);
    CHECK(lit > 1000);
    CHECK(dark > 1000);
}


// The sun (a 5 degree disc) straight above a floor, half of it under a plane 1 m up whose
// straight edge runs along x = 0: the shadowmask reads the visible share of the disc, which a
// straight edge cuts as a chord: (acos c - c sqrt(1 - c^2)) / pi with c = -x / tan(2.5 deg).
TEST_CASE("the shadowmask of a disc light under a straight edge: the disc's visible share, 0.5 on the shadow line") {
    TempDir dir;
    const std::string body = quad({{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}, 0.5) +
                             quad({{-3, 1, -3}, {-3, 1, 3}, {0, 1, 3}, {0, 1, -3}}, 0.5, true);
    DaylightOptions sun;
    sun.sun = SunPosition{0.0, 90.0};
    sun.sun_diameter_degrees = 5.0;
    const Bake baked = bakeMixed(dir, body, sun, {"sun"}, {}, 64);
    const Shadowmask& mask = baked.lightmaps->shadowmask;
    REQUIRE(mask.images.size() == baked.lightmaps->lightmaps.images.size());
    REQUIRE(mask.lights.size() == 1);
    CHECK(mask.lights[0].channel == 0);
    CHECK(mask.lights_without_channel == 0);
    const double radius = std::tan(2.5 * kPi / 180.0);
    size_t penumbra = 0, lit = 0, dark = 0;
    std::vector<double> flanking;  // the texels either side of the shadow line
    forFloorMask(baked, 0, [&](const DVec3& p, double got, double texels_per_metre) {
        const double c = std::clamp(-p.x / radius, -1.0, 1.0);
        const double expected = (std::acos(c) - c * std::sqrt(1.0 - c * c)) / kPi;
        CAPTURE(p.x);
        // The sun's disc is sampled at 6 x 6 points in a penumbra (punctual_lights.cpp): its
        // visible share is within two of them.
        CHECK(std::abs(got - expected) < 2.0 / 36.0);
        if (std::abs(p.x) < 0.5 / texels_per_metre + 1e-9) flanking.push_back(got);
        penumbra += expected > 0.05 && expected < 0.95;
        lit += expected == 1.0 && got == 1.0;
        dark += expected == 0.0 && got == 0.0;
    });
    CHECK(penumbra >= 20);
    // Bilinear filtering on the shadow line (between two texel centres) reads their mean: 0.5.
    REQUIRE(flanking.size() >= 20);
    double mean = 0.0;
    for (const double v : flanking) mean += v / static_cast<double>(flanking.size());
    CHECK(mean == doctest::Approx(0.5).epsilon(0.01));
    CHECK(lit > 1000);
    CHECK(dark > 1000);
}

// Six lamps along a corridor floor, each reaching only its neighbours (radius), get channels so
// that no two lighting one texel share one; five overlapping at one texel leave one without.
TEST_CASE("shadowmask channels: overlapping lights differ, a fifth overlapping four is counted") {
    TempDir dir;
    std::string lamps;
    for (int i = 0; i < 6; ++i)
        lamps += "DEF L" + std::to_string(i) + " PointLight { location " + std::to_string(2 * i) + " 1 0 radius 2.5 }\n";
    const std::string floor = quad({{-1, 0, -1}, {-1, 0, 1}, {11, 0, 1}, {11, 0, -1}}, 0.5);
    const Bake corridor = bakeMixed(dir, lamps + floor, {}, {"L0", "L1", "L2", "L3", "L4", "L5"}, {}, 8);
    const Shadowmask& mask = corridor.lightmaps->shadowmask;
    REQUIRE(mask.lights.size() == 6);
    for (int i = 0; i + 1 < 6; ++i) CHECK(mask.lights[i].channel != mask.lights[i + 1].channel);  // neighbours overlap
    for (int i = 0; i < 6; ++i) CHECK(mask.lights[i].channel >= 0);
    CHECK(mask.lights_without_channel == 0);

    std::string crowd;
    for (int i = 0; i < 5; ++i) crowd += "DEF C" + std::to_string(i) + " PointLight { location " + std::to_string(0.1 * i) + " 1 0 }\n";
    const Bake crowded = bakeMixed(dir, crowd + floor, {}, {"C0", "C1", "C2", "C3", "C4"}, {}, 8);
    CHECK(crowded.lightmaps->shadowmask.lights_without_channel == 1);
    CHECK(crowded.lightmaps->shadowmask.texels_over_channels > 0);
    CHECK(crowded.lightmaps->shadowmask.lights[4].channel == -1);
}

// Directional lightmaps: on a floor lit by a large area light (and a wall's bounce), the
// irradiance rebuilt from a texel's lightmap and direction for normals tilted up to 30 degrees
// against the exhaustive gather (--probes' read-out) at those normals. The floor is black: a
// probe just above a lit floor with a tilted normal sees the floor itself below its horizon,
// which a normal-mapped surface, tilted in its own plane, does not (the read-out of a surface
// point leaves its own plane out).
TEST_CASE("--directional: the irradiance rebuilt for normals tilted up to 30 degrees within 5 % of probes there") {
    TempDir dir;
    const std::string lamp = "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 4 4 4 } }\n"
                             " geometry IndexedFaceSet { coord Coordinate { point [ 0 1.5 -1, 2 1.5 -1, 2 1.5 1, 0 1.5 1 ] }\n"
                             " coordIndex [ 0 1 2 3 -1 ] } }\n";
    const std::string body = lamp + quad({{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}, 0.0) +
                             quad({{-2, 0, -2}, {2, 0, -2}, {2, 2, -2}, {-2, 2, -2}}, 0.8);
    BakeOptions options = BakeOptions::forQuality(Quality::Medium);
    options.lightmaps.texels_per_unit = 8.0;
    options.lightmaps.directional = true;
    options.threading.threads = 2;
    Progress progress(false);
    Diagnostics diagnostics;
    const Bake baked = bake(testfs::writeText(dir, "directional.wrl", "#VRML V2.0 utf8\n" + body), options, progress, diagnostics);
    REQUIRE(std::string(toString(baked.status)) == "ok");
    const LightmapDirections& directions = baked.lightmaps->directions;
    const Lightmaps& lightmaps = baked.lightmaps->lightmaps;
    REQUIRE(directions.images.size() == lightmaps.images.size());
    const auto lum = [](const DVec3& v) { return 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z; };
    size_t points = 0;
    double worst = 0.0, worst_flat = 0.0;
    for (const LightmapChart& chart : lightmaps.layout.charts) {
        if (chart.mesh != 1) continue;  // the floor
        const size_t atlas = static_cast<size_t>(chart.atlas);
        for (int ty = chart.y + 1; ty + 1 < chart.y + chart.height; ty += 3)
            for (int tx = chart.x + 1; tx + 1 < chart.x + chart.width; tx += 3) {
                const DVec2 centre = chart.min_plane + (DVec2(tx - chart.x, ty - chart.y) + 0.5) / chart.texels_per_metre;
                const DVec3 p = chart.worldPoint(centre);
                // Off the floor's far corners, where the lamp lies within 30 degrees of the horizon
                // and tilting the normal takes part of it out of view: E(n) bends there, and the
                // linear model is up to 8 % off at 30 degrees (docs/gltf.md).
                if (std::abs(p.x) > 1.3 || std::abs(p.z) > 1.3) continue;
                const size_t i = static_cast<size_t>(ty) * static_cast<size_t>(directions.widths[atlas]) + static_cast<size_t>(tx);
                const float* rgb = &lightmaps.images[atlas].rgb[3 * i];
                const double e0 = kPi * lum(DVec3(rgb[0], rgb[1], rgb[2]));
                const DVec3 g(directions.images[atlas][3 * i], directions.images[atlas][3 * i + 1], directions.images[atlas][3 * i + 2]);
                const DVec3 n0(0, 1, 0);
                for (const double tilt : {10.0, 20.0, 30.0})
                    for (int k = 0; k < 8; ++k) {
                        const double azimuth = kPi * k / 4.0, t = tilt * kPi / 180.0;
                        const DVec3 n(std::sin(t) * std::cos(azimuth), std::cos(t), std::sin(t) * std::sin(azimuth));
                        const double rebuilt = e0 * std::max(0.0, 1.0 + glm::dot(g, n - n0));
                        const double probe = lum(probeIrradiance(*baked.solution, baked.options.readout, p, n));
                        REQUIRE(probe > 0.0);
                        worst = std::max(worst, std::abs(rebuilt / probe - 1.0));
                        worst_flat = std::max(worst_flat, std::abs(e0 / probe - 1.0));  // the lightmap alone
                        INFO("p " << p.x << " " << p.z << ", tilt " << tilt << " azimuth " << k * 45 << ": rebuilt "
                                  << rebuilt << " probe " << probe << ", lightmap " << e0);
                        CHECK(std::abs(rebuilt / probe - 1.0) < 0.05);
                        ++points;
                    }
            }
    }
    MESSAGE(points << " points x normals: rebuilt within " << worst << ", the flat lightmap within " << worst_flat);
    CHECK(points > 300);
    CHECK(worst_flat > 0.15);  // the normals matter here: without the directions the error is large
}

TEST_CASE("--realtime-lights file: names a line, comments and blanks skipped, a name given twice is an error at its line") {
    Diagnostics diagnostics;
    const auto names = parseRealtimeLights("# drawn by the engine\n\n  Lamp 1  # the desk's\nsun\n", "rt.txt", diagnostics);
    REQUIRE(names);
    REQUIRE(names->size() == 2);
    CHECK((*names)[0].name == "Lamp 1");
    CHECK((*names)[0].location.line == 3);
    CHECK((*names)[1].name == "sun");
    CHECK_FALSE(parseRealtimeLights("sun\nLamp\nsun\n", "rt.txt", diagnostics));
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(formatDiagnostic(diagnostics.all().back()) == "rt.txt:3:1: error: 'sun' is named twice (first on line 1)");
}
