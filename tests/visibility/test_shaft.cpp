// Shaft construction and the AABB / OBB crossing tests on literal configurations.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "part_builders.h"
#include "visibility/shaft.h"

using namespace radbake;
using namespace radbake::testing;

namespace {

Aabb makeBox(DVec3 min, DVec3 max) {
    Aabb box;
    box.add(min);
    box.add(max);
    return box;
}

std::array<DVec3, 8> corners(const Aabb& b) {
    std::array<DVec3, 8> c;
    for (int i = 0; i < 8; ++i) {
        c[i] = DVec3((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                     (i & 4) ? b.max.z : b.min.z);
    }
    return c;
}

double maxOver(const Plane& plane, const Aabb& box) {
    double m = -1e300;
    for (const DVec3& p : corners(box)) m = std::max(m, plane.eval(p));
    return m;
}

}  // namespace

TEST_CASE("box shaft: aligned boxes of equal section have only the union box planes") {
    const Shaft shaft =
        shaftBetweenBoxes(makeBox({0, 0, 0}, {1, 1, 1}), makeBox({3, 0, 0}, {4, 1, 1}));
    CHECK(shaft.kind == ShaftKind::Boxes);
    CHECK(shaft.planes.size() == 6);
    CHECK(shaft.link_axis == 0);
    CHECK(shaft.box.min.x == 0.0);
    CHECK(shaft.box.max.x == 4.0);
    CHECK(shaft.pairs.size() == 2);
}

TEST_CASE("box shaft: a larger receiver adds four side planes touching both boxes") {
    const Aabb a = makeBox({0, 0, 0}, {1, 1, 1});
    const Aabb b = makeBox({3, -1, -1}, {5, 2, 2});
    const Shaft shaft = shaftBetweenBoxes(a, b);
    REQUIRE(shaft.planes.size() == 10);
    // No side planes parallel to x; two parallel to y (the +-z edges), two parallel to z.
    CHECK(shaft.side_begin[1] - shaft.side_begin[0] == 0);
    CHECK(shaft.side_begin[2] - shaft.side_begin[1] == 2);
    CHECK(shaft.side_begin[3] - shaft.side_begin[2] == 2);
    for (size_t i = 6; i < shaft.planes.size(); ++i) {
        const Plane& p = shaft.planes[i];
        CHECK(glm::length(p.normal) == doctest::Approx(1.0).epsilon(1e-15));
        CHECK(p.normal.x < 0.0);  // they lean back towards the small source
        CHECK(maxOver(p, a) == doctest::Approx(0.0).epsilon(1e-12));
        CHECK(maxOver(p, b) == doctest::Approx(0.0).epsilon(1e-12));
    }
    // The plane parallel to z through A's edge (0, 1) and B's edge (3, 2): normal (-1, 3)/sqrt10.
    bool found = false;
    for (size_t i = shaft.side_begin[2]; i < shaft.side_begin[3]; ++i) {
        const DVec3 n = shaft.planes[i].normal;
        if (n.y > 0.0) {
            found = true;
            CHECK(n.x == doctest::Approx(-1.0 / std::sqrt(10.0)));
            CHECK(n.y == doctest::Approx(3.0 / std::sqrt(10.0)));
            CHECK(n.z == 0.0);
        }
    }
    CHECK(found);
}

TEST_CASE("box shaft: crossed boxes reach the maximum of 14 planes, side planes in cyclic order") {
    // A owns both x faces, B the y and z faces: all 8 edges joining an x face to a y or z
    // face separate different owners.
    const Aabb a = makeBox({-2, 0, 0}, {2, 1, 1});
    const Aabb b = makeBox({-1, -2, -2}, {1, 3, 3});
    const Shaft shaft = shaftBetweenBoxes(a, b);
    CHECK(shaft.planes.size() == 14);
    CHECK(shaft.side_begin[1] - shaft.side_begin[0] == 0);  // y and z faces have one owner
    // Cyclic order around y (u = z, v = x) and around z (u = x, v = y): the angle of the
    // normal in the (u, v) plane increases.
    for (int k = 1; k < 3; ++k) {
        const int u = (k + 1) % 3, v = (k + 2) % 3;
        double last = -10.0;
        for (size_t i = shaft.side_begin[k]; i < shaft.side_begin[k + 1]; ++i) {
            const DVec3 n = shaft.planes[i].normal;
            CHECK(std::abs(n[k]) == 0.0);
            double angle = std::atan2(n[v], n[u]);
            if (angle < last) angle += 2.0 * kPi;
            CHECK(angle > last);
            last = angle;
        }
        CHECK(shaft.side_begin[k + 1] - shaft.side_begin[k] == 4);
    }
}

TEST_CASE("box shaft: random boxes lie inside every plane and every side plane touches both") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-5.0, 5.0), s(0.0, 3.0);
    int side_planes = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const DVec3 c0(u(rng), u(rng), u(rng)), c1(u(rng), u(rng), u(rng));
        const Aabb a = makeBox(c0, c0 + DVec3(s(rng), s(rng), s(rng)));
        const Aabb b = makeBox(c1, c1 + DVec3(s(rng), s(rng), s(rng)));
        const Shaft shaft = shaftBetweenBoxes(a, b);
        REQUIRE(shaft.planes.size() <= 14);
        for (size_t i = 0; i < shaft.planes.size(); ++i) {
            const Plane& p = shaft.planes[i];
            REQUIRE(maxOver(p, a) <= 0.0);
            REQUIRE(maxOver(p, b) <= 0.0);
            if (i >= 6) {
                ++side_planes;
                REQUIRE(maxOver(p, a) > -1e-12);
                REQUIRE(maxOver(p, b) > -1e-12);
            }
        }
    }
    CHECK(side_planes > 4000);  // the random pairs do exercise side planes
}

TEST_CASE("polygon shaft: two facing squares give the 6 planes of their box") {
    const auto s = rectangle(2, 0.0, 0.0, 1.0, 0.0, 1.0);
    const auto r = rectangle(2, 2.0, 0.0, 1.0, 0.0, 1.0);
    const Shaft shaft = shaftBetweenPolygons(s, r);
    CHECK(shaft.kind == ShaftKind::Polygons);
    CHECK(shaft.planes.size() == 6);
    for (const Plane& p : shaft.planes) {
        // Each plane holds 4 of the 8 vertices (within the pushed-out tolerance).
        int on = 0;
        for (const auto* poly : {&s, &r}) {
            for (const DVec3& v : *poly) {
                CHECK(p.eval(v) <= 0.0);
                if (p.eval(v) > -1e-12) ++on;
            }
        }
        CHECK(on == 4);
    }
}

TEST_CASE("polygon shaft: tilted triangle to quad is the hull, tighter than the box shaft") {
    const std::vector<DVec3> s = {{0, 0, 0}, {1, 0, 0.5}, {0, 1, 0.2}};
    const std::vector<DVec3> r = {{2, 2, 3}, {3, 2, 3.5}, {3, 3, 4}, {2, 3, 3.5}};  // planar
    const Shaft poly = shaftBetweenPolygons(s, r);
    const Shaft box = shaftBetweenBoxes(boxOfPoints(s), boxOfPoints(r));
    REQUIRE(poly.kind == ShaftKind::Polygons);
    CHECK(poly.planes.size() >= 5);
    CHECK(poly.planes.size() <= s.size() + r.size() + 2);
    for (const Plane& p : poly.planes) {
        int on = 0;
        for (const auto* pts : {&s, &r}) {
            for (const DVec3& v : *pts) {
                REQUIRE(p.eval(v) <= 0.0);
                if (p.eval(v) > -1e-12) ++on;
            }
        }
        CHECK(on >= 3);  // a hull face
    }
    // Random points: inside the polygon shaft implies inside the box shaft; some points are
    // in the box shaft only.
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-0.5, 4.5);
    auto inside = [](const Shaft& sh, const DVec3& p) {
        for (const Plane& q : sh.planes) {
            if (q.eval(p) > 0.0) return false;
        }
        return true;
    };
    int in_poly = 0, in_box_only = 0;
    for (int i = 0; i < 20000; ++i) {
        const DVec3 p(u(rng), u(rng), u(rng));
        const bool ip = inside(poly, p), ib = inside(box, p);
        if (ip) {
            ++in_poly;
            REQUIRE(ib);
        } else if (ib) {
            ++in_box_only;
        }
    }
    CHECK(in_poly > 100);
    CHECK(in_box_only > 100);
}

TEST_CASE("polygon shaft: a warped quad is still inside every plane") {
    const std::vector<DVec3> s = {{0, 0, 0}, {1, 0, 0.5}, {0, 1, 0.2}};
    const std::vector<DVec3> r = {{2, 2, 3}, {3, 2, 3.5}, {3, 3, 4}, {2, 3, 3.2}};  // warped
    const Shaft poly = shaftBetweenPolygons(s, r);
    for (const Plane& p : poly.planes) {
        for (const auto* pts : {&s, &r}) {
            for (const DVec3& v : *pts) CHECK(p.eval(v) <= 0.0);
        }
    }
    CHECK(poly.planes.size() >= 8);  // the warp adds faces holding receiver points only
}

TEST_CASE("polygon shaft: coplanar polygons fall back to the box shaft") {
    const auto s = rectangle(2, 0.0, 0.0, 1.0, 0.0, 1.0);
    const auto r = rectangle(2, 0.0, 2.0, 3.0, 0.0, 1.0);
    const Shaft shaft = shaftBetweenPolygons(s, r);
    CHECK(shaft.kind == ShaftKind::Boxes);
    CHECK(shaft.planes.size() == 6);
}

TEST_CASE("crossing: boxes inside, outside and across a shaft") {
    const auto s = rectangle(2, 0.0, 0.0, 1.0, 0.0, 1.0);
    const auto r = rectangle(2, 2.0, 0.0, 1.0, 0.0, 1.0);
    for (const Shaft& shaft :
         {shaftBetweenPolygons(s, r), shaftBetweenBoxes(boxOfPoints(s), boxOfPoints(r))}) {
        const ConvexPart inside = boxPart({0.4, 0.4, 0.9}, {0.6, 0.6, 1.1});
        const ConvexPart outside = boxPart({2, 0, 0.5}, {3, 1, 1.5});
        const ConvexPart across = boxPart({0.5, 0.5, 1.0}, {3, 0.6, 1.1});
        const ConvexPart beyond = boxPart({0, 0, 2.5}, {1, 1, 3});  // behind the receiver
        const ConvexPart touching_edge = boxPart({1, 1, 0.5}, {2, 2, 1.5});
        const ConvexPart touching_face = boxPart({1, 0, 0.5}, {2, 1, 1.5});
        for (const ConvexPart* p : {&inside, &across, &touching_edge, &touching_face}) {
            CHECK(classifyAabb(shaft, p->aabb) == Side::Crossing);
            CHECK(classifyObb(shaft, p->obb) == Side::Crossing);
        }
        for (const ConvexPart* p : {&outside, &beyond}) {
            CHECK(classifyAabb(shaft, p->aabb) == Side::Outside);
            CHECK(classifyObb(shaft, p->obb) == Side::Outside);
        }
        // A hair beyond the side is outside (1e-9 is far above the rounding tolerance).
        const ConvexPart hair = boxPart({1 + 1e-9, 0, 0.5}, {2, 1, 1.5});
        CHECK(classifyAabb(shaft, hair.aabb) == Side::Outside);
    }
}

TEST_CASE("crossing: an OBB along a tilted side plane is outside while its AABB crosses") {
    // Source [0,1]^2 at z = 0, receiver [2,3]x[0,1] at z = 2: side plane x - z <= 1.
    const auto s = rectangle(2, 0.0, 0.0, 1.0, 0.0, 1.0);
    const auto r = rectangle(2, 2.0, 2.0, 3.0, 0.0, 1.0);
    const Shaft shaft = shaftBetweenBoxes(boxOfPoints(s), boxOfPoints(r));
    const double k = 1.0 / std::sqrt(2.0);
    const DVec3 along(k, 0, k), across(k, 0, -k);
    const DVec3 center = DVec3(2, 0.5, 1) + 0.3 * across;
    const ConvexPart part = orientedBoxPart(center, {along, DVec3(0, 1, 0), across},
                                            DVec3(1.0, 0.5, 0.1));
    CHECK(classifyAabb(shaft, part.aabb) == Side::Crossing);
    CHECK(classifyObb(shaft, part.obb) == Side::Outside);
    // Moved so that it pokes 0.01 into the shaft: crossing.
    const ConvexPart in = orientedBoxPart(DVec3(2, 0.5, 1) + 0.09 * across,
                                          {along, DVec3(0, 1, 0), across}, DVec3(1.0, 0.5, 0.1));
    CHECK(classifyObb(shaft, in.obb) == Side::Crossing);
}

TEST_CASE("crossing: far from the origin, touching boxes stay crossing") {
    // Coordinates ~1e5: rounding of plane values is ~1e-11, the tolerance covers it.
    const DVec3 o(1e5, -2e5, 3e5);
    std::vector<DVec3> s = rectangle(2, 0.0, 0.0, 1.0, 0.0, 1.0);
    std::vector<DVec3> r = rectangle(2, 2.0, 0.3, 1.7, 0.1, 0.9);
    for (auto& p : s) p += o;
    for (auto& p : r) p += o;
    const Shaft shaft = shaftBetweenPolygons(s, r);
    // A box whose corner is exactly the source's corner (0, 0, 0) + o, lying outside.
    const ConvexPart corner = boxPart(o + DVec3(-1, -1, -1), o);
    CHECK(classifyAabb(shaft, corner.aabb) == Side::Crossing);
    CHECK(classifyObb(shaft, corner.obb) == Side::Crossing);
}
