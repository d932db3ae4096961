#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>

#include "geometry/hull.h"
#include "geometry/polygon.h"

using namespace radbake;

namespace {

// Brute-force hull of points in general position: a triple is a facet when every other
// point lies strictly on one side of its plane. Returns the facet vertices and the volume.
void bruteHull(const std::vector<DVec3>& p, std::set<size_t>& vertices, double& volume) {
    DVec3 centroid(0.0);
    for (const DVec3& q : p) centroid += q;
    centroid /= double(p.size());
    volume = 0.0;
    for (size_t i = 0; i < p.size(); ++i)
        for (size_t j = i + 1; j < p.size(); ++j)
            for (size_t k = j + 1; k < p.size(); ++k) {
                const DVec3 n = glm::cross(p[j] - p[i], p[k] - p[i]);
                int above = 0, below = 0;
                for (size_t m = 0; m < p.size(); ++m) {
                    if (m == i || m == j || m == k) continue;
                    const double d = glm::dot(n, p[m] - p[i]);
                    above += d > 0;
                    below += d < 0;
                }
                if (above && below) continue;
                vertices.insert({i, j, k});
                volume += std::abs(glm::dot(n, centroid - p[i])) / 6.0;
            }
}

}  // namespace

TEST_CASE("quickhull matches a brute-force hull on random clouds") {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int cloud = 0; cloud < 200; ++cloud) {
        const int n = 4 + cloud % 37;
        std::vector<DVec3> points;
        const DVec3 scale(u(rng) + 2.0, u(rng) + 2.0, 0.1 + std::abs(u(rng)));
        for (int i = 0; i < n; ++i) points.push_back(DVec3(u(rng), u(rng), u(rng)) * scale + DVec3(100.0, -50.0, 7.0));
        const Hull3 hull = quickhull(points);
        REQUIRE(hull.dimension == 3);
        std::set<size_t> expected;
        double expected_volume = 0.0;
        bruteHull(points, expected, expected_volume);
        // Same vertex set: every hull vertex is extreme and every extreme point is a vertex.
        std::set<size_t> got;
        for (const DVec3& v : hull.vertices) {
            const auto it = std::find(points.begin(), points.end(), v);
            REQUIRE(it != points.end());
            got.insert(size_t(it - points.begin()));
        }
        CHECK(got == expected);
        CHECK(hull.volume == doctest::Approx(expected_volume).epsilon(1e-9));
        CHECK(hull.planes.size() == hull.faces.size());
        // Every input point inside every plane (rounding tolerance of coordinates ~100).
        for (const Plane& plane : hull.planes)
            for (const DVec3& p : points) CHECK(plane.eval(p) <= 1e-11);
        // Faces are counter-clockwise seen from outside: Newell normal agrees with the plane.
        for (size_t f = 0; f < hull.faces.size(); ++f) {
            std::vector<DVec3> loop;
            for (uint32_t i : hull.faces[f]) loop.push_back(hull.vertices[i]);
            CHECK(glm::dot(glm::normalize(newellNormal(loop)), hull.planes[f].normal) > 0.999999);
        }
        // Euler: V - E + F = 2 for the (triangulated, general position) hull.
        size_t edges = 0;
        for (const auto& face : hull.faces) edges += face.size();
        CHECK(hull.vertices.size() - edges / 2 + hull.faces.size() == 2);
    }
}

TEST_CASE("quickhull of a grid cube merges coplanar faces and drops face and edge points") {
    std::vector<DVec3> points;
    for (int x = 0; x <= 4; ++x)
        for (int y = 0; y <= 4; ++y)
            for (int z = 0; z <= 4; ++z) points.push_back(DVec3(x, y, z) * 0.25);
    const Hull3 hull = quickhull(points);
    CHECK(hull.dimension == 3);
    CHECK(hull.vertices.size() == 8);
    CHECK(hull.faces.size() == 6);
    for (const auto& face : hull.faces) CHECK(face.size() == 4);
    CHECK(hull.volume == doctest::Approx(1.0).epsilon(1e-12));
}

TEST_CASE("quickhull degenerate inputs do not crash and report their dimension") {
    CHECK(quickhull(std::vector<DVec3>{}).dimension == -1);
    const Hull3 point = quickhull(std::vector<DVec3>(5, DVec3(1, 2, 3)));
    CHECK(point.dimension == 0);
    CHECK(point.vertices.size() == 1);
    std::vector<DVec3> line;
    for (int i = 0; i < 7; ++i) line.push_back(DVec3(1, 2, 3) + DVec3(1, 1, 0) * double(i % 4));
    const Hull3 segment = quickhull(line);
    CHECK(segment.dimension == 1);
    REQUIRE(segment.vertices.size() == 2);
    CHECK(glm::length(segment.vertices[0] - segment.vertices[1]) == doctest::Approx(3.0 * std::sqrt(2.0)));
    // A tilted square grid with interior points: flat hull of 4 corners.
    std::vector<DVec3> plane;
    for (int x = 0; x <= 3; ++x)
        for (int y = 0; y <= 3; ++y) plane.push_back(DVec3(x, y, x + y));
    const Hull3 flat = quickhull(plane);
    CHECK(flat.dimension == 2);
    CHECK(flat.vertices.size() == 4);
    CHECK(polygonArea(flat.vertices) == doctest::Approx(9.0 * std::sqrt(3.0)));
    // Duplicated tetrahedron corners.
    std::vector<DVec3> tetra = {DVec3(0, 0, 0), DVec3(1, 0, 0), DVec3(0, 1, 0), DVec3(0, 0, 1)};
    for (int i = 0; i < 3; ++i) tetra.insert(tetra.end(), tetra.begin(), tetra.begin() + 4);
    const Hull3 t = quickhull(tetra);
    CHECK(t.vertices.size() == 4);
    CHECK(t.faces.size() == 4);
    CHECK(t.volume == doctest::Approx(1.0 / 6.0));
}

TEST_CASE("2D hull and minimum-area rectangle") {
    // Square rotated by 30 degrees with points inside and on its edges.
    const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
    auto rot = [&](double x, double y) { return DVec2(c * x - s * y + 3.0, s * x + c * y - 1.0); };
    std::vector<DVec2> pts;
    for (int x = 0; x <= 4; ++x)
        for (int y = 0; y <= 2; ++y) pts.push_back(rot(x * 0.5, y * 0.5));
    const std::vector<uint32_t> ring = convexHull2d(pts, 1e-12);
    REQUIRE(ring.size() == 4);
    std::vector<DVec2> hull;
    for (uint32_t i : ring) hull.push_back(pts[i]);
    double signed_area = 0.0;
    for (size_t i = 0; i < hull.size(); ++i) {
        const DVec2 a = hull[i], b = hull[(i + 1) % hull.size()];
        signed_area += a.x * b.y - a.y * b.x;
    }
    CHECK(signed_area / 2.0 == doctest::Approx(2.0));  // counter-clockwise, 2 x 1
    const Rect2 rect = minAreaRect(hull);
    CHECK(rect.area() == doctest::Approx(2.0));
    // The rectangle is aligned with the square's rotated axes (either one as u).
    const double align = std::max(std::abs(rect.axis_u.x * c + rect.axis_u.y * s),
                                  std::abs(rect.axis_u.x * -s + rect.axis_u.y * c));
    CHECK(align == doctest::Approx(1.0).epsilon(1e-12));
    CHECK(rect.center.x == doctest::Approx(rot(1.0, 0.5).x));
    CHECK(rect.center.y == doctest::Approx(rot(1.0, 0.5).y));
    // A regular hexagon of circumradius 1: min rectangle is 2 x sqrt(3).
    std::vector<DVec2> hex;
    for (int i = 0; i < 6; ++i) hex.push_back(DVec2(std::cos(i * kPi / 3), std::sin(i * kPi / 3)));
    CHECK(minAreaRect(hex).area() == doctest::Approx(2.0 * std::sqrt(3.0)));
    // Collinear and single points.
    CHECK(convexHull2d(std::vector<DVec2>{DVec2(0, 0), DVec2(1, 1), DVec2(2, 2), DVec2(0.5, 0.5)}).size() == 2);
    CHECK(convexHull2d(std::vector<DVec2>{DVec2(1, 1), DVec2(1, 1)}).size() == 1);
}

TEST_CASE("minimum-area rectangle beats a brute-force angle sweep on random polygons") {
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<DVec2> pts;
        for (int i = 0; i < 3 + trial % 20; ++i) pts.push_back(DVec2(u(rng) * 3.0, u(rng)));
        std::vector<DVec2> hull;
        for (uint32_t i : convexHull2d(pts)) hull.push_back(pts[i]);
        const Rect2 rect = minAreaRect(hull);
        double sweep = std::numeric_limits<double>::max();
        for (int k = 0; k < 3600; ++k) {
            const double a = kPi * k / 3600.0;
            const DVec2 x(std::cos(a), std::sin(a)), y(-x.y, x.x);
            double lx = 1e9, hx = -1e9, ly = 1e9, hy = -1e9;
            for (const DVec2& p : hull) {
                lx = std::min(lx, glm::dot(p, x)), hx = std::max(hx, glm::dot(p, x));
                ly = std::min(ly, glm::dot(p, y)), hy = std::max(hy, glm::dot(p, y));
            }
            sweep = std::min(sweep, (hx - lx) * (hy - ly));
        }
        CHECK(rect.area() <= sweep * (1.0 + 1e-12));
        // ... and it really encloses every point.
        const DVec2 v(-rect.axis_u.y, rect.axis_u.x);
        for (const DVec2& p : pts) {
            CHECK(std::abs(glm::dot(p - rect.center, rect.axis_u)) <= rect.half_extents.x + 1e-12);
            CHECK(std::abs(glm::dot(p - rect.center, v)) <= rect.half_extents.y + 1e-12);
        }
    }
}
