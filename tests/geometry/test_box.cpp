#include <doctest/doctest.h>

#include <random>

#include "geometry/box.h"
#include "geometry/parts.h"
#include "geometry/polygon.h"

using namespace radbake;

namespace {

DVec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<double> g;
    DVec3 v;
    do v = DVec3(g(rng), g(rng), g(rng));
    while (glm::length(v) < 1e-6);
    return glm::normalize(v);
}

}  // namespace

TEST_CASE("tight OBB of random rotated clouds: contains every point, never larger than PCA") {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int strictly_better = 0;
    for (int cloud = 0; cloud < 1000; ++cloud) {
        const glm::dquat q = glm::angleAxis(kPi * u(rng), randomUnit(rng));
        const DVec3 scale(1.0 + 3.0 * std::abs(u(rng)), 1.0 + std::abs(u(rng)), 0.05 + std::abs(u(rng)));
        const DVec3 offset = DVec3(u(rng), u(rng), u(rng)) * 50.0;
        std::vector<DVec3> points;
        const int n = 4 + cloud % 60;
        // Alternate box-like (uniform) and blob-like (gaussian-ish) clouds.
        for (int i = 0; i < n; ++i) {
            DVec3 p(u(rng), u(rng), u(rng));
            if (cloud % 2) p *= std::abs(u(rng));
            points.push_back(q * (p * scale) + offset);
        }
        const Obb tight = fitObb(points);
        const Obb pca = pcaObb(points);
        const double tolerance = 1e-9 * pointExtent(points);
        for (const DVec3& p : points) {
            CHECK(contains(tight, p, tolerance));
            CHECK(contains(pca, p, tolerance));
        }
        // Orthonormal, right-handed axes.
        CHECK(glm::dot(glm::cross(tight.axes[0], tight.axes[1]), tight.axes[2]) == doctest::Approx(1.0));
        CHECK(std::abs(glm::dot(tight.axes[0], tight.axes[1])) < 1e-9);
        CHECK(obbVolume(tight) <= obbVolume(pca));
        strictly_better += obbVolume(tight) < 0.99 * obbVolume(pca);
    }
    // The refinement must actually win: measured 995 of 1000 clouds at least 1% smaller than
    // PCA (mean volume 0.83 of PCA's) when this was written; fail if that collapses.
    CHECK(strictly_better > 900);
}

TEST_CASE("OBB of a rotated box's corners is the box") {
    const glm::dquat q = glm::angleAxis(kPi / 6, DVec3(1, 0, 0)) * glm::angleAxis(kPi / 6, DVec3(0, 1, 0));
    std::vector<DVec3> corners;
    for (int i = 0; i < 8; ++i)
        corners.push_back(q * DVec3(i & 1 ? 3 : -3, i & 2 ? 1 : -1, i & 4 ? 0.5 : -0.5) + DVec3(4, 5, 6));
    const Obb box = fitObb(corners);
    CHECK(obbVolume(box) == doctest::Approx(12.0).epsilon(1e-12));
    CHECK(box.center.x == doctest::Approx(4.0));
    CHECK(box.center.y == doctest::Approx(5.0));
    CHECK(box.center.z == doctest::Approx(6.0));
    // Corners of the fitted box are the input corners (as sets).
    for (const DVec3& c : boxCorners(box)) {
        double nearest = 1e9;
        for (const DVec3& p : corners) nearest = std::min(nearest, glm::length(c - p));
        CHECK(nearest < 1e-9);
    }
    const Aabb aabb = aabbOf(box);
    for (const DVec3& p : corners) CHECK(contains(aabb, p, 1e-12));
}

TEST_CASE("flat OBB of a planar polygon: zero thickness, min-area rectangle, normal as axis 2") {
    // A right triangle with legs 3 and 4 in a tilted plane: the best rectangle is flush with
    // a side; for a triangle min area is twice the triangle area.
    const DVec3 n = glm::normalize(DVec3(1, 2, 3));
    DVec3 u, v;
    tangentFrame(n, u, v);
    const std::vector<DVec3> tri = {DVec3(1, 1, 1), DVec3(1, 1, 1) + 3.0 * u, DVec3(1, 1, 1) + 4.0 * v};
    const Obb box = flatObb(tri, n);
    CHECK(box.half_extents.z == 0.0);
    CHECK(glm::dot(box.axes[2], n) == doctest::Approx(1.0));
    CHECK(4.0 * box.half_extents.x * box.half_extents.y == doctest::Approx(12.0));
    for (const DVec3& p : tri) CHECK(contains(box, p, 1e-12));
    // partFromPoints on the same points makes a flat part with that box.
    const ConvexPart part = partFromPoints(tri);
    CHECK_FALSE(part.closed);
    CHECK(part.area == doctest::Approx(6.0));
    CHECK(obbTightness(part) == doctest::Approx(2.0));
}

TEST_CASE("box corners: bit i of the index picks the max side of axis i") {
    Aabb box;
    box.add(DVec3(-1, -2, -3));
    box.add(DVec3(1, 2, 3));
    const auto c = boxCorners(box);
    CHECK(c[0] == DVec3(-1, -2, -3));
    CHECK(c[7] == DVec3(1, 2, 3));
    CHECK(c[1] == DVec3(1, -2, -3));
    CHECK(c[2] == DVec3(-1, 2, -3));
    CHECK(c[4] == DVec3(-1, -2, 3));
    Obb obb;
    obb.center = DVec3(1, 1, 1);
    obb.half_extents = DVec3(1, 2, 3);
    const auto d = boxCorners(obb);
    CHECK(d[0] == DVec3(0, -1, -2));
    CHECK(d[7] == DVec3(2, 3, 4));
}

TEST_CASE("polygon utilities") {
    const std::vector<DVec3> square = {DVec3(0, 0, 1), DVec3(2, 0, 1), DVec3(2, 2, 1), DVec3(0, 2, 1)};
    CHECK(newellNormal(square) == DVec3(0, 0, 8));
    CHECK(polygonArea(square) == doctest::Approx(4.0));
    const DVec3 c = polygonCentroid(square);
    CHECK(c == DVec3(1, 1, 1));
    const Plane plane = planeFromPolygon(square);
    CHECK(plane.normal == DVec3(0, 0, 1));
    CHECK(plane.offset == -1.0);
    const Plane p3 = planeFromPoints(DVec3(0, 0, 1), DVec3(1, 0, 1), DVec3(0, 1, 1));
    CHECK(p3.normal == DVec3(0, 0, 1));
    CHECK(p3.eval(DVec3(5, 5, 3)) == 2.0);
    CHECK(pointInConvexPolygon(square, DVec3(0, 0, 1), DVec3(1, 1, 1), 0.0));
    CHECK(pointInConvexPolygon(square, DVec3(0, 0, 1), DVec3(2, 1, 1), 0.0));  // on an edge
    CHECK_FALSE(pointInConvexPolygon(square, DVec3(0, 0, 1), DVec3(2.01, 1, 1), 0.0));
    CHECK(pointInConvexPolygon(square, DVec3(0, 0, 1), DVec3(2.01, 1, 1), 0.02));
    CHECK(isConvexPolygon(square, DVec3(0, 0, 1), 1e-9));
    CHECK_FALSE(isConvexPolygon(square, DVec3(0, 0, -1), 1e-9));  // clockwise around -z
    const std::vector<DVec3> dart = {DVec3(0, 0, 0), DVec3(2, 0, 0), DVec3(1, 0.5, 0), DVec3(1, 2, 0)};
    CHECK_FALSE(isConvexPolygon(dart, DVec3(0, 0, 1), 1e-9));
    const std::vector<DVec3> with_mid = {DVec3(0, 0, 0), DVec3(1, 0, 0), DVec3(2, 0, 0), DVec3(2, 2, 0), DVec3(2, 2, 0), DVec3(0, 2, 0)};
    CHECK(isConvexPolygon(std::vector<DVec3>{DVec3(0, 0, 0), DVec3(1, 0, 0), DVec3(2, 0, 0), DVec3(2, 2, 0), DVec3(0, 2, 0)}, DVec3(0, 0, 1), 1e-9));
    CHECK(removeCollinear(with_mid, 1e-9).size() == 4);
}
