#include <doctest/doctest.h>

#include <array>
#include <cmath>

#include "radiosity/punctual_lights.h"
#include "visibility/ray_caster.h"

using namespace radbake;

namespace {

// Axis-aligned rectangle [x0, x1] x [y0, y1] in the plane z = height, one polygon of two
// triangles.
Mesh rectangleZ(double x0, double x1, double y0, double y1, double height) {
    Mesh mesh;
    mesh.positions = {Vec3(x0, y0, height), Vec3(x1, y0, height), Vec3(x1, y1, height), Vec3(x0, y1, height)};
    mesh.triangles = {UVec3(0, 1, 2), UVec3(0, 2, 3)};
    mesh.triangle_polygon = {0, 0};
    mesh.polygon_count = 1;
    return mesh;
}

// A 20 x 20 floor at z = 0, optionally with a wall (a horizontal plate) at z = 1 over
// x in [-1, 1]: it shades the floor's points below it from a light above.
Scene floorScene(bool with_plate) {
    Scene scene;
    scene.materials.push_back({});
    scene.meshes.push_back(rectangleZ(-10, 10, -10, 10, 0));
    if (with_plate) scene.meshes.push_back(rectangleZ(-1, 1, -1, 1, 1));
    return scene;
}

std::unique_ptr<RayCaster> buildOrFail(const Scene& scene) {
    Diagnostics diagnostics;
    auto caster = RayCaster::build(scene, diagnostics);
    REQUIRE(caster != nullptr);
    return caster;
}

Light pointLight(const DVec3& position, float intensity, const Vec3& color = Vec3(1.0f)) {
    Light light;
    light.type = LightType::Point;
    light.position = Vec3(position);
    light.intensity = intensity;
    light.color = color;
    return light;
}

const DVec3 kUp(0, 0, 1);
// Closed-form values are evaluated in double from float-stored light data; 1e-12 relative
// leaves room for a few roundings of the formula only.
constexpr double kRelative = 1e-12;

}  // namespace

TEST_CASE("a point light at height h: I/h^2 straight below, I cos^3(theta)/h^2 off axis") {
    const Scene scene = floorScene(false);
    auto caster = buildOrFail(scene);
    const double h = 2.0, intensity = 5.0;
    const Light light = pointLight(DVec3(0, 0, h), float(intensity), Vec3(1.0f, 0.5f, 0.25f));
    size_t rays = 0;
    const DVec3 below = lightIrradiance(light, caster.get(), DVec3(0, 0, 0), kUp, &rays);
    CHECK(below.x == doctest::Approx(intensity / (h * h)).epsilon(kRelative).scale(0.0));
    CHECK(below.y == doctest::Approx(0.5 * intensity / (h * h)).epsilon(kRelative).scale(0.0));
    CHECK(below.z == doctest::Approx(0.25 * intensity / (h * h)).epsilon(kRelative).scale(0.0));
    for (double x : {0.5, 1.0, 2.0, 5.0, 9.0}) {
        const double cos_theta = h / std::sqrt(h * h + x * x);
        const DVec3 off = lightIrradiance(light, caster.get(), DVec3(x, 0.3 * x, 0), kUp, &rays);
        const double cos_theta_xy = h / std::sqrt(h * h + x * x + 0.09 * x * x);
        CHECK(off.x == doctest::Approx(intensity * std::pow(cos_theta_xy, 3) / (h * h)).epsilon(kRelative).scale(0.0));
        // And along the x axis alone, the brief's cos^3 form literally.
        const DVec3 on_axis = lightIrradiance(light, caster.get(), DVec3(x, 0, 0), kUp, &rays);
        CHECK(on_axis.x == doctest::Approx(intensity * std::pow(cos_theta, 3) / (h * h)).epsilon(kRelative).scale(0.0));
    }
    CHECK(rays == 11);  // one shadow segment per evaluation
    // Without a caster (no shadows) the value is the same on an open floor.
    CHECK(lightIrradiance(light, nullptr, DVec3(0, 0, 0), kUp) == below);
}

TEST_CASE("a point light is shadowed by a plate, and dark behind the surface") {
    const Scene scene = floorScene(true);
    auto caster = buildOrFail(scene);
    const Light light = pointLight(DVec3(0, 0, 3), 4.0f);
    CHECK(lightIrradiance(light, caster.get(), DVec3(0, 0, 0), kUp) == DVec3(0.0));
    CHECK(lightIrradiance(light, caster.get(), DVec3(0.5, -0.5, 0), kUp) == DVec3(0.0));
    // Outside the plate's shadow (the shadow of [-1, 1] from height 3 onto z = 0 is [-1.5, 1.5]).
    const DVec3 lit = lightIrradiance(light, caster.get(), DVec3(2, 0, 0), kUp);
    CHECK(lit.x == doctest::Approx(4.0 * 3.0 / std::pow(13.0, 1.5)).epsilon(kRelative).scale(0.0));
    // The plate's top is lit (its own surface does not shadow it) and its underside is not.
    CHECK(lightIrradiance(light, caster.get(), DVec3(0, 0, 1), kUp).x == doctest::Approx(1.0).epsilon(kRelative).scale(0.0));
    CHECK(lightIrradiance(light, caster.get(), DVec3(0, 0, 1), -kUp) == DVec3(0.0));
    // A light below the floor does not reach its top side.
    CHECK(lightIrradiance(pointLight(DVec3(3, 3, -1), 4.0f), nullptr, DVec3(3, 3, 0), kUp) == DVec3(0.0));
}

TEST_CASE("VRML attenuation, radius and on") {
    Light light = pointLight(DVec3(0, 0, 2), 8.0f);
    const DVec3 p(0, 0, 0);
    const double free = 8.0 / 4.0;
    light.attenuation = Vec3(2.0f, 0.0f, 0.0f);
    CHECK(lightIrradiance(light, nullptr, p, kUp).x == doctest::Approx(free / 2.0).epsilon(kRelative).scale(0.0));
    light.attenuation = Vec3(1.0f, 0.5f, 0.25f);  // 1 + 1 + 1 at d = 2
    CHECK(lightIrradiance(light, nullptr, p, kUp).x == doctest::Approx(free / 3.0).epsilon(kRelative).scale(0.0));
    light.attenuation = Vec3(0.25f, 0.0f, 0.0f);  // below 1: max(.., 1) keeps the factor at 1
    CHECK(lightIrradiance(light, nullptr, p, kUp).x == doctest::Approx(free).epsilon(kRelative).scale(0.0));
    CHECK(attenuationFactor(Vec3(0.0f), 10.0) == 1.0);
    light.attenuation = Vec3(1.0f, 0.0f, 0.0f);
    light.radius = 1.5f;  // the floor point is 2 away
    CHECK(lightIrradiance(light, nullptr, p, kUp) == DVec3(0.0));
    light.radius = 2.5f;
    CHECK(lightIrradiance(light, nullptr, p, kUp).x == doctest::Approx(free).epsilon(kRelative).scale(0.0));
    light.on = false;
    CHECK(lightIrradiance(light, nullptr, p, kUp) == DVec3(0.0));
}

TEST_CASE("a spot light: full inside the beam, linear falloff, nothing outside the cut-off") {
    Light spot = pointLight(DVec3(0, 0, 1), 3.0f);
    spot.type = LightType::Spot;
    spot.direction = Vec3(0.0f, 0.0f, -1.0f);
    spot.beam_width = float(kPi / 8);     // 22.5 degrees
    spot.cut_off_angle = float(kPi / 4);  // 45 degrees
    auto atAngle = [&](double angle) {
        const DVec3 p(std::tan(angle), 0, 0);  // at height 1, the angle from the axis is the incidence angle
        return lightIrradiance(spot, nullptr, p, kUp).x;
    };
    auto unshadedPoint = [](double angle) { return 3.0 * std::pow(std::cos(angle), 3); };
    CHECK(atAngle(0.0) == doctest::Approx(3.0).epsilon(kRelative).scale(0.0));
    CHECK(atAngle(0.3) == doctest::Approx(unshadedPoint(0.3)).epsilon(kRelative).scale(0.0));
    // Halfway between beam width and cut-off, the factor is 1/2 (within the float storage of
    // the two angles, ~1e-7 relative).
    const double middle = 3 * kPi / 16;
    CHECK(atAngle(middle) == doctest::Approx(0.5 * unshadedPoint(middle)).epsilon(1e-6).scale(0.0));
    CHECK(atAngle(kPi / 4 + 1e-3) == 0.0);
    CHECK(atAngle(1.2) == 0.0);
    CHECK(spotFactor(0.5, 0.1, 1.0) == doctest::Approx(0.5 / 0.9).epsilon(kRelative).scale(0.0));
    CHECK(spotFactor(0.5, 2.0, 1.0) == 1.0);  // beam width above cut-off: a hard edge at the cut-off
    CHECK(spotFactor(1.0, 2.0, 1.0) == 0.0);
    // Shadowed by the plate like a point light.
    const Scene scene = floorScene(true);
    auto caster = buildOrFail(scene);
    spot.position = Vec3(0.0f, 0.0f, 3.0f);
    CHECK(lightIrradiance(spot, caster.get(), DVec3(0.2, 0, 0), kUp) == DVec3(0.0));
}

TEST_CASE("a directional light gives I cos(theta), and a plate shadows it") {
    const Scene scene = floorScene(true);
    auto caster = buildOrFail(scene);
    Light sun;
    sun.type = LightType::Directional;
    sun.intensity = 2.0f;
    sun.color = Vec3(1.0f, 1.0f, 0.5f);
    const double theta = 0.4;
    sun.direction = Vec3(float(-std::sin(theta)), 0.0f, float(-std::cos(theta)));  // travelling down and to -x
    // Light comes from +x above: the plate's shadow on the floor is shifted towards -x by tan(theta).
    const DVec3 open(5, 0, 0), shaded(-0.2, 0, 0);
    const DVec3 lit = lightIrradiance(sun, caster.get(), open, kUp);
    // The direction is stored in float: cos(theta) holds to ~1e-7.
    CHECK(lit.x == doctest::Approx(2.0 * std::cos(theta)).epsilon(1e-6).scale(0.0));
    CHECK(lit.z == doctest::Approx(1.0 * std::cos(theta)).epsilon(1e-6).scale(0.0));
    CHECK(lightIrradiance(sun, caster.get(), shaded, kUp) == DVec3(0.0));
    // On a wall facing +x the angle to the light is pi/2 - theta.
    CHECK(lightIrradiance(sun, nullptr, open, DVec3(1, 0, 0)).x == doctest::Approx(2.0 * std::sin(theta)).epsilon(1e-6).scale(0.0));
    CHECK(lightIrradiance(sun, nullptr, open, DVec3(-1, 0, 0)) == DVec3(0.0));
    // A probe far outside the scene's box (here the plate alone, diagonal sqrt(8)) is still
    // shadowed by the plate 50 units away between it and the light; 3 units aside it is lit.
    Scene plate_only;
    plate_only.meshes.push_back(rectangleZ(-1, 1, -1, 1, 1));
    auto plate_caster = buildOrFail(plate_only);
    const DVec3 far_below(-0.2 - 50 * std::tan(theta), 0, -49);
    CHECK(lightIrradiance(sun, plate_caster.get(), far_below, kUp) == DVec3(0.0));
    CHECK(lightIrradiance(sun, plate_caster.get(), far_below + DVec3(0, 3, 0), kUp).x ==
          doctest::Approx(2.0 * std::cos(theta)).epsilon(1e-6).scale(0.0));
}

TEST_CASE("punctualIrradiance sums every light") {
    const std::array<Light, 2> lights = {pointLight(DVec3(0, 0, 1), 1.0f), pointLight(DVec3(0, 0, 2), 8.0f)};
    size_t rays = 0;
    const Scene scene = floorScene(false);
    auto caster = buildOrFail(scene);
    const DVec3 total = punctualIrradiance(lights, caster.get(), DVec3(0, 0, 0), kUp, &rays);
    CHECK(total.x == doctest::Approx(1.0 + 2.0).epsilon(kRelative).scale(0.0));
    CHECK(rays == 2);
}
