// The solver against closed forms and its invariances.
#include <doctest/doctest.h>

#include <cstring>

#include "radiosity/elements.h"
#include "radiosity/form_factor.h"
#include "radiosity/linear_solve.h"
#include "test_scenes.h"
#include "readout/evaluate_probe.h"

using namespace radbake;
using namespace radbake::test;

namespace {

constexpr double kPerpendicularUnit = 0.200043776075403154;

SolverOptions medium(LinkVisibility mode = LinkVisibility::Exact) {
    SolverOptions o = SolverOptions::forQuality(Quality::Medium);
    o.visibility = mode;
    return o;
}

Scene closedBox(float rho, float emission, float size = 1.0f) {
    Scene scene;
    const uint32_t m = addMaterial(scene, Vec3(rho), Vec3(emission));
    addInwardBox(scene, m, Vec3(0.0f), Vec3(size));
    return scene;
}

}  // namespace

TEST_CASE("closed emitting box: H = pi L_e / (1 - rho) everywhere (medium within 1 %)") {
    for (const float rho : {0.5f, 0.9f, 0.99f}) {
        CAPTURE(rho);
        const Scene scene = closedBox(rho, 1.0f);
        Diagnostics diagnostics;
        const auto solution = solve(scene, medium(), diagnostics);
        REQUIRE(solution);
        CHECK(solution->stats.converged);
        const double expected = kPi * 1.0 / (1.0 - rho);
        // Probes: the floor's centre, near a floor corner, a wall's edge; all facing inwards.
        const DVec3 points[][2] = {{{0.5, 0.5, 0.0}, {0, 0, 1}},
                                   {{0.02, 0.03, 0.0}, {0, 0, 1}},
                                   {{0.0, 0.5, 0.7}, {1, 0, 0}},
                                   {{0.5, 0.5, 0.5}, {0, 0.6, 0.8}}};
        for (const auto& probe : points) {
            const DVec3 h =
                probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), probe[0], probe[1]);
            CAPTURE(probe[0]);
            CHECK(h.x == doctest::Approx(expected).epsilon(0.01).scale(0.0));
            CHECK(h.y == h.x);
        }
        // Leaves: every leaf's radiosity is B = pi L_e + rho H = pi L_e / (1 - rho) too.
        double worst = 0.0;
        for (const Element& e : solution->elements)
            if (e.isLeaf()) worst = std::max(worst, std::abs(e.radiosity.x / expected - 1.0));
        MESSAGE("rho " << rho << ": elements " << solution->stats.elements << ", links " << solution->stats.links
                       << ", iterations " << solution->stats.iterations << ", worst leaf error " << worst);
        CHECK(worst < 0.01);
    }
}

// A block hovering 1 mm above a furnace's floor: the floor under it and the block's bottom see
// each other at 1 mm, where visibility between their elements is not exact; rows then summed to
// more than 1.25 (no surface sees more than its hemisphere), and light was amplified to 1.54 x the
// furnace's B = pi L_e / (1 - rho), which no surface of a closed furnace can exceed. Rows above
// 1.25 are scaled to 1 (linear_solve.cpp). (The gap reads up to half too dark: thin gaps are not
// solved right yet, so only the maximum is asserted.)
TEST_CASE("a block hovering 1 mm above a furnace's floor: no surface brighter than the furnace") {
    const float rho = 0.9f;
    Scene scene = closedBox(rho, 1.0f);
    addOutwardBox(scene, scene.meshes[0].material, {0.3f, 0.3f, 0.001f}, {0.7f, 0.7f, 0.011f});
    Diagnostics diagnostics;
    const auto solution = solve(scene, medium(), diagnostics);
    REQUIRE(solution);
    CHECK(solution->stats.converged);
    CHECK(solution->stats.limited_row_sums > 0);
    const double expected = kPi * 1.0 / (1.0 - rho);
    double brightest = 0.0, darkest = 1e30;
    for (const Element& e : solution->elements)
        if (e.isLeaf()) {
            brightest = std::max(brightest, e.radiosity.x / expected);
            darkest = std::min(darkest, e.radiosity.x / expected);
        }
    MESSAGE("hovering block: " << solution->stats.limited_row_sums << " rows limited, leaves from " << darkest
                               << " to " << brightest << " of the furnace value");
    CHECK(brightest < 1.01);
}

// A lamp panel 8 cm under a room's ceiling, lighting it from below: the ceiling's leaves above it
// inherit links (from their ancestors) to the floor and walls whose visibility was judged over
// more of the ceiling than the lamp hides, so their rows sum past 1.25. Scaling those whole rows
// also scaled the lamp's own direct light, and the ceiling, the room's main source of bounced
// light, read a third too dark there. The solve's irradiance at each leaf above the lamp,
// (B - E) / rho, must match the exhaustive gather at its centroid from the same radiosities.
TEST_CASE("a ceiling lit by a lamp just under it keeps the lamp's direct light where rows are limited") {
    for (const LinkVisibility mode : {LinkVisibility::Aabb, LinkVisibility::Exact}) {
        Scene scene;
        const uint32_t wall = addMaterial(scene, Vec3(0.8f), Vec3(0.0f));
        const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(1.0f));
        addInwardBox(scene, wall, Vec3(0.0f), Vec3(8.0f, 8.0f, 2.6f));
        const float x0 = 1.9f, x1 = 2.1f, y0 = 1.25f, y1 = 2.75f, up = 2.52025f, down = 2.51975f;
        addQuad(scene, lamp, {x0, y0, up}, {x1, y0, up}, {x1, y1, up}, {x0, y1, up});        // faces +z
        addQuad(scene, lamp, {x0, y0, down}, {x0, y1, down}, {x1, y1, down}, {x1, y0, down});  // faces -z
        Diagnostics diagnostics;
        const auto solution = solve(scene, medium(mode), diagnostics);
        REQUIRE(solution);
        const ReadoutOptions readout = ReadoutOptions::forQuality(Quality::Medium);
        double solved = 0.0, gathered = 0.0;
        size_t leaves = 0;
        for (const Element& e : solution->elements) {
            if (!e.isLeaf() || e.mesh != 1 || e.centroid.x < x0 || e.centroid.x > x1 || e.centroid.y < y0 ||
                e.centroid.y > y1)
                continue;
            const DVec3 h = probeIrradiance(*solution, readout, e.centroid + 1e-6 * e.normal, e.normal);
            solved += e.area * (e.radiosity.x - e.emission.x) / e.reflectance.x;
            gathered += e.area * h.x;
            ++leaves;
        }
        MESSAGE(std::string(toString(mode)) << ": " << leaves << " ceiling leaves over the lamp, rows limited "
                               << solution->stats.limited_row_sums << ", solved / gathered " << solved / gathered);
        REQUIRE(leaves > 0);
        CHECK(solution->stats.limited_row_sums > 0);
        // 0.64 when whole rows were scaled. What is left is light from past the lamp's edges
        // that the leaves' own sampled links found blocked.
        CHECK(solved / gathered > 0.9);
        CHECK(solved / gathered < 1.02);
    }
}

TEST_CASE("irradiance below an emitting unit square: centre and corner (closed forms)") {
    Scene scene;
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(2.0f));
    addQuad(scene, lamp, {-0.5f, -0.5f, 1.0f}, {-0.5f, 0.5f, 1.0f}, {0.5f, 0.5f, 1.0f}, {0.5f, -0.5f, 1.0f});
    Diagnostics diagnostics;
    const auto solution = solve(scene, medium(), diagnostics);
    REQUIRE(solution);
    const double b = kPi * 2.0;
    // Centre: F = (4 / pi) (a / s) atan(a / s), a = 1/2, s = sqrt(a^2 + 1).
    const double s = std::sqrt(1.25);
    const double f_centre = 4.0 / kPi * (0.5 / s) * std::atan(0.5 / s);
    CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {0, 0, 0}, {0, 0, 1}).x ==
          doctest::Approx(b * f_centre).epsilon(1e-9).scale(0.0));
    // Below a corner: F = (1 / 2 pi) [2 (1 / sqrt 2) atan(1 / sqrt 2)] for a unit square at height 1.
    const double f_corner = 1.0 / (2.0 * kPi) * 2.0 / std::sqrt(2.0) * std::atan(1.0 / std::sqrt(2.0));
    CHECK(
        probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {0.5, 0.5, 0}, {0, 0, 1}).x ==
        doctest::Approx(b * f_corner).epsilon(1e-9).scale(0.0));
    // Facing away: nothing.
    CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {0, 0, 0}, {0, 0, -1}).x ==
          0.0);
}

TEST_CASE("perpendicular unit squares sharing an edge: the hierarchy's links sum to F") {
    Scene scene;
    const uint32_t floor_material = addMaterial(scene, Vec3(0.5f), Vec3(0.0f));
    const uint32_t wall_material = addMaterial(scene, Vec3(0.0f), Vec3(1.0f));
    addQuad(scene, floor_material, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    addQuad(scene, wall_material, {0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1});  // x = 0, faces +x
    Diagnostics diagnostics;
    const auto solution = solve(scene, medium(), diagnostics);
    REQUIRE(solution);
    double floor_to_wall = 0.0;
    size_t links = 0;
    for (const Link& link : solution->links) {
        const Element& r = solution->elements[link.receiver];
        const Element& e = solution->elements[link.source];
        if (r.mesh == 0 && e.mesh == 1) {
            floor_to_wall += r.area * link.form_factor;
            ++links;
        }
    }
    MESSAGE("floor->wall: " << links << " links, F = " << floor_to_wall);
    CHECK(links > 1);  // the emitter's gradient was refined
    CHECK(floor_to_wall == doctest::Approx(kPerpendicularUnit).epsilon(2e-4).scale(0.0));
}

TEST_CASE("an occluder fully between two squares: zero transfer in every visibility mode") {
    for (const LinkVisibility mode :
         {LinkVisibility::Rays, LinkVisibility::Aabb, LinkVisibility::Obb, LinkVisibility::Exact}) {
        CAPTURE(toString(mode));
        Scene scene;
        const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(1.0f));
        const uint32_t grey = addMaterial(scene, Vec3(0.5f), Vec3(0.0f));
        addQuad(scene, grey, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});                 // receiver, faces +z
        addQuad(scene, lamp, {0, 0, 2}, {0, 1, 2}, {1, 1, 2}, {1, 0, 2});                 // emitter, faces -z
        addOutwardBox(scene, grey, Vec3(-1.0f, -1.0f, 0.9f), Vec3(2.0f, 2.0f, 1.1f));   // slab between
        Diagnostics diagnostics;
        const auto solution = solve(scene, medium(mode), diagnostics);
        REQUIRE(solution);
        for (const Element& e : solution->elements)
            if (e.mesh == 0) CHECK(e.radiosity.x == 0.0);
        CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {0.5, 0.5, 0.0},
                              {0, 0, 1})
                  .x == 0.0);
        if (mode == LinkVisibility::Obb || mode == LinkVisibility::Exact) CHECK(solution->stats.occluded_links > 0);
        // The lamp does light the slab's underside... no: the slab's top faces the lamp.
        CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {0.5, 0.5, 1.1},
                              {0, 0, 1})
                  .x > 0.0);
    }
}

TEST_CASE("closed emitting box at high quality: within 0.3 %") {
    for (const float rho : {0.5f, 0.9f}) {
        CAPTURE(rho);
        const Scene scene = closedBox(rho, 1.0f);
        SolverOptions options = SolverOptions::forQuality(Quality::High);
        Diagnostics diagnostics;
        const auto solution = solve(scene, options, diagnostics);
        REQUIRE(solution);
        const double expected = kPi / (1.0 - rho);
        CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {0.5, 0.5, 0.0},
                              {0, 0, 1})
                  .x == doctest::Approx(expected).epsilon(0.003).scale(0.0));
        CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {0.0, 0.5, 0.5},
                              {1, 0, 0})
                  .x == doctest::Approx(expected).epsilon(0.003).scale(0.0));
        // Near and at a corner the leaf corrections' centroid rule leaves ~0.35 % (measured).
        for (const DVec3 p : {DVec3(0.02, 0.03, 0.0), DVec3(0.0, 0.0, 0.0)})
            CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), p, {0, 0, 1}).x ==
                  doctest::Approx(expected).epsilon(0.005).scale(0.0));
    }
}

TEST_CASE("a point light above a grey floor: direct irradiance, then bounced") {
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.5f), Vec3(0.0f));
    addQuad(scene, grey, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    Light light;
    light.type = LightType::Point;
    light.position = Vec3(0.0f, 0.0f, 1.0f);
    light.intensity = 2.0f;  // W/sr
    scene.lights.push_back(light);
    Diagnostics diagnostics;
    const auto solution = solve(scene, SolverOptions::forQuality(Quality::Medium), diagnostics);
    REQUIRE(solution);
    // H = I cos(theta) / d^2: 2 at the centre, 2 (1/sqrt 2) / 2 at (1, 0).
    CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {0, 0, 0}, {0, 0, 1}).x ==
          doctest::Approx(2.0).epsilon(1e-9).scale(0.0));
    CHECK(probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {1, 0, 0}, {0, 0, 1}).x ==
          doctest::Approx(1.0 / std::sqrt(2.0)).epsilon(1e-9).scale(0.0));
    // The floor reflects it: area-weighted mean of B = rho * mean H over the floor, with
    // mean H = I * (projected solid angle of the floor seen from the light) / A.
    double power = 0.0;
    for (const Element& e : solution->elements)
        if (e.isLeaf()) power += e.area * e.radiosity.x;
    // Power reaching the floor = I * solid angle of the 2 x 2 square seen from 1 above its
    // centre: Omega = 4 asin(a b / sqrt((a^2 + d^2)(b^2 + d^2))) = 4 asin(1/2), half-sides a = b = 1.
    const double omega = 4.0 * std::asin(0.5);
    CHECK(power == doctest::Approx(0.5 * 2.0 * omega).epsilon(0.01).scale(0.0));
    CHECK(solution->stats.elements > 1);  // the light's gradient was refined
}

// The row sums and cluster shares kept between solves (RowSumCache) give the same answer as
// taking them afresh, after the links a leaf inherits or its root's cluster links changed: a
// kept value is used only for the same sources at the same visibility.
TEST_CASE("row sums kept between solves: the same radiosities as without them, after links change") {
    Scene scene = closedBox(0.9f, 0.0f);
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(5.0f));
    addOutwardBox(scene, lamp, Vec3(0.4f, 0.8f, 0.4f), Vec3(0.6f, 0.85f, 0.6f));
    const uint32_t grey = addMaterial(scene, Vec3(0.5f), Vec3(0.0f));
    addOutwardBox(scene, grey, Vec3(0.2f, 0.0f, 0.2f), Vec3(0.5f, 0.3f, 0.5f));
    Diagnostics diagnostics;
    auto solution = solve(scene, medium(), diagnostics);
    REQUIRE(solution);
    Solution& s = *solution;
    const auto radiosities = [&] {
        std::vector<DVec3> b;
        for (const Element& e : s.elements) b.push_back(e.radiosity);
        return b;
    };
    const auto solveWith = [&](RowSumCache* cache) {
        solveHierarchy(s, testRunner(), SolveStart::Emission, 1e-10, 400, cache);
        return radiosities();
    };
    RowSumCache cache;
    const std::vector<DVec3> first = solveWith(&cache);
    CHECK(first == solveWith(nullptr));
    size_t kept = 0;
    for (const uint8_t known : cache.row_sums.known) kept += known;
    REQUIRE(kept > 0);
    // Change inherited links: the visibility of one, the source of another (both on inner
    // elements, whose leaves below read them).
    size_t changed = 0;
    for (Link& link : s.links) {
        if (s.elements[link.receiver].isLeaf() || !(link.visibility > 0.0f)) continue;
        if (changed == 0) link.visibility *= 0.5f;
        else if (changed == 1) link.source = s.elements[link.source].parent != kNoElement ? s.elements[link.source].parent : link.source;
        if (++changed == 2) break;
    }
    REQUIRE(changed == 2);
    const std::vector<DVec3> fresh = solveWith(nullptr);
    CHECK(fresh != first);
    CHECK(solveWith(&cache) == fresh);
    // And the cluster links reaching one subdivided root (its own and its clusters') dropped
    // but one: its leaves' shares of the cluster light are then that link's kernel alone.
    const auto reaches = [&](uint32_t receiver, uint32_t r) {
        if (receiver == r) return true;
        for (uint32_t c = s.root_leaf_cluster[r]; c != kNoElement; c = s.clusters[c].parent)
            if (receiver == (c | kClusterNode)) return true;
        return false;
    };
    uint32_t root = kNoElement;
    for (uint32_t r = 0; r < s.root_count && root == kNoElement; ++r) {
        if (s.elements[r].isLeaf()) continue;
        size_t count = 0;
        for (const ClusterLink& link : s.cluster_links) count += reaches(link.receiver, r) && link.visibility > 0.0f;
        if (count >= 2) root = r;
    }
    REQUIRE(root != kNoElement);
    size_t kept_links = 0;
    for (ClusterLink& link : s.cluster_links)
        if (reaches(link.receiver, root) && link.visibility > 0.0f && kept_links++ > 0) link.visibility = 0.0f;
    const std::vector<DVec3> without_links = solveWith(nullptr);
    CHECK(without_links != fresh);
    CHECK(solveWith(&cache) == without_links);
}
