#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "scene/triangulate.h"

using namespace radbake;

namespace {

struct Polygon {
    std::vector<Vec3> positions;
    std::vector<uint32_t> loop;
};

Polygon fromXY(const std::vector<Vec2>& xy) {
    Polygon p;
    for (const Vec2& q : xy) {
        p.loop.push_back(static_cast<uint32_t>(p.positions.size()));
        p.positions.emplace_back(q.x, q.y, 0.0f);
    }
    return p;
}

// Shoelace area of the loop in the XY plane (positive when counter-clockwise).
double shoelace(const Polygon& p) {
    double sum = 0.0;
    for (size_t i = 0; i < p.loop.size(); ++i) {
        const Vec3& a = p.positions[p.loop[i]];
        const Vec3& b = p.positions[p.loop[(i + 1) % p.loop.size()]];
        sum += double(a.x) * b.y - double(b.x) * a.y;
    }
    return 0.5 * sum;
}

DVec3 triangleNormal(const Polygon& p, const UVec3& t) {
    const DVec3 a(p.positions[t.x]), b(p.positions[t.y]), c(p.positions[t.z]);
    return 0.5 * glm::cross(b - a, c - a);
}

// Even-odd point-in-polygon in XY, for brute-force coverage checks.
bool insideXY(const Polygon& p, double x, double y) {
    bool inside = false;
    for (size_t i = 0, j = p.loop.size() - 1; i < p.loop.size(); j = i++) {
        const Vec3& a = p.positions[p.loop[i]];
        const Vec3& b = p.positions[p.loop[j]];
        if ((a.y > y) != (b.y > y) && x < (b.x - a.x) * (y - a.y) / (b.y - a.y) + a.x) inside = !inside;
    }
    return inside;
}

// Checks that the triangles exactly tile the polygon: every triangle faces +Z (the loop's
// winding), their areas add up to the polygon's, and every triangle's centroid is inside it.
void checkTiling(const Polygon& p, const std::vector<UVec3>& tris, size_t expected_count) {
    CHECK(tris.size() == expected_count);
    double sum = 0.0;
    for (const UVec3& t : tris) {
        const DVec3 n = triangleNormal(p, t);
        CHECK(n.z > 0.0);
        sum += n.z;
        const Vec3 c = (p.positions[t.x] + p.positions[t.y] + p.positions[t.z]) / 3.0f;
        CHECK(insideXY(p, c.x, c.y));
    }
    CHECK(sum == doctest::Approx(shoelace(p)).epsilon(1e-9));
}

}  // namespace

TEST_CASE("triangulate: convex loops become a fan with the loop's winding") {
    Polygon square = fromXY({{0, 0}, {2, 0}, {2, 2}, {0, 2}});
    std::vector<UVec3> tris;
    CHECK(triangulatePolygon(square.positions, square.loop, true, tris) == 2);
    REQUIRE(tris.size() == 2);
    CHECK(tris[0] == UVec3(0, 1, 2));
    CHECK(tris[1] == UVec3(0, 2, 3));
    // the same square ear-clipped tiles the same area
    std::vector<UVec3> clipped;
    CHECK(triangulatePolygon(square.positions, square.loop, false, clipped) == 2);
    checkTiling(square, clipped, 2);
}

TEST_CASE("triangulate: fewer than three points append nothing") {
    Polygon line = fromXY({{0, 0}, {1, 0}});
    std::vector<UVec3> tris;
    CHECK(triangulatePolygon(line.positions, line.loop, false, tris) == 0);
    CHECK(tris.empty());
}

TEST_CASE("triangulate: an L of area 3") {
    Polygon l = fromXY({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
    REQUIRE(shoelace(l) == doctest::Approx(3.0));
    std::vector<UVec3> tris;
    CHECK(triangulatePolygon(l.positions, l.loop, false, tris) == 4);
    checkTiling(l, tris, 4);
}

TEST_CASE("triangulate: a comb with five teeth") {
    // base 0..10 x 0..1, teeth 1 wide and 3 tall at x = 0, 2, 4, 6, 8 -> area 10 + 5*3 = 25
    Polygon comb = fromXY({{0, 0}, {10, 0}, {10, 1}, {9, 1}, {9, 4}, {8, 4}, {8, 1}, {7, 1}, {7, 4}, {6, 4},
                           {6, 1}, {5, 1}, {5, 4}, {4, 4}, {4, 1}, {3, 1}, {3, 4}, {2, 4}, {2, 1}, {1, 1},
                           {1, 4}, {0, 4}});
    REQUIRE(shoelace(comb) == doctest::Approx(10.0 + 5 * 3.0));
    std::vector<UVec3> tris;
    CHECK(triangulatePolygon(comb.positions, comb.loop, false, tris) == comb.loop.size() - 2);
    checkTiling(comb, tris, comb.loop.size() - 2);
}

TEST_CASE("triangulate: a five-pointed star, both windings") {
    std::vector<Vec2> xy;
    for (int i = 0; i < 10; ++i) {
        const double angle = kPi / 2 + i * kPi / 5;
        const double r = i % 2 == 0 ? 2.0 : 0.8;
        xy.emplace_back(float(r * std::cos(angle)), float(r * std::sin(angle)));
    }
    Polygon star = fromXY(xy);
    // closed form: 10 triangles (centre, outer, inner) of area 0.5 * 2 * 0.8 * sin(36 deg)
    const double expected = 10 * 0.5 * 2.0 * 0.8 * std::sin(kPi / 5);
    REQUIRE(shoelace(star) == doctest::Approx(expected).epsilon(1e-6));
    std::vector<UVec3> tris;
    CHECK(triangulatePolygon(star.positions, star.loop, false, tris) == 8);
    checkTiling(star, tris, 8);

    // clockwise: triangles keep the clockwise winding (normals face -Z), same total area
    std::reverse(star.loop.begin(), star.loop.end());
    tris.clear();
    CHECK(triangulatePolygon(star.positions, star.loop, false, tris) == 8);
    double sum = 0.0;
    for (const UVec3& t : tris) {
        CHECK(triangleNormal(star, t).z < 0.0);
        sum -= triangleNormal(star, t).z;
    }
    CHECK(sum == doctest::Approx(expected).epsilon(1e-6));
}

TEST_CASE("triangulate: collinear points leave no zero-area triangle") {
    // a 3x1 rectangle with two extra points on each long edge and one on a short edge
    Polygon p = fromXY({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 0.5f}, {3, 1}, {2, 1}, {1, 1}, {0, 1}});
    std::vector<UVec3> tris;
    const size_t count = triangulatePolygon(p.positions, p.loop, false, tris);
    CHECK(count == 7);
    checkTiling(p, tris, 7);
    for (const UVec3& t : tris) CHECK(triangleNormal(p, t).z > 1e-3);
}

TEST_CASE("triangulate: duplicate points and a self-touching vertex") {
    // an L with a repeated corner, and two squares touching at one point (index reused)
    Polygon dup = fromXY({{0, 0}, {2, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 2}});
    std::vector<UVec3> tris;
    triangulatePolygon(dup.positions, dup.loop, false, tris);
    // (1,1) lies on the diagonal (0,2)-(2,0), so three triangles can tile this L
    checkTiling(dup, tris, 3);
    double sum = 0.0;
    Polygon bow;
    bow.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}, {0, 1, 0}};
    bow.loop = {0, 1, 2, 3, 4, 5, 2, 6};  // vertex 2 visited twice
    tris.clear();
    triangulatePolygon(bow.positions, bow.loop, false, tris);
    sum = 0.0;
    for (const UVec3& t : tris) {
        CHECK(triangleNormal(bow, t).z > 0.0);
        sum += triangleNormal(bow, t).z;
    }
    CHECK(tris.size() == 4);
    CHECK(sum == doctest::Approx(2.0));
}

TEST_CASE("triangulate: a tilted non-convex loop in 3D keeps its area and winding") {
    // the L rotated into a plane whose dominant axis is -X
    Polygon l = fromXY({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
    const Quat rotation = glm::angleAxis(float(kPi / 2), Vec3(0, 1, 0)) * glm::angleAxis(0.3f, Vec3(1, 0, 0));
    for (Vec3& p : l.positions) p = rotation * p;
    const DVec3 plane_normal = DVec3(rotation * Vec3(0, 0, 1));
    REQUIRE(std::abs(plane_normal.x) > 0.9);
    std::vector<UVec3> tris;
    CHECK(triangulatePolygon(l.positions, l.loop, false, tris) == 4);
    double sum = 0.0;
    for (const UVec3& t : tris) {
        const DVec3 n = triangleNormal(l, t);
        CHECK(glm::dot(n, plane_normal) > 0.0);
        sum += glm::length(n);
    }
    CHECK(sum == doctest::Approx(3.0).epsilon(1e-5));
}

TEST_CASE("triangulate: garbage loops end and stay in range") {
    // all points equal, a zig-zag that crosses itself, an out-of-range index
    std::vector<Vec3> positions{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    std::vector<uint32_t> same{0, 1, 2, 3};
    std::vector<UVec3> tris;
    CHECK(triangulatePolygon(positions, same, false, tris) == 2);  // fan fallback
    positions = {{0, 0, 0}, {3, 3, 0}, {3, 0, 0}, {0, 3, 0}, {1, 5, 0}, {-2, 1, 0}};
    std::vector<uint32_t> crossing{0, 1, 2, 3, 4, 5};
    tris.clear();
    const size_t count = triangulatePolygon(positions, crossing, false, tris);
    CHECK(count == tris.size());
    CHECK(count <= 4);
    for (const UVec3& t : tris) CHECK(glm::all(glm::lessThan(t, UVec3(6))));
    std::vector<uint32_t> bad{0, 1, 99, 2};
    tris.clear();
    CHECK(triangulatePolygon(positions, bad, false, tris) == 2);
}
