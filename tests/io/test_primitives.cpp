// Primitive tessellations checked against the closed-form area and volume of the polygonal
// approximation they are meant to be (not of the smooth shape), and for outward orientation.
#include <doctest/doctest.h>

#include <cmath>

#include "io/vrml/primitives.h"

using namespace radbake;
using namespace radbake::vrml;

namespace {

constexpr double kN = kRoundSegments;
// Positions are stored as float: relative errors of a few float epsilons per vertex,
// summed over ~1000 triangles, stay far below 1e-5.
constexpr double kRel = 1e-5;

double meshArea(const Mesh& mesh) {
    double area = 0.0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) area += triangleArea(mesh, t);
    return area;
}

// Divergence theorem: positive for a closed mesh whose triangles turn counter-clockwise
// seen from outside.
double signedVolume(const Mesh& mesh) {
    double volume = 0.0;
    for (const UVec3& t : mesh.triangles) {
        const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
        volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return volume;
}

// For shapes convex around the origin: every triangle's normal points away from the origin.
int inwardTriangles(const Mesh& mesh) {
    int inward = 0;
    for (const UVec3& t : mesh.triangles) {
        const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
        const DVec3 n = glm::cross(b - a, c - a);
        if (glm::dot(n, (a + b + c) / 3.0) <= 0.0) ++inward;
    }
    return inward;
}

// Polygon ids run 0..polygon_count-1 with each polygon's triangles contiguous and coplanar.
void checkPolygonStructure(const Mesh& mesh) {
    REQUIRE(mesh.triangle_polygon.size() == mesh.triangles.size());
    uint32_t expected = 0;
    DVec3 first_normal(0.0);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const UVec3& tri = mesh.triangles[t];
        const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
        const DVec3 n = glm::normalize(glm::cross(b - a, c - a));
        if (t == 0 || mesh.triangle_polygon[t] != mesh.triangle_polygon[t - 1]) {
            CHECK(mesh.triangle_polygon[t] == expected);
            ++expected;
            first_normal = n;
        } else {
            CHECK(glm::dot(n, first_normal) > 1.0 - 1e-6);
        }
    }
    CHECK(mesh.polygon_count == expected);
}

double ngonArea(double r) { return 0.5 * kN * r * r * std::sin(2.0 * kPi / kN); }

}  // namespace

TEST_CASE("box: six quads, exact area and volume, outward") {
    Mesh mesh;
    appendBox(mesh, Vec3(2.0f, 3.0f, 4.0f));
    CHECK(mesh.polygon_count == 6);
    CHECK(mesh.triangles.size() == 12);
    CHECK(mesh.positions.size() == 8);
    CHECK(mesh.convex_solid);
    checkPolygonStructure(mesh);
    CHECK(meshArea(mesh) == doctest::Approx(2.0 * (6 + 12 + 8)).epsilon(kRel));
    CHECK(signedVolume(mesh) == doctest::Approx(24.0).epsilon(kRel));
    CHECK(inwardTriangles(mesh) == 0);
    for (const Vec3& p : mesh.positions) {
        CHECK(std::abs(p.x) == 1.0f);
        CHECK(std::abs(p.y) == 1.5f);
        CHECK(std::abs(p.z) == 2.0f);
    }
}

TEST_CASE("appending a second shape continues polygon ids and is no longer one convex solid") {
    Mesh mesh;
    appendBox(mesh, Vec3(1.0f));
    appendBox(mesh, Vec3(1.0f));
    CHECK(mesh.polygon_count == 12);
    CHECK(mesh.triangles.size() == 24);
    CHECK_FALSE(mesh.convex_solid);
    checkPolygonStructure(mesh);
    CHECK(mesh.triangles[12].x >= 8u);  // the second box indexes its own vertices
}

TEST_CASE("sphere: closed-form area and volume of the polygonal approximation") {
    const double r = 1.5;
    Mesh mesh;
    appendSphere(mesh, static_cast<float>(r));
    CHECK(mesh.polygon_count == static_cast<uint32_t>(kRoundSegments * kSphereBands));
    CHECK(mesh.triangles.size() == static_cast<size_t>(2 * kRoundSegments * (kSphereBands - 1)));
    CHECK(mesh.convex_solid);
    checkPolygonStructure(mesh);
    CHECK(inwardTriangles(mesh) == 0);

    // Band k lies between latitudes theta_k and theta_k+1: n isosceles trapezoids (triangles at
    // the poles) whose height joins the midpoints of the parallel edges; its volume is an
    // n-gon frustum.
    double area = 0.0, volume = 0.0;
    const double s = std::sin(kPi / kN), c = std::cos(kPi / kN);
    for (int k = 0; k < kSphereBands; ++k) {
        const double t0 = kPi * k / kSphereBands, t1 = kPi * (k + 1) / kSphereBands;
        const double rho0 = r * std::sin(t0), rho1 = r * std::sin(t1);
        const double dy = r * (std::cos(t0) - std::cos(t1));
        area += kN * (rho0 + rho1) * s * std::sqrt(dy * dy + (rho0 - rho1) * (rho0 - rho1) * c * c);
        const double a0 = ngonArea(rho0), a1 = ngonArea(rho1);
        volume += dy / 3.0 * (a0 + a1 + std::sqrt(a0 * a1));
    }
    CHECK(meshArea(mesh) == doctest::Approx(area).epsilon(kRel));
    CHECK(signedVolume(mesh) == doctest::Approx(volume).epsilon(kRel));
    // And the approximation is close to the true sphere (inscribed, so a little smaller).
    CHECK(volume < 4.0 / 3.0 * kPi * r * r * r);
    CHECK(volume > 0.97 * 4.0 / 3.0 * kPi * r * r * r);
}

TEST_CASE("cylinder: n side quads and two n-gon caps") {
    const double r = 0.5, h = 2.0;
    Mesh mesh;
    appendCylinder(mesh, static_cast<float>(r), static_cast<float>(h), true, true, true);
    CHECK(mesh.polygon_count == static_cast<uint32_t>(kRoundSegments + 2));
    CHECK(mesh.triangles.size() == static_cast<size_t>(2 * kRoundSegments + 2 * (kRoundSegments - 2)));
    CHECK(mesh.convex_solid);
    checkPolygonStructure(mesh);
    CHECK(inwardTriangles(mesh) == 0);
    const double side = kN * 2.0 * r * std::sin(kPi / kN) * h;
    CHECK(meshArea(mesh) == doctest::Approx(side + 2.0 * ngonArea(r)).epsilon(kRel));
    CHECK(signedVolume(mesh) == doctest::Approx(ngonArea(r) * h).epsilon(kRel));
    float y_min = 1e9f, y_max = -1e9f;
    for (const Vec3& p : mesh.positions) {
        y_min = std::min(y_min, p.y);
        y_max = std::max(y_max, p.y);
    }
    CHECK(y_min == -1.0f);
    CHECK(y_max == 1.0f);
}

TEST_CASE("cylinder parts: side only, top only") {
    const double r = 1.0, h = 1.0;
    Mesh side_only;
    appendCylinder(side_only, 1.0f, 1.0f, true, false, false);
    CHECK(side_only.polygon_count == static_cast<uint32_t>(kRoundSegments));
    CHECK_FALSE(side_only.convex_solid);
    CHECK(meshArea(side_only) == doctest::Approx(kN * 2.0 * r * std::sin(kPi / kN) * h).epsilon(kRel));

    Mesh top_only;
    appendCylinder(top_only, 1.0f, 1.0f, false, true, false);
    CHECK(top_only.polygon_count == 1);
    CHECK_FALSE(top_only.convex_solid);
    CHECK(meshArea(top_only) == doctest::Approx(ngonArea(r)).epsilon(kRel));
    for (const UVec3& t : top_only.triangles) {
        const Vec3 n = glm::cross(top_only.positions[t.y] - top_only.positions[t.x],
                                  top_only.positions[t.z] - top_only.positions[t.x]);
        CHECK(n.y > 0.0f);  // the top cap faces +Y
    }
}

TEST_CASE("cone: n side triangles and an n-gon base facing -Y") {
    const double r = 1.0, h = 3.0;
    Mesh mesh;
    appendCone(mesh, static_cast<float>(r), static_cast<float>(h), true, true);
    CHECK(mesh.polygon_count == static_cast<uint32_t>(kRoundSegments + 1));
    CHECK(mesh.convex_solid);
    checkPolygonStructure(mesh);
    CHECK(inwardTriangles(mesh) == 0);
    // Each side triangle: base 2 r sin(pi/n), height from the base edge midpoint (at distance
    // r cos(pi/n) from the axis) to the apex.
    const double slant = std::sqrt(h * h + r * std::cos(kPi / kN) * r * std::cos(kPi / kN));
    const double side = kN * r * std::sin(kPi / kN) * slant;
    CHECK(meshArea(mesh) == doctest::Approx(side + ngonArea(r)).epsilon(kRel));
    CHECK(signedVolume(mesh) == doctest::Approx(ngonArea(r) * h / 3.0).epsilon(kRel));

    Mesh base_only;
    appendCone(base_only, 1.0f, 3.0f, false, true);
    CHECK(base_only.polygon_count == 1);
    CHECK_FALSE(base_only.convex_solid);
    const UVec3 t = base_only.triangles[0];
    const Vec3 n = glm::cross(base_only.positions[t.y] - base_only.positions[t.x],
                              base_only.positions[t.z] - base_only.positions[t.x]);
    CHECK(n.y < 0.0f);
    CHECK(base_only.positions[t.x].y == -1.5f);
}
