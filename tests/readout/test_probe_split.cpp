// The fast paths of probeIrradiance give the same bits as the general code they replace:
// splitQuad vs splitPolygon, pointPolygonFormFactor vs a plain loop, countOpenFrom vs
// segmentBlocked; and the probe's work counters on a case where they are known exactly.
#include <doctest/doctest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "readout/evaluate_probe.h"
#include "readout/gather.h"
#include "radiosity/form_factor.h"
#include "radiosity/refine.h"
#include "../radiosity/test_scenes.h"
#include "visibility/ray_caster.h"

using namespace radbake;
using namespace radbake::test;

namespace {

// splitmix64: a fixed sequence on every platform.
struct Random {
    uint64_t state;
    double uniform() {
        uint64_t z = (state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        z ^= z >> 31;
        return static_cast<double>(z >> 11) * 0x1.0p-53;
    }
    double in(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    DVec3 vec(double lo, double hi) { return {in(lo, hi), in(lo, hi), in(lo, hi)}; }
};

// A convex planar quad: a rectangle of random size and aspect (up to 4:1, so both split rules
// occur), its corners jittered along its edges, in a random frame.
std::vector<DVec3> randomQuad(Random& random) {
    const DVec3 centre = random.vec(-2.0, 2.0);
    DVec3 u = glm::normalize(random.vec(-1.0, 1.0) + DVec3(1e-3, 0.0, 0.0));
    DVec3 v = glm::normalize(glm::cross(u, glm::normalize(random.vec(-1.0, 1.0) + DVec3(0.0, 0.0, 1e-3))));
    const double a = random.in(0.05, 1.0), b = a * random.in(0.25, 4.0);
    const double j = 0.1;  // jitter as a fraction of the sides: keeps the quad convex
    return {centre + (-a + j * a * random.uniform()) * u - b * v, centre + a * u + (-b + j * b * random.uniform()) * v,
            centre + (a - j * a * random.uniform()) * u + b * v, centre - a * u + (b - j * b * random.uniform()) * v};
}

DVec3 quadNormal(const std::vector<DVec3>& q) { return glm::normalize(glm::cross(q[1] - q[0], q[2] - q[0])); }

bool sameBits(const DVec3& a, const DVec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
bool sameBits(double a, double b) { return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b); }

}  // namespace

TEST_CASE("splitQuad gives splitPolygon's children to the bit") {
    Random random{7};
    int halved = 0, quartered = 0;
    for (int trial = 0; trial < 500; ++trial) {
        const std::vector<DVec3> quad = randomQuad(random);
        const std::vector<std::vector<DVec3>> expected = splitPolygon(quad);
        QuadChildren children;
        splitQuad(quad, children);
        REQUIRE(children.count == expected.size());
        (children.count == 2 ? halved : quartered) += 1;
        for (size_t c = 0; c < children.count; ++c) {
            REQUIRE(expected[c].size() == 4);
            for (size_t k = 0; k < 4; ++k) CHECK(sameBits(children.loops[c][k], expected[c][k]));
        }
    }
    // Both rules were exercised (aspect up to 4:1 either way).
    CHECK(halved > 50);
    CHECK(quartered > 50);
}

// pointPolygonFormFactor as a plain loop: clip, then one edge at a time.
double plainPointPolygonFormFactor(const DVec3& point, const DVec3& normal, std::span<const DVec3> source,
                                   const DVec3& source_normal) {
    if (!(glm::dot(source_normal, point - source[0]) > 0.0)) return 0.0;
    std::array<DVec3, kMaxClip> clipped;
    const size_t count = clipAboveHorizon(point, normal, source, clipped.data());
    if (count < 3) return 0.0;
    double sum = 0.0;
    for (size_t i = 0; i < count; ++i) {
        const DVec3 r0 = clipped[i] - point, r1 = clipped[(i + 1) % count] - point;
        const DVec3 c = glm::cross(r0, r1);
        const double c_len = glm::length(c);
        if (!(c_len > 0.0)) continue;
        sum += atan2Upper(c_len, glm::dot(r0, r1)) * glm::dot(normal, c) / c_len;
    }
    return std::abs(sum) / (2.0 * kPi);
}

TEST_CASE("pointPolygonFormFactor (edges in lanes, the clip skipped when whole) equals the plain loop to the bit") {
    Random random{11};
    int positive = 0, clipped = 0, zero = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const std::vector<DVec3> quad = randomQuad(random);
        const DVec3 quad_normal = quadNormal(quad);
        const DVec3 point = random.vec(-4.0, 4.0);
        const DVec3 normal = glm::normalize(random.vec(-1.0, 1.0) + DVec3(0.0, 1e-3, 0.0));
        const double expected = plainPointPolygonFormFactor(point, normal, quad, quad_normal);
        // Triangles too (an odd edge count: the last edge fills both lanes).
        const std::vector<DVec3> triangle(quad.begin(), quad.begin() + 3);
        CHECK(sameBits(pointPolygonFormFactor(point, normal, quad, quad_normal), expected));
        CHECK(sameBits(pointPolygonFormFactor(point, normal, triangle, quad_normal),
                       plainPointPolygonFormFactor(point, normal, triangle, quad_normal)));
        bool all_above = true, any_above = false;
        for (const DVec3& q : quad) {
            all_above = all_above && glm::dot(normal, q - point) > 0.0;
            any_above = any_above || glm::dot(normal, q - point) > 0.0;
        }
        if (expected > 0.0 && all_above) ++positive;
        if (expected > 0.0 && !all_above && any_above) ++clipped;
        if (expected == 0.0) ++zero;
    }
    CHECK(positive > 300);  // the whole quad
    CHECK(clipped > 100);   // the horizon across it
    CHECK(zero > 300);      // behind the quad or below the horizon
}

TEST_CASE("countOpenFrom counts exactly the segments segmentBlocked leaves open") {
    // Three plates between z = 0 and z = 2, so a segment from below to above may be blocked by
    // some; segments ending on a plate (its epsilon at both ends) and shorter than 2 epsilon too.
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.5f), Vec3(0.0f));
    addQuad(scene, grey, {-1.0f, -1.0f, 0.5f}, {0.2f, -1.0f, 0.5f}, {0.2f, 1.0f, 0.5f}, {-1.0f, 1.0f, 0.5f});
    addQuad(scene, grey, {-0.3f, -1.0f, 1.0f}, {1.0f, -1.0f, 1.0f}, {1.0f, 0.1f, 1.0f}, {-0.3f, 0.1f, 1.0f});
    addQuad(scene, grey, {-1.0f, 0.4f, 1.5f}, {1.0f, 0.4f, 1.5f}, {1.0f, 1.0f, 1.5f}, {-1.0f, 1.0f, 1.5f});
    Diagnostics diagnostics;
    const auto caster = RayCaster::build(scene, diagnostics);
    REQUIRE(caster);
    Random random{3};
    size_t blocked_total = 0, open_total = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const DVec3 from(random.in(-1.0, 1.0), random.in(-1.0, 1.0), random.in(-0.2, 0.4));
        std::vector<DVec3> to;
        const size_t count = 1 + static_cast<size_t>(trial % 9);  // partial and several packets
        for (size_t k = 0; k < count; ++k) {
            DVec3 q(random.in(-1.0, 1.0), random.in(-1.0, 1.0), random.in(0.4, 2.0));
            if (k == 0 && trial % 5 == 0) q = from + DVec3(0.5 * caster->epsilon(), 0.0, 0.0);  // too short
            if (k == 1 && trial % 7 == 0) q.z = 1.0;                                            // ends on a plate's plane
            to.push_back(q);
        }
        size_t expected = 0;
        for (const DVec3& q : to) expected += caster->segmentBlocked(from, q) ? 0 : 1;
        CHECK(caster->countOpenFrom(from, to) == expected);
        open_total += expected;
        blocked_total += to.size() - expected;
    }
    CHECK(open_total > 200);
    CHECK(blocked_total > 200);
    CHECK(caster->countOpenFrom({0, 0, 0}, {}) == 0);
}

TEST_CASE("probe counters: an emitting square over a probe is split three times, 4 rays a piece") {
    // A unit square lamp (L_e = 1, no reflector) at z = 1 above a probe at the origin: radius
    // 0.707 at distance 1 is split (probe_visibility_coarse 0.1) into 4, 16 and 64 pieces; the
    // 64 pieces (radius 0.088, distance >= 1) are coarse enough. So 1 + 4 + 16 + 64 = 85 form
    // factors and 85 x 2 x 2 rays, 64 contributing pieces, and H = pi F to rounding.
    Scene scene;
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(1.0f));
    addQuad(scene, lamp, {-0.5f, -0.5f, 1.0f}, {-0.5f, 0.5f, 1.0f}, {0.5f, 0.5f, 1.0f}, {0.5f, -0.5f, 1.0f});
    SolverOptions options = SolverOptions::forQuality(Quality::Medium);
    const ReadoutOptions readout = ReadoutOptions::forQuality(Quality::Medium);
    REQUIRE(readout.probe_samples == 2);
    REQUIRE(readout.probe_visibility_coarse == 0.1);
    Diagnostics diagnostics;
    const auto solution = solve(scene, options, diagnostics);
    REQUIRE(solution);
    REQUIRE(solution->elements.size() == 1);
    ProbeCounters counters;
    const DVec3 h = probeIrradianceCounted(*solution, readout, {0, 0, 0}, {0, 0, 1}, counters);
    CHECK(counters.form_factors == 85);
    CHECK(counters.rays == 85 * 4);
    CHECK(counters.pieces == 64);
    CHECK(sameBits(h, probeIrradiance(*solution, readout, {0, 0, 0}, {0, 0, 1})));
    const std::vector<DVec3> square = {{-0.5, -0.5, 1.0}, {-0.5, 0.5, 1.0}, {0.5, 0.5, 1.0}, {0.5, -0.5, 1.0}};
    CHECK(h.x == doctest::Approx(kPi * pointPolygonFormFactor({0, 0, 0}, {0, 0, 1}, square, {0, 0, -1})).epsilon(1e-12));
}

TEST_CASE("the exhaustive gather's faintest roots are read from a few rays among them, within probe_faint_share of the light") {
    // A lamp over the probe and 400 small tiles 8 m up (about 3 % of the probe's unoccluded
    // light), a dark board at 4 m hiding those with x > 0: with a share of 5 % the tiles' light
    // is estimated from kFaintTailRays rays among them (one at each sampled tile's centre)
    // instead of 2 x 2 rays a tile once the lamp is gathered, and the probe moves by at most
    // that share of its light; the default share takes the faintest tiles only.
    Scene scene;
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(1.0f));
    const uint32_t tile = addMaterial(scene, Vec3(0.0f), Vec3(3.0f));
    const uint32_t board = addMaterial(scene, Vec3(0.0f), Vec3(0.0f));
    addQuad(scene, lamp, {-0.5f, -0.5f, 1.0f}, {-0.5f, 0.5f, 1.0f}, {0.5f, 0.5f, 1.0f}, {0.5f, -0.5f, 1.0f});
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j) {
            const float x = -8.1f + 0.8f * float(i), y = -8.1f + 0.8f * float(j);
            addQuad(scene, tile, {x, y, 8.0f}, {x, y + 0.05f, 8.0f}, {x + 0.05f, y + 0.05f, 8.0f}, {x + 0.05f, y, 8.0f});
        }
    addQuad(scene, board, {0.0f, -9.0f, 4.0f}, {0.0f, 9.0f, 4.0f}, {9.0f, 9.0f, 4.0f}, {9.0f, -9.0f, 4.0f});
    Diagnostics diagnostics;
    const auto solution = solve(scene, SolverOptions::forQuality(Quality::Medium), diagnostics);
    REQUIRE(solution);
    const DVec3 p{0.0, 0.0, 0.0}, n{0.0, 0.0, 1.0};
    double unoccluded = 0.0, tiles = 0.0;
    for (uint32_t r = 0; r < solution->root_count; ++r) {
        const Element& e = solution->elements[r];
        const double light = pointPolygonFormFactor(p, n, polygonOf(*solution, e).vertices, e.normal) * maxChannel(e.radiosity);
        unoccluded += light;
        if (e.centroid.z > 7.0) tiles += light;
    }
    REQUIRE(tiles > 0.02 * unoccluded);
    REQUIRE(tiles < 0.05 * unoccluded);
    ReadoutOptions exact = ReadoutOptions::forQuality(Quality::Medium);
    exact.probe_faint_share = 0.0;
    ReadoutOptions faint = exact;
    faint.probe_faint_share = 0.05;
    ProbeCounters exact_work, faint_work, default_work;
    const DVec3 h_exact = probeIrradianceCounted(*solution, exact, p, n, exact_work);
    const DVec3 h_faint = probeIrradianceCounted(*solution, faint, p, n, faint_work);
    // The board hides a third or more of the tiles' light: the rays matter.
    CHECK(maxChannel(h_exact) < unoccluded - 0.3 * tiles);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(h_faint[c] - h_exact[c]) <= 0.05 * h_exact[c]);
    // Here each tile is hidden or not as a whole, and the sampled tiles are spread over both
    // sides of the board: the tiles' light (the probe's less the lamp's, which no board hides)
    // within a tenth.
    const DVec3 lamp_light = pointPolygonFormFactor(p, n, polygonOf(*solution, solution->elements[0]).vertices,
                                                    solution->elements[0].normal) *
                             solution->elements[0].radiosity;
    REQUIRE(solution->elements[0].centroid.z == doctest::Approx(1.0));
    CHECK(std::abs(maxChannel(h_faint - h_exact)) <= 0.1 * maxChannel(h_exact - lamp_light));
    // The 400 tiles' 2 x 2 rays each, against kFaintTailRays among them.
    CHECK(exact_work.rays - faint_work.rays == 4 * 400 - gather::Gatherer::kFaintTailRays);
    // Wherever the probe stands under the board's edge, the estimate stays within the share.
    for (double x = -3.0; x <= 3.0; x += 0.75) {
        const DVec3 q{x, 0.3 * x, 0.0};
        const DVec3 a = probeIrradiance(*solution, exact, q, n), b = probeIrradiance(*solution, faint, q, n);
        for (int c = 0; c < 3; ++c) CHECK(std::abs(b[c] - a[c]) <= 0.05 * a[c]);
    }
    probeIrradianceCounted(*solution, ReadoutOptions::forQuality(Quality::Medium), p, n, default_work);
    CHECK(default_work.rays < exact_work.rays);
    CHECK(default_work.rays > faint_work.rays);
}
