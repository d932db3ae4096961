// The visibility tests on parts made by the geometry stage (partFromPoints): closed hulls of
// random point clouds (general convex polytopes, not only boxes) and flat polygons, against
// the brute-force segment test. Checks that the two stages agree on the ConvexPart contract.
#include <doctest/doctest.h>

#include <random>

#include "geometry/parts.h"
#include "part_builders.h"
#include "visibility/occlusion.h"
#include "visibility/reference.h"

using namespace radbake;
using namespace radbake::testing;

TEST_CASE("geometry parts: a hull wall occludes, a hull column beside the link does not") {
    const auto s = rectangle(2, 0.0, 0.0, 1.0, 0.0, 1.0);
    const auto r = rectangle(2, 2.0, 0.0, 1.0, 0.0, 1.0);
    std::vector<DVec3> wall_points;
    for (int i = 0; i < 8; ++i) {
        wall_points.push_back(DVec3((i & 1) ? 1.5 : -0.5, (i & 2) ? 1.5 : -0.5, (i & 4) ? 1.1 : 0.9));
    }
    const ConvexPart wall = partFromPoints(wall_points);
    REQUIRE(wall.closed);
    REQUIRE(wall.planes.size() == 6);
    CHECK(occludesExact(s, r, wall));
    CHECK(occludesObb(shaftBetweenBoxes(boxOfPoints(s), boxOfPoints(r)), wall.obb));
    // A flat square plate at z = 1 (partFromPoints makes a flat part of coplanar points).
    const ConvexPart plate = partFromPoints(rectangle(2, 1.0, -0.5, 1.5, -0.5, 1.5));
    REQUIRE_FALSE(plate.closed);
    CHECK(occludesExact(s, r, plate));
    const ConvexPart small_plate = partFromPoints(rectangle(2, 1.0, 0.1, 0.9, -0.5, 1.5));
    CHECK_FALSE(occludesExact(s, r, small_plate));
}

TEST_CASE("geometry parts: random convex hulls and plates against the brute force") {
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const auto s = rectangle(2, 0.0, 0.0, 1.0, 0.0, 1.0);
    const auto ps = polygonSamplePoints(s, 3);
    size_t claims = 0, real = 0, false_claims = 0, false_outside = 0;
    constexpr int kConfigurations = 3000;
    for (int trial = 0; trial < kConfigurations; ++trial) {
        // Receiver: a random tilted quad-ish triangle pair above the source.
        const double h = 1.5 + u(rng);
        std::vector<DVec3> r = {{u(rng) * 0.3, u(rng) * 0.3, h},
                                {1 + u(rng) * 0.3, u(rng) * 0.3, h + 0.2 * u(rng)},
                                {0.5 + u(rng) * 0.3, 1 + u(rng) * 0.3, h + 0.2 * u(rng)}};
        // Occluder: hull of 12 random points around a centre between the two.
        const DVec3 centre(0.5 + 0.4 * u(rng), 0.5 + 0.4 * u(rng), h * (0.5 + 0.3 * u(rng)));
        const DVec3 spread(0.8 + std::abs(u(rng)), 0.8 + std::abs(u(rng)),
                           trial % 3 == 0 ? 0.0 : 0.05 + 0.3 * std::abs(u(rng)));
        std::vector<DVec3> points;
        for (int i = 0; i < 12; ++i) {
            points.push_back(centre + DVec3(u(rng), u(rng), u(rng)) * spread);
        }
        const ConvexPart part = partFromPoints(points);
        if (part.vertices.empty()) continue;
        const auto pr = polygonSamplePoints(r, 3);
        const SegmentCount count = countSegmentHits(ps, pr, part);
        const bool all_hit = count.hits_strict == count.segments;
        real += all_hit;
        const bool exact = occludesExact(s, r, part);
        claims += exact;
        false_claims += exact && !all_hit;
        if (count.hits_any > 0) {
            const Shaft shaft = shaftBetweenPolygons(s, r);
            false_outside += classifyAabb(shaft, part.aabb) == Side::Outside;
            false_outside += classifyObb(shaft, part.obb) == Side::Outside;
        }
    }
    MESSAGE("geometry parts: " << kConfigurations << " configurations, real occlusions " << real
                               << ", exact claims " << claims << ", false " << false_claims);
    CHECK(false_claims == 0);
    CHECK(false_outside == 0);
    CHECK(real > kConfigurations / 5);
    CHECK(claims > real / 2);
}
