#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "geometry/box.h"
#include "geometry/parts.h"
#include "geometry/polygon.h"
#include "mesh_builders.h"

using namespace radbake;
using namespace radbake::test;

namespace {

PartSet partsOf(std::vector<Mesh> meshes, PartOptions options = {}) {
    Diagnostics diagnostics;
    const PartSet set = buildParts(sceneOf(std::move(meshes)), options, diagnostics);
    CHECK_FALSE(diagnostics.hasErrors());
    return set;
}

Quat tilt30() {
    return glm::angleAxis(float(kPi / 6), Vec3(1, 0, 0)) * glm::angleAxis(float(kPi / 6), Vec3(0, 1, 0));
}

// Brute force: every vertex of every part inside its AABB and OBB; flat parts on their plane
// with a flat box. Tolerance: float positions converted to double, 1e-6 of the extent.
void checkBoxesContainVertices(const PartSet& set) {
    for (const ConvexPart& part : set.parts) {
        const double tolerance = 1e-6 * std::max(1.0, pointExtent(part.vertices));
        for (const DVec3& p : part.vertices) {
            CHECK(contains(part.aabb, p, tolerance));
            CHECK(contains(part.obb, p, tolerance));
            for (const Plane& plane : part.planes) CHECK(plane.eval(p) <= tolerance);
        }
        if (!part.closed) {
            CHECK(part.obb.half_extents.z == 0.0);
            CHECK(std::abs(glm::dot(part.obb.axes[2], part.planes[0].normal)) == doctest::Approx(1.0).epsilon(1e-9));
            CHECK(isConvexPolygon(part.vertices, part.planes[0].normal, 1e-9));
        }
    }
}

}  // namespace

TEST_CASE("a box mesh is one closed part with 6 planes and an exact OBB, also rotated") {
    for (const Quat q : {Quat(1, 0, 0, 0), tilt30()}) {
        for (const bool flagged : {false, true}) {
            Mesh box = boxMesh(Vec3(1.0f, 2.0f, 0.5f), q, Vec3(10, -3, 2));
            box.convex_solid = flagged;
            const PartSet set = partsOf({box});
            REQUIRE(set.parts.size() == 1);
            const ConvexPart& part = set.parts[0];
            CHECK(part.closed);
            CHECK(part.planes.size() == 6);
            CHECK(part.faces.size() == 6);
            CHECK(part.vertices.size() == 8);
            CHECK(part.polygons.size() == 6);
            CHECK(part.volume == doctest::Approx(8.0).epsilon(1e-6));
            CHECK(part.area == doctest::Approx(2 * (2 * 4 + 4 * 1 + 2 * 1)).epsilon(1e-6));
            CHECK(obbVolume(part.obb) / part.volume == doctest::Approx(1.0).epsilon(1e-6));
            // The OBB's half extents are the box's, in some order.
            std::array<double, 3> h{part.obb.half_extents.x, part.obb.half_extents.y, part.obb.half_extents.z};
            std::sort(h.begin(), h.end());
            CHECK(h[0] == doctest::Approx(0.5).epsilon(1e-6));
            CHECK(h[1] == doctest::Approx(1.0).epsilon(1e-6));
            CHECK(h[2] == doctest::Approx(2.0).epsilon(1e-6));
            CHECK(set.stats.closed_parts == 1);
            CHECK(set.stats.max_obb_volume_ratio == doctest::Approx(1.0).epsilon(1e-6));
            CHECK(set.polygon_part[0] == std::vector<uint32_t>(6, 0u));
            // A detected solid carries the detection tolerance (1e-3 of its extent) as the
            // amount its hull may overshoot it; a flagged one only the plane tolerance.
            const double diagonal = 2.0 * std::sqrt(1.0 + 4.0 + 0.25);
            const double relative = flagged ? 1e-5 : 1e-3;
            CHECK(part.inflation >= relative * 1.0);  // at least relative x the shortest side
            CHECK(part.inflation <= relative * diagonal + 1e-4);  // + float rounding at |p| ~ 12
            checkBoxesContainVertices(set);
        }
    }
}

TEST_CASE("a cylinder mesh is one closed part with a plane per side and cap") {
    const PartSet set = partsOf({cylinderMesh(0.5f, 2.0f, 24)});
    REQUIRE(set.parts.size() == 1);
    const ConvexPart& part = set.parts[0];
    CHECK(part.closed);
    CHECK(part.planes.size() == 26);
    CHECK(part.vertices.size() == 48);
    // Volume of the inscribed 24-gon prism: (n/2) r^2 sin(2 pi / n) * height.
    CHECK(part.volume == doctest::Approx(12.0 * 0.25 * std::sin(2 * kPi / 24) * 2.0).epsilon(1e-5));
    // 24 is a multiple of 4, so the tightest box has its sides flush with four side faces:
    // a square of side 2 r cos(pi / 24) (the 24-gon's width across flats), height 2.
    const double side = 2.0 * 0.5 * std::cos(kPi / 24);
    CHECK(obbVolume(part.obb) == doctest::Approx(side * side * 2.0).epsilon(1e-5));
    checkBoxesContainVertices(set);
}

TEST_CASE("a non-convex L-shaped floor splits into 2 convex flat parts") {
    SUBCASE("one polygon") {
        Mesh floor;
        addPolygon(floor, {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(1, 1, 0), Vec3(1, 2, 0), Vec3(0, 2, 0)});
        const PartSet set = partsOf({floor});
        REQUIRE(set.parts.size() == 2);
        CHECK(set.parts[0].area + set.parts[1].area == doctest::Approx(3.0));
        for (const ConvexPart& part : set.parts) {
            CHECK_FALSE(part.closed);
            CHECK(part.vertices.size() == 4);
            CHECK(part.polygons == std::vector<uint32_t>{0});
            CHECK(part.planes[0].normal.z == doctest::Approx(1.0));
        }
        checkBoxesContainVertices(set);
    }
    SUBCASE("three unit squares") {
        Mesh floor;
        addPolygon(floor, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)});
        addPolygon(floor, {Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(1, 1, 0)});
        addPolygon(floor, {Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(1, 2, 0), Vec3(0, 2, 0)});
        const PartSet set = partsOf({floor});
        REQUIRE(set.parts.size() == 2);
        const double a0 = set.parts[0].area, a1 = set.parts[1].area;
        CHECK(std::min(a0, a1) == doctest::Approx(1.0));
        CHECK(std::max(a0, a1) == doctest::Approx(2.0));
        CHECK(set.stats.max_obb_area_ratio == doctest::Approx(1.0));
        checkBoxesContainVertices(set);
    }
}

TEST_CASE("coplanar squares sharing an edge merge into one rectangle; perpendicular ones do not") {
    Mesh flat;
    addPolygon(flat, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)});
    addPolygon(flat, {Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(1, 1, 0)});
    PartSet set = partsOf({flat});
    REQUIRE(set.parts.size() == 1);
    CHECK(set.parts[0].vertices.size() == 4);  // the collinear middle corners are dropped
    CHECK(set.parts[0].area == doctest::Approx(2.0));
    CHECK(set.parts[0].polygons == std::vector<uint32_t>{0, 1});
    CHECK(set.polygon_part[0] == std::vector<uint32_t>{0, 0});
    CHECK(set.parts[0].obb.half_extents.x * set.parts[0].obb.half_extents.y == doctest::Approx(0.5));
    checkBoxesContainVertices(set);

    PartOptions no_merge;
    no_merge.merge_coplanar = false;
    CHECK(partsOf({flat}, no_merge).parts.size() == 2);

    Mesh bent;
    addPolygon(bent, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)});
    addPolygon(bent, {Vec3(1, 0, 0), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(1, 1, 0)});
    set = partsOf({bent});
    CHECK(set.parts.size() == 2);
    checkBoxesContainVertices(set);

    // Facing opposite ways (a double-sided sheet's two sides) never merge.
    Mesh flipped;
    addPolygon(flipped, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)});
    addPolygon(flipped, {Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(2, 0, 0)});
    CHECK(partsOf({flipped}).parts.size() == 2);
}

TEST_CASE("an open box (5 faces) gives 5 flat parts") {
    const PartSet set = partsOf({boxMesh(Vec3(1, 1, 1), tilt30(), Vec3(0), true)});
    CHECK(set.parts.size() == 5);
    CHECK(set.stats.flat_parts == 5);
    CHECK(set.stats.closed_parts == 0);
    for (const ConvexPart& part : set.parts) {
        CHECK(part.vertices.size() == 4);
        CHECK(part.area == doctest::Approx(4.0).epsilon(1e-6));
        CHECK(obbTightness(part) == doctest::Approx(1.0).epsilon(1e-6));
    }
    checkBoxesContainVertices(set);
}

TEST_CASE("a closed non-convex mesh is not one part") {
    // An L-shaped prism: 8 faces, the two L caps split in two each, six walls.
    Mesh prism;
    const std::vector<Vec3> l = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(1, 1, 0), Vec3(1, 2, 0), Vec3(0, 2, 0)};
    // Reversed to face down, still fanned from the corner (0, 0) that sees every vertex.
    std::vector<Vec3> bottom = {l[0], l[5], l[4], l[3], l[2], l[1]}, top;
    for (const Vec3& p : l) top.push_back(p + Vec3(0, 0, 1));
    addPolygon(prism, bottom);
    addPolygon(prism, top);
    for (size_t i = 0; i < l.size(); ++i) {
        const Vec3 a = l[i], b = l[(i + 1) % l.size()];
        addPolygon(prism, {a, b, b + Vec3(0, 0, 1), a + Vec3(0, 0, 1)});
    }
    const PartSet set = partsOf({prism});
    CHECK(set.stats.closed_parts == 0);
    CHECK(set.parts.size() == 10);
    checkBoxesContainVertices(set);
}

TEST_CASE("a flagged convex solid without volume falls back to flat parts with a warning") {
    Mesh sheet = boxMesh(Vec3(1, 1, 0), Quat(1, 0, 0, 0));
    sheet.convex_solid = true;
    Diagnostics diagnostics;
    const PartSet set = buildParts(sceneOf({sheet}), {}, diagnostics);
    CHECK(diagnostics.warningCount() == 1);
    CHECK(set.stats.degenerate_solids == 1);
    CHECK(set.stats.closed_parts == 0);
    // Top and bottom are 2x2 squares facing apart; the four side walls have no area.
    CHECK(set.parts.size() == 2);
    CHECK(set.stats.degenerate_polygons == 4);
    checkBoxesContainVertices(set);
}

TEST_CASE("random polygon soups: boxes contain their parts' vertices") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-5.0f, 5.0f);
    Mesh soup;
    for (int i = 0; i < 200; ++i) {
        const Vec3 a(u(rng), u(rng), u(rng));
        addPolygon(soup, {a, a + Vec3(u(rng), u(rng), u(rng)) * 0.2f, a + Vec3(u(rng), u(rng), u(rng)) * 0.2f});
    }
    Mesh grid;  // a 10 x 10 grid of quads: one plane, merges into one rectangle
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 10; ++x)
            addPolygon(grid, {Vec3(x, y, 3), Vec3(x + 1, y, 3), Vec3(x + 1, y + 1, 3), Vec3(x, y + 1, 3)});
    const PartSet set = partsOf({soup, grid, cylinderMesh(1.0f, 3.0f, 64), boxMesh(Vec3(1, 2, 3), tilt30())});
    size_t grid_parts = 0;
    for (const ConvexPart& part : set.parts) grid_parts += part.mesh == 1;
    CHECK(grid_parts == 1);
    CHECK(set.stats.closed_parts == 2);
    CHECK(set.parts.size() == 200 + 1 + 2);
    checkBoxesContainVertices(set);
    for (const ConvexPart& part : set.parts) {
        CHECK(set.bounds.min.x <= part.aabb.min.x);
        CHECK(set.bounds.max.z >= part.aabb.max.z);
    }
}

TEST_CASE("a UV sphere with coordinates rounded to 4 decimals is one closed part") {
    const PartSet set = partsOf({sphereMesh(0.3f, 32, 16, 4)});
    REQUIRE(set.parts.size() == 1);
    CHECK(set.parts[0].closed);
    CHECK(set.parts[0].vertices.size() == 32 * 15 + 2);
    // Box around a sphere: 8 r^3 over (4/3) pi r^3 = 6 / pi, a little more for the polytope.
    CHECK(obbTightness(set.parts[0]) == doctest::Approx(6.0 / kPi).epsilon(0.03));
    checkBoxesContainVertices(set);
    // A dent deeper than the solid tolerance makes it non-convex: flat parts.
    Mesh dented = sphereMesh(0.3f, 32, 16, 0);
    for (Vec3& p : dented.positions)
        if (p == Vec3(0, 0, 0.3f)) p = Vec3(0, 0, 0.25f);
    CHECK(partsOf({dented}).stats.closed_parts == 0);
}

TEST_CASE("a box far from the origin is still one closed part with 6 planes") {
    const PartSet set = partsOf({boxMesh(Vec3(0.5f, 0.25f, 1.0f), tilt30(), Vec3(20000, -15000, 3000))});
    REQUIRE(set.parts.size() == 1);
    CHECK(set.parts[0].planes.size() == 6);
    CHECK(obbTightness(set.parts[0]) == doctest::Approx(1.0).epsilon(1e-3));
    checkBoxesContainVertices(set);
}

TEST_CASE("a polygon with a hole splits into convex pieces that avoid the hole") {
    // 3 x 3 square with a 1 x 1 square hole, triangulated as 8 triangles between the loops.
    Mesh frame;
    const std::vector<Vec3> outer = {Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(3, 3, 0), Vec3(0, 3, 0)};
    const std::vector<Vec3> inner = {Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(2, 2, 0), Vec3(1, 2, 0)};
    for (const Vec3& p : outer) frame.positions.push_back(p);
    for (const Vec3& p : inner) frame.positions.push_back(p);
    for (uint32_t i = 0; i < 4; ++i) {
        const uint32_t j = (i + 1) % 4;
        frame.triangles.push_back(UVec3(i, j, 4 + j));
        frame.triangles.push_back(UVec3(i, 4 + j, 4 + i));
        frame.triangle_polygon.push_back(0);
        frame.triangle_polygon.push_back(0);
    }
    frame.polygon_count = 1;
    const PartSet set = partsOf({frame});
    CHECK(set.parts.size() == 4);  // each trapezoid side; no two merge without covering the hole
    double area = 0.0;
    for (const ConvexPart& part : set.parts) {
        area += part.area;
        CHECK_FALSE(pointInConvexPolygon(part.vertices, part.planes[0].normal, DVec3(1.5, 1.5, 0), 0.0));
    }
    CHECK(area == doctest::Approx(8.0));
    checkBoxesContainVertices(set);
}
