// Numerical extremes (issue 6): the answer stays right, against a closed form or the
// unperturbed answer, when the scene is scaled by 1e-4 / 1e6, rho nears 1, surfaces touch,
// a 1e6:1 sliver sits beside a large face, emitters differ by 1e8, a face is duplicated,
// the scene is one polygon, or an emitter faces away from everything.
// Already covered elsewhere, not repeated here: the scaled room's radiosity against the
// unscaled one (tests/radiosity/test_invariance.cpp), the grey furnace at rho = 0.99 and
// 0.999 (test_solver.cpp, test_analytic_solver.cpp).
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../radiosity/test_scenes.h"
#include "readout/evaluate_probe.h"
#include "scene/validate.h"

using namespace radbake;
using namespace radbake::test;

namespace {

constexpr double kPerpendicularUnit = 0.200043776075403154;  // unit squares sharing an edge

// Relative comparison: doctest::Approx alone adds 1 to the scale (|a - b| < eps (1 + max)),
// an absolute tolerance for the small irradiances here.
doctest::Approx rel(double expected, double epsilon) { return doctest::Approx(expected).epsilon(epsilon).scale(0.0); }

SolverOptions medium() {
    SolverOptions o = SolverOptions::forQuality(Quality::Medium);
    return o;
}

// Lambert's contour formula: the exact form factor from a point (normal n) to a polygon
// wholly in front of the point's tangent plane, F = 1/(2 pi) |sum_i gamma_i n . unit(r_i x r_i+1)|.
// Independent of the solver's own form-factor code (which clips and orients).
double pointFormFactor(const DVec3& p, const DVec3& n, const std::vector<DVec3>& polygon) {
    double sum = 0.0;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const DVec3 a = polygon[i] - p, b = polygon[(i + 1) % polygon.size()] - p;
        const DVec3 c = glm::cross(a, b);
        const double gamma = std::atan2(glm::length(c), glm::dot(a, b));
        sum += gamma * glm::dot(n, c) / glm::length(c);
    }
    return std::abs(sum) / (2.0 * kPi);
}

std::vector<DVec3> quadOf(const Scene& scene, size_t mesh) {
    std::vector<DVec3> out;
    for (const Vec3& p : scene.meshes[mesh].positions) out.emplace_back(p);
    return out;
}

const Element& rootOfMesh(const Solution& s, uint32_t mesh) {
    for (uint32_t i = 0; i < s.root_count; ++i)
        if (s.elements[i].mesh == mesh) return s.elements[i];
    FAIL("no root element for mesh " << mesh);
    return s.elements.front();
}

// Every element's radiosity and gathered irradiance finite and non-negative.
size_t badElements(const Solution& s) {
    size_t bad = 0;
    for (const Element& e : s.elements)
        for (int c = 0; c < 3; ++c)
            bad += !std::isfinite(e.radiosity[c]) || e.radiosity[c] < 0.0 || !std::isfinite(e.gathered[c]) ||
                   e.gathered[c] < 0.0 || !std::isfinite(e.area) || !(e.area > 0.0);
    return bad;
}

// Floor (rho_floor) and an emitting wall (L_e = 1, rho 0) sharing the edge x = 0, side `size`.
Scene perpendicularSquares(float size, float rho_floor) {
    Scene scene;
    const uint32_t floor_material = addMaterial(scene, Vec3(rho_floor), Vec3(0.0f));
    const uint32_t wall_material = addMaterial(scene, Vec3(0.0f), Vec3(1.0f));
    const float s = size;
    addQuad(scene, floor_material, {0, 0, 0}, {s, 0, 0}, {s, s, 0}, {0, s, 0});
    addQuad(scene, wall_material, {0, 0, 0}, {0, s, 0}, {0, s, s}, {0, 0, s});  // x = 0, faces +x
    return scene;
}

// A lamp square (L_e, side 1, facing -z) at height 1 over a floor of side `floor_size`
// centred below it.
Scene lampOverFloor(float emission, float rho_floor, float floor_size = 3.0f) {
    Scene scene;
    const uint32_t floor_material = addMaterial(scene, Vec3(rho_floor), Vec3(0.0f));
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(emission));
    const float h = floor_size / 2;
    addQuad(scene, floor_material, {-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0});
    addQuad(scene, lamp, {-0.5f, -0.5f, 1}, {-0.5f, 0.5f, 1}, {0.5f, 0.5f, 1}, {0.5f, -0.5f, 1});  // faces -z
    return scene;
}

// A warning whose message holds both fragments.
bool warnedAbout(const Diagnostics& diagnostics, const std::string& what, const std::string& mesh) {
    for (const Diagnostic& d : diagnostics.all())
        if (d.severity == Severity::Warning && d.message.find(what) != std::string::npos &&
            d.message.find(mesh) != std::string::npos)
            return true;
    return false;
}

}  // namespace

// --- scale ------------------------------------------------------------------------------

TEST_CASE("extremes: touching squares scaled by 1e-4 and 1e6 keep F and the near-edge probes") {
    // Extends test_invariance (scaled room vs unscaled) with closed forms at each scale:
    // the floor's mean irradiance is pi L_e F (rho_floor B_floor = rho H, the wall is black),
    // and probes at 1e-1 .. 1e-4 of the side from the shared edge read Lambert's formula.
    for (const float scale : {1e-4f, 1.0f, 1e6f}) {
        CAPTURE(scale);
        const Scene scene = perpendicularSquares(scale, 0.5f);
        Diagnostics diagnostics;
        const auto solution = solve(scene, medium(), diagnostics);
        REQUIRE(solution);
        CHECK_FALSE(diagnostics.hasErrors());
        CHECK(badElements(*solution) == 0);
        const double h_mean = rootOfMesh(*solution, 0).radiosity.x / 0.5;
        // Tolerance 0.5 %: the leaves' row sums come from 2 x 2 Gauss points, graded towards
        // the edge; measured about 1e-4 at scale 1.
        CHECK(h_mean == rel(kPi * kPerpendicularUnit, 5e-3));
        const std::vector<DVec3> wall = quadOf(scene, 1);
        for (const double d : {1e-1, 1e-2, 1e-3, 1e-4}) {
            CAPTURE(d);
            const DVec3 p = DVec3(d, 0.5, 0.0) * double(scale);
            const double exact = kPi * pointFormFactor(p, {0, 0, 1}, wall);
            // 1 %: probes gather from the hierarchy with point-to-polygon form factors (opened
            // near the source); exact but for float positions and ray visibility.
            CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), p, {0, 0, 1}).x ==
                  rel(exact, 1e-2));
        }
    }
}

TEST_CASE("extremes: a coloured furnace (rho 0.5 / 0.99 / 0.999 per channel) at scale 1e-4, 1 and 1e6") {
    // Closed box, every face L_e = 1: H = pi L_e / (1 - rho) per channel (pi/0.5, 100 pi,
    // 1000 pi). One solve holds both extremes; the oracle refines on the largest channel.
    // Extends the grey furnaces (one rho per solve, scale 1) to colour and scale.
    for (const float scale : {1e-4f, 1.0f, 1e6f}) {
        CAPTURE(scale);
        Scene scene;
        const uint32_t m = addMaterial(scene, Vec3(0.5f, 0.99f, 0.999f), Vec3(1.0f));
        addInwardBox(scene, m, Vec3(0.0f), Vec3(scale));
        Diagnostics diagnostics;
        const auto solution = solve(scene, medium(), diagnostics);
        REQUIRE(solution);
        CHECK(solution->stats.converged);
        CHECK(badElements(*solution) == 0);
        const DVec3 expected(kPi / (1.0 - double(0.5f)), kPi / (1.0 - double(0.99f)), kPi / (1.0 - double(0.999f)));
        const DVec3 points[][2] = {{{0.5, 0.5, 0.0}, {0, 0, 1}}, {{0.02, 0.03, 0.0}, {0, 0, 1}}, {{0.0, 0.5, 0.7}, {1, 0, 0}}};
        for (const auto& probe : points) {
            const DVec3 h = probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality),
                                            probe[0] * double(scale), probe[1]);
            CAPTURE(probe[0]);
            // 1 % at 0.99 (issue 6's definition of done); 2 % at 0.999, the analytic file's
            // tolerance (a row-sum error e shows as e / (1 - rho) = 1000 e).
            CHECK(h.x == rel(expected.x, 1e-2));
            CHECK(h.y == rel(expected.y, 1e-2));
            CHECK(h.z == rel(expected.z, 2e-2));
        }
    }
}

// --- sliver -----------------------------------------------------------------------------

TEST_CASE("extremes: a 1e6:1 sliver triangle beside a large floor changes nothing else") {
    // Lamp over a 3 x 3 floor (rho 0.5) with a wall behind (rho 0.5) so light bounces; the
    // sliver (base 1, height 1e-6, rho 0.5) lies in the floor's plane along its edge, or
    // stands upright on it. Its area is 5e-7 of the floor's: the floor's and wall's mean
    // irradiance must not move by more than 1e-3 (float/oracle noise), nothing may be NaN or
    // negative, and the sliver's radiosity is rho times the irradiance where it lies.
    auto build = [](int sliver) {
        Scene scene = lampOverFloor(1.0f, 0.5f);
        const uint32_t grey = scene.meshes[0].material;
        addQuad(scene, grey, {-1.5f, 1.5f, 0}, {1.5f, 1.5f, 0}, {1.5f, 1.5f, 2}, {-1.5f, 1.5f, 2});  // y = 1.5, faces -y
        if (sliver != 0) {
            // Base 3, height 3e-6. (Shorter is not possible at this extent: a triangle under
            // 4 float steps of the extent, about 1.1e-6 here, is dropped as degenerate; below.)
            Mesh mesh;
            mesh.name = "sliver";
            mesh.material = grey;
            if (sliver == 1)  // flat, along the floor's +x edge, faces +z
                mesh.positions = {{1.5f, -1.5f, 0}, {1.5f + 3e-6f, 0.0f, 0}, {1.5f, 1.5f, 0}};
            else if (sliver == 2)  // upright on the floor, in the plane y = 0, faces -y
                mesh.positions = {{-1.5f, 0.0f, 0}, {1.5f, 0.0f, 0}, {0.0f, 0.0f, 3e-6f}};
            else  // base 1, height 1e-6: below the degenerate height
                mesh.positions = {{1.5f, -0.5f, 0}, {1.5f + 1e-6f, 0.0f, 0}, {1.5f, 0.5f, 0}};
            mesh.triangles = {UVec3(0, 1, 2)};
            mesh.triangle_polygon = {0};
            mesh.polygon_count = 1;
            scene.meshes.push_back(mesh);
        }
        return scene;
    };
    Scene base_scene = build(0);
    Diagnostics base_diagnostics;
    REQUIRE(validateScene(base_scene, base_diagnostics));
    const auto base = solve(base_scene, medium(), base_diagnostics);
    REQUIRE(base);
    for (const int sliver : {1, 2}) {
        CAPTURE(sliver);
        Scene scene = build(sliver);
        Diagnostics diagnostics;
        REQUIRE(validateScene(scene, diagnostics));
        REQUIRE(scene.meshes.size() == 4);  // the sliver is thin, not degenerate at this extent
        const auto solution = solve(scene, medium(), diagnostics);
        REQUIRE(solution);
        CHECK_FALSE(diagnostics.hasErrors());
        CHECK(solution->stats.converged);
        CHECK(badElements(*solution) == 0);
        for (const uint32_t mesh : {0u, 2u}) {
            CAPTURE(mesh);
            CHECK(rootOfMesh(*solution, mesh).radiosity.x ==
                  rel(rootOfMesh(*base, mesh).radiosity.x, 1e-3));
        }
        for (const DVec3& p : {DVec3(0, 0, 0), DVec3(1.2, -1.2, 0), DVec3(1.4999, 0.0, 0)}) {
            CAPTURE(p);
            CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), p, {0, 0, 1}).x ==
                  rel(probeIrradiance(*base, ReadoutOptions::forQuality(base->options.quality), p, {0, 0, 1}).x, 1e-3));
        }
        // The sliver's radiosity is rho times its area-mean irradiance: the width grows
        // linearly to the apex, so probes along the base weighted by 1 - |t|.
        const Element& s = rootOfMesh(*solution, 3);
        double h_mean = 0.0, weights = 0.0, h_min = 1e300, h_max = 0.0;
        for (int i = -20; i <= 20; ++i) {
            const double t = i / 20.0, w = 1.0 - std::abs(t);
            const DVec3 p = sliver == 1 ? DVec3(1.5 + 1e-6, 1.5 * t, 0.0) : DVec3(1.5 * t, 0.0, 1e-6);
            const double h =
                probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), p, s.normal).x;
            h_mean += w * h;
            weights += w;
            h_min = std::min(h_min, h);
            h_max = std::max(h_max, h);
        }
        h_mean /= weights;
        MESSAGE("sliver " << sliver << ": B = " << s.radiosity.x << ", rho * mean H = " << 0.5 * h_mean);
        CHECK(h_mean > 0.0);
        // B lies within rho times the irradiance range along it.
        CHECK(s.radiosity.x >= 0.5 * h_min);
        CHECK(s.radiosity.x <= 0.5 * h_max);
        // Within 5 % of rho times its mean (one root element, below the minimum area; the
        // probes' mean is itself a 41-point quadrature). Upright (standing on the lit floor,
        // F = 0.5 to it) it read 40 % low before the local rule: the power rule never split
        // the floor for a receiver of 3e-7 of the scene's area, so it gathered the floor's mean
        // radiosity, not the bright patch under the lamp. Measured now: flat -0.01 %, upright +3.4 %.
        CHECK(s.radiosity.x == rel(0.5 * h_mean, 5e-2));
    }
    // Aspect 1e6 but only 1e-6 high in a scene 4.7 across: below float precision of this
    // extent, so it is dropped, and said so.
    Scene tiny = build(3);
    Diagnostics diagnostics;
    REQUIRE(validateScene(tiny, diagnostics));
    CHECK(tiny.meshes.size() == 3);
    bool reported = false;
    for (const Diagnostic& d : diagnostics.all())
        reported |= d.severity == Severity::Warning && d.message.find("sliver") != std::string::npos &&
                    d.message.find("degenerate") != std::string::npos;
    CHECK(reported);
}

// --- emitters 1e8 apart -----------------------------------------------------------------

TEST_CASE("extremes: emitters 1e8 apart: superposition, and the dim one's light is right") {
    // Two closed rooms side by side: a bright lamp (L_e = 1e8) in a grey room, a dim one
    // (L_e = 1) in a black room, so that the dim room's irradiance is the dim lamp's direct
    // light, Lambert's closed form. The refinement threshold is a fraction of the total power
    // (the bright lamp's): the dim lamp's light must still be exact at probes, the rooms must
    // not leak into each other, and solving both together equals the sum of solving each.
    // The dim room grey, with light that bounces: the next test.
    auto build = [](float bright, float dim) {
        Scene scene;
        const uint32_t grey = addMaterial(scene, Vec3(0.6f), Vec3(0.0f));
        const uint32_t black = addMaterial(scene, Vec3(0.0f), Vec3(0.0f));
        const uint32_t lamp_bright = addMaterial(scene, Vec3(0.0f), Vec3(bright));
        const uint32_t lamp_dim = addMaterial(scene, Vec3(0.0f), Vec3(dim));
        addInwardBox(scene, grey, Vec3(0.0f), Vec3(2.0f));
        addInwardBox(scene, black, Vec3(3.0f, 0.0f, 0.0f), Vec3(5.0f, 2.0f, 2.0f));
        addQuad(scene, lamp_bright, {0.8f, 0.8f, 1.99f}, {0.8f, 1.2f, 1.99f}, {1.2f, 1.2f, 1.99f}, {1.2f, 0.8f, 1.99f});
        addQuad(scene, lamp_dim, {3.8f, 0.8f, 1.99f}, {3.8f, 1.2f, 1.99f}, {4.2f, 1.2f, 1.99f}, {4.2f, 0.8f, 1.99f});
        return scene;
    };
    const Scene both_scene = build(1e8f, 1.0f), bright_scene = build(1e8f, 0.0f), dim_scene = build(0.0f, 1.0f);
    Diagnostics diagnostics;
    const auto both = solve(both_scene, medium(), diagnostics);
    const auto bright = solve(bright_scene, medium(), diagnostics);
    const auto dim = solve(dim_scene, medium(), diagnostics);
    REQUIRE(both);
    REQUIRE(bright);
    REQUIRE(dim);
    CHECK_FALSE(diagnostics.hasErrors());
    CHECK(badElements(*both) == 0);
    const std::vector<DVec3> dim_lamp = quadOf(both_scene, 13);
    const DVec3 probes[][2] = {{{1.5, 1.5, 0.0}, {0, 0, 1}}, {{0.0, 1.0, 1.0}, {1, 0, 0}}, {{1.0, 1.0, 2.0}, {0, 0, -1}},
                               {{4.5, 1.5, 0.0}, {0, 0, 1}}, {{3.0, 1.0, 1.0}, {1, 0, 0}}, {{4.0, 1.3, 0.0}, {0, 0, 1}}};
    for (const auto& probe : probes) {
        CAPTURE(probe[0]);
        const double h_both =
            probeIrradiance(*both, ReadoutOptions::forQuality(both->options.quality), probe[0], probe[1]).x;
        const double h_bright =
            probeIrradiance(*bright, ReadoutOptions::forQuality(bright->options.quality), probe[0], probe[1]).x;
        const double h_dim =
            probeIrradiance(*dim, ReadoutOptions::forQuality(dim->options.quality), probe[0], probe[1]).x;
        if (probe[0].x > 2.5) {  // the dim room: nothing from the bright lamp, the dim one exact
            const double exact = kPi * pointFormFactor(probe[0], probe[1], dim_lamp);
            CHECK(h_bright == 0.0);
            CHECK(h_dim == rel(exact, 1e-3));
            CHECK(h_both == rel(exact, 1e-3));
        } else {
            CHECK(h_dim == 0.0);
            CHECK(h_bright > 0.0);
            // The dim lamp changes the total power by 1e-8: the same refinement, the same answer.
            CHECK(h_both == rel(h_bright, 1e-6));
        }
    }
    for (uint32_t mesh = 0; mesh < 14; ++mesh) {
        CAPTURE(mesh);
        const double b_both = rootOfMesh(*both, mesh).radiosity.x;
        const double b_sum = rootOfMesh(*bright, mesh).radiosity.x + rootOfMesh(*dim, mesh).radiosity.x;
        if (b_sum == 0.0)
            CHECK(b_both == 0.0);  // the black room's walls
        else
            CHECK(b_both == rel(b_sum, 1e-6));
    }
}

TEST_CASE("extremes: a grey dim room beside one 1e8 brighter is refined as if it were alone") {
    // The rooms of the test above, both grey (rho 0.6) so the dim room's light bounces. The
    // power rule once judged the dim room's links against the bright lamp's power: its
    // ceiling read 8.5 % low, a wall probe 3.1 %. The rooms cannot light each other, so each
    // is now its own light-exchange group with its own threshold: the dim room must read as
    // the dim room solved alone, within 1 % (the medium quality's analytic tolerance; the
    // first round still refines against the total power, so the hierarchies differ a little).
    auto build = [](float bright) {
        Scene scene;
        const uint32_t grey = addMaterial(scene, Vec3(0.6f), Vec3(0.0f));
        const uint32_t lamp_bright = addMaterial(scene, Vec3(0.0f), Vec3(bright));
        const uint32_t lamp_dim = addMaterial(scene, Vec3(0.0f), Vec3(1.0f));
        addInwardBox(scene, grey, Vec3(0.0f), Vec3(2.0f));
        addInwardBox(scene, grey, Vec3(3.0f, 0.0f, 0.0f), Vec3(5.0f, 2.0f, 2.0f));
        addQuad(scene, lamp_bright, {0.8f, 0.8f, 1.99f}, {0.8f, 1.2f, 1.99f}, {1.2f, 1.2f, 1.99f}, {1.2f, 0.8f, 1.99f});
        addQuad(scene, lamp_dim, {3.8f, 0.8f, 1.99f}, {3.8f, 1.2f, 1.99f}, {4.2f, 1.2f, 1.99f}, {4.2f, 0.8f, 1.99f});
        return scene;
    };
    const Scene both_scene = build(1e8f), alone_scene = build(0.0f);
    Diagnostics diagnostics;
    const auto both = solve(both_scene, medium(), diagnostics);
    const auto alone = solve(alone_scene, medium(), diagnostics);
    REQUIRE(both);
    REQUIRE(alone);
    CHECK_FALSE(diagnostics.hasErrors());
    CHECK(badElements(*both) == 0);
    // Not the ceiling straight above the lamp (1 cm below it): lit only through that gap.
    const DVec3 probes[][2] = {{{4.6, 1.6, 2.0}, {0, 0, -1}}, {{3.5, 0.5, 2.0}, {0, 0, -1}}, {{3.0, 1.0, 1.0}, {1, 0, 0}},
                               {{5.0, 1.5, 0.5}, {-1, 0, 0}}, {{4.5, 1.5, 0.0}, {0, 0, 1}}, {{4.0, 0.0, 1.5}, {0, 1, 0}}};
    for (const auto& probe : probes) {
        CAPTURE(probe[0]);
        const double h_both =
            probeIrradiance(*both, ReadoutOptions::forQuality(both->options.quality), probe[0], probe[1]).x;
        const double h_alone =
            probeIrradiance(*alone, ReadoutOptions::forQuality(alone->options.quality), probe[0], probe[1]).x;
        MESSAGE("dim room probe " << probe[0].x << " " << probe[0].y << " " << probe[0].z << ": beside "
                                  << h_both << ", alone " << h_alone << " (" << 100.0 * (h_both / h_alone - 1.0) << " %)");
        CHECK(h_alone > 0.0);
        CHECK(h_both == rel(h_alone, 1e-2));
    }
    // Every dim-room root's radiosity too (meshes 6..11 are its walls, 13 its lamp).
    for (uint32_t mesh = 6; mesh < 14; ++mesh) {
        if (mesh == 12) continue;  // the bright lamp
        CAPTURE(mesh);
        CHECK(rootOfMesh(*both, mesh).radiosity.x == rel(rootOfMesh(*alone, mesh).radiosity.x, 1e-2));
    }
}

// --- duplicate face ---------------------------------------------------------------------

TEST_CASE("extremes: a coplanar duplicate floor is reported, and the answer stays finite and right") {
    // Lamp over a grey floor and nothing else: the floor's irradiance is the lamp's direct
    // light, the closed form of Lambert's formula, whether the floor is given once or twice.
    Scene scene = lampOverFloor(1.0f, 0.5f);
    Mesh copy = scene.meshes[0];
    copy.name = "floor copy";
    scene.meshes.push_back(copy);
    Diagnostics diagnostics;
    REQUIRE(validateScene(scene, diagnostics));
    CHECK(warnedAbout(diagnostics, "duplicate coplanar face", "floor copy"));
    const auto solution = solve(scene, medium(), diagnostics);
    REQUIRE(solution);
    CHECK_FALSE(diagnostics.hasErrors());
    CHECK(badElements(*solution) == 0);
    const std::vector<DVec3> lamp = quadOf(scene, 1);
    for (const DVec3& p : {DVec3(0, 0, 0), DVec3(0.5, 0.5, 0), DVec3(1.2, -0.7, 0)}) {
        CAPTURE(p);
        const double exact = kPi * pointFormFactor(p, {0, 0, 1}, lamp);
        CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), p, {0, 0, 1}).x ==
              rel(exact, 1e-3));
    }
    // Both copies: B = rho H with H the lamp's mean over the floor, the same for each.
    const double b0 = rootOfMesh(*solution, 0).radiosity.x, b2 = rootOfMesh(*solution, 2).radiosity.x;
    CHECK(b0 > 0.0);
    CHECK(b2 == rel(b0, 1e-3));
}

TEST_CASE("extremes: a coplanar face half overlapping the floor is reported, and the answer stays right") {
    // The copy is shifted by half the floor: validation reports the partial overlap (z-fighting
    // in any renderer). The answer must be sane: the lamp's direct light at floor probes, both
    // faces B = rho H, nothing NaN.
    Scene scene = lampOverFloor(1.0f, 0.5f);
    Mesh copy = scene.meshes[0];
    copy.name = "floor shifted";
    for (Vec3& p : copy.positions) p.x += 1.5f;
    scene.meshes.push_back(copy);
    Diagnostics diagnostics;
    REQUIRE(validateScene(scene, diagnostics));
    CHECK(warnedAbout(diagnostics, "partly overlapping", "floor shifted"));
    const auto solution = solve(scene, medium(), diagnostics);
    REQUIRE(solution);
    CHECK_FALSE(diagnostics.hasErrors());
    CHECK(badElements(*solution) == 0);
    const std::vector<DVec3> lamp = quadOf(scene, 1);
    for (const DVec3& p : {DVec3(0, 0, 0), DVec3(0.5, 0.5, 0), DVec3(2.5, -0.7, 0)}) {
        CAPTURE(p);
        CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), p, {0, 0, 1}).x ==
              rel(kPi * pointFormFactor(p, {0, 0, 1}, lamp), 1e-3));
    }
}

// --- single polygon ---------------------------------------------------------------------

TEST_CASE("extremes: a scene of a single polygon") {
    for (const float emission : {0.0f, 3.0f}) {
        for (const bool triangle : {false, true}) {
            CAPTURE(emission);
            CAPTURE(triangle);
            Scene scene;
            const uint32_t m = addMaterial(scene, Vec3(0.7f), Vec3(emission));
            addQuad(scene, m, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0});  // faces +z
            if (triangle) {
                scene.meshes[0].triangles = {UVec3(0, 1, 2)};
                scene.meshes[0].triangle_polygon = {0};
                scene.meshes[0].positions.pop_back();
            }
            Diagnostics diagnostics;
            REQUIRE(validateScene(scene, diagnostics));
            const auto solution = solve(scene, medium(), diagnostics);
            REQUIRE(solution);
            CHECK_FALSE(diagnostics.hasErrors());
            CHECK(badElements(*solution) == 0);
            // It sees nothing, so B = pi L_e exactly on every element.
            for (const Element& e : solution->elements) {
                if (emission == 0.0f)
                    CHECK(e.radiosity.x == 0.0);
                else
                    CHECK(e.radiosity.x == rel(kPi * emission, 1e-12));
            }
            const std::vector<DVec3> polygon = quadOf(scene, 0);
            for (const DVec3& p : {DVec3(0.5, 0.4, 1.0), DVec3(1.0, 0.5, 0.01), DVec3(-1.0, 3.0, 2.0)}) {
                CAPTURE(p);
                const double exact = kPi * emission * pointFormFactor(p, {0, 0, -1}, polygon);
                const double h =
                    probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), p, {0, 0, -1}).x;
                if (emission == 0.0f)
                    CHECK(h == 0.0);
                else
                    CHECK(h == rel(exact, 1e-3));
                CHECK(
                    probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), p, {0, 0, 1}).x ==
                    0.0);  // facing away
                CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality),
                                      p - DVec3(0, 0, 2.0 * p.z), {0, 0, 1})
                          .x == 0.0);  // behind it
            }
        }
    }
}

// --- emitter facing away ----------------------------------------------------------------

TEST_CASE("extremes: an emitter facing away from everything lights nothing") {
    // A lamp (L_e = 5) at height 1.2 over an open box of grey walls 1 high, facing +z (up):
    // everything is behind its plane, so nothing receives its light. Every non-emitter must read
    // exactly 0, with no NaN; a probe above it facing down reads its closed form.
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.8f), Vec3(0.0f));
    const uint32_t lamp = addMaterial(scene, Vec3(0.3f), Vec3(5.0f));
    addInwardBox(scene, grey, Vec3(-2.0f, -2.0f, 0.0f), Vec3(2.0f, 2.0f, 1.0f));
    scene.meshes.erase(scene.meshes.begin() + 1);  // no ceiling
    addQuad(scene, lamp, {-0.5f, -0.5f, 1.2f}, {0.5f, -0.5f, 1.2f}, {0.5f, 0.5f, 1.2f}, {-0.5f, 0.5f, 1.2f});  // faces +z
    const uint32_t lamp_mesh = static_cast<uint32_t>(scene.meshes.size() - 1);
    Diagnostics diagnostics;
    REQUIRE(validateScene(scene, diagnostics));
    const auto solution = solve(scene, medium(), diagnostics);
    REQUIRE(solution);
    CHECK_FALSE(diagnostics.hasErrors());
    CHECK(badElements(*solution) == 0);
    size_t lit = 0;
    for (const Element& e : solution->elements) {
        if (e.mesh == lamp_mesh)
            CHECK(e.radiosity.x == rel(kPi * 5.0, 1e-12));
        else
            lit += e.radiosity != DVec3(0.0) || e.gathered != DVec3(0.0);
    }
    CHECK(lit == 0);
    for (const DVec3& p : {DVec3(0, 0, 0), DVec3(1.5, 1.5, 0), DVec3(0, 0, 1.19)}) {
        CAPTURE(p);
        CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), p, {0, 0, 1}).x == 0.0);
    }
    CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {-2.0, 0.0, 0.9}, {1, 0, 0})
              .x == 0.0);  // a wall's top
    const std::vector<DVec3> polygon = quadOf(scene, lamp_mesh);
    const DVec3 above(0.2, 0.1, 2.0);
    CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), above, {0, 0, -1}).x ==
          rel(kPi * 5.0 * pointFormFactor(above, {0, 0, -1}, polygon), 1e-3));
}
