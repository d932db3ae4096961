// Root polygons cut where another touches or crosses them (contact_cuts.h), against the
// geometry worked out by hand.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "geometry/polygon.h"
#include "radiosity/contact_cuts.h"

using namespace radbake;

namespace {

constexpr double kTolerance = 1e-6;

RootPolygon quad(uint32_t mesh, DVec3 a, DVec3 b, DVec3 c, DVec3 d) { return {mesh, 0, {a, b, c, d}}; }

// The 4 side faces of a box [x0, x1] x [y0, y1] x [0, h] standing on z = 0 (no bottom: the
// blocks of a tessellated Cornell box), facing out, and its top.
void addBlock(std::vector<RootPolygon>& out, uint32_t mesh, double x0, double y0, double x1, double y1, double h) {
    out.push_back(quad(mesh, {x0, y0, 0}, {x1, y0, 0}, {x1, y0, h}, {x0, y0, h}));  // y = y0, faces -y
    out.push_back(quad(mesh, {x1, y0, 0}, {x1, y1, 0}, {x1, y1, h}, {x1, y0, h}));  // x = x1, faces +x
    out.push_back(quad(mesh, {x1, y1, 0}, {x0, y1, 0}, {x0, y1, h}, {x1, y1, h}));  // y = y1, faces +y
    out.push_back(quad(mesh, {x0, y1, 0}, {x0, y0, 0}, {x0, y0, h}, {x0, y1, h}));  // x = x0, faces -x
    out.push_back(quad(mesh, {x0, y0, h}, {x1, y0, h}, {x1, y1, h}, {x0, y1, h}));  // top, faces +z
}

double areaOf(const std::vector<RootPolygon>& polygons, uint32_t mesh) {
    double area = 0.0;
    for (const RootPolygon& p : polygons)
        if (p.mesh == mesh) area += polygonArea(p.loop);
    return area;
}

size_t countOf(const std::vector<RootPolygon>& polygons, uint32_t mesh) {
    size_t n = 0;
    for (const RootPolygon& p : polygons) n += p.mesh == mesh;
    return n;
}

// Every piece convex, facing +z like the floor, and lying on one side of each of the block's
// side planes (no piece straddles the footprint's outline).
void checkFloorPieces(const std::vector<RootPolygon>& polygons, double x0, double y0, double x1, double y1) {
    for (const RootPolygon& p : polygons) {
        if (p.mesh != 0) continue;
        const DVec3 n = glm::normalize(newellNormal(p.loop));
        CHECK(n.z == doctest::Approx(1.0));
        CHECK(isConvexPolygon(p.loop, n, 1e-12));
        for (const double x : {x0, x1}) {
            bool below = false, above = false;
            for (const DVec3& v : p.loop) below = below || v.x < x - 1e-12, above = above || v.x > x + 1e-12;
            // A piece may straddle x = x0 only outside the block's y range.
            if (below && above)
                for (const DVec3& v : p.loop) CHECK((v.y <= y0 + 1e-12 || v.y >= y1 - 1e-12));
        }
        for (const double y : {y0, y1}) {
            bool below = false, above = false;
            for (const DVec3& v : p.loop) below = below || v.y < y - 1e-12, above = above || v.y > y + 1e-12;
            if (below && above)
                for (const DVec3& v : p.loop) CHECK((v.x <= x0 + 1e-12 || v.x >= x1 - 1e-12));
        }
    }
}

}  // namespace

TEST_CASE("a floor is cut along the foot of a block standing on it: the footprint is one piece") {
    std::vector<RootPolygon> polygons{quad(0, {0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0})};
    addBlock(polygons, 1, 1.0, 1.5, 2.0, 3.0, 0.6);
    const size_t cuts = cutAtContacts(polygons, kTolerance, 32);
    // One cut per side of the footprint, each splitting the piece that holds that side.
    CHECK(cuts == 4);
    CHECK(countOf(polygons, 0) == 5);
    CHECK(countOf(polygons, 1) == 5);  // the block's faces meet the floor only on their edges
    CHECK(areaOf(polygons, 0) == doctest::Approx(16.0).epsilon(1e-12));
    checkFloorPieces(polygons, 1.0, 1.5, 2.0, 3.0);
    // The piece under the block is exactly its footprint.
    size_t footprints = 0;
    for (const RootPolygon& p : polygons) {
        if (p.mesh != 0) continue;
        const DVec3 c = polygonCentroid(p.loop);
        if (c.x > 1.0 && c.x < 2.0 && c.y > 1.5 && c.y < 3.0) {
            ++footprints;
            CHECK(polygonArea(p.loop) == doctest::Approx(1.5).epsilon(1e-12));
        }
    }
    CHECK(footprints == 1);
    // The pieces follow each other in place of the floor, then the block's faces in order.
    for (size_t i = 0; i < 5; ++i) CHECK(polygons[i].mesh == 0);
}

TEST_CASE("a lit sliver beside a block's foot is cut off down to 0.1 % of the tile; a hidden one stays below 1 %") {
    // A unit floor tile that a block covers but for a strip 3e-3 wide (0.3 % of the tile) in
    // front of its +x face: the strip is what a point on that face's bottom edge mostly sees.
    std::vector<RootPolygon> lit{quad(0, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0})};
    addBlock(lit, 1, -1.0, -1.0, 0.997, 2.0, 0.5);
    CHECK(cutAtContacts(lit, kTolerance, 32) == 1);
    REQUIRE(countOf(lit, 0) == 2);
    double smallest = 1.0;
    for (const RootPolygon& p : lit)
        if (p.mesh == 0) smallest = std::min(smallest, polygonArea(p.loop));
    CHECK(smallest == doctest::Approx(3e-3).epsilon(1e-9));
    // The same strip under a block (behind its -x face) moves the tile's mean by at most 0.3 %.
    std::vector<RootPolygon> hidden{quad(0, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0})};
    addBlock(hidden, 1, 0.997, -1.0, 2.0, 2.0, 0.5);
    CHECK(cutAtContacts(hidden, kTolerance, 32) == 0);
    CHECK(countOf(hidden, 0) == 1);
    // Below 0.1 % in front, not cut either.
    std::vector<RootPolygon> thin{quad(0, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0})};
    addBlock(thin, 1, -1.0, -1.0, 0.9995, 2.0, 0.5);
    CHECK(cutAtContacts(thin, kTolerance, 32) == 0);
}

TEST_CASE("a beam going into the ground is cut at the ground, and the ground along the beam") {
    // Ground 10 x 10 at z = 0; a beam [-4, 4] x [-0.15, 0.15] x [-0.35, 0.05] crossing it.
    std::vector<RootPolygon> polygons{quad(0, {-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0})};
    const double y0 = -0.15, y1 = 0.15, z0 = -0.35, z1 = 0.05;
    polygons.push_back(quad(1, {-4, y0, z0}, {4, y0, z0}, {4, y0, z1}, {-4, y0, z1}));  // faces -y
    polygons.push_back(quad(1, {4, y1, z0}, {-4, y1, z0}, {-4, y1, z1}, {4, y1, z1}));  // faces +y
    cutAtContacts(polygons, kTolerance, 32);
    // Each side face in two at z = 0: 0.35 below, 0.05 above.
    size_t above = 0, below = 0;
    for (const RootPolygon& p : polygons) {
        if (p.mesh != 1) continue;
        double lo = 1e9, hi = -1e9;
        for (const DVec3& v : p.loop) lo = std::min(lo, v.z), hi = std::max(hi, v.z);
        CHECK((std::abs(lo) < 1e-12 || std::abs(hi) < 1e-12));
        if (lo > -1e-12) {
            ++above;
            CHECK(polygonArea(p.loop) == doctest::Approx(8 * 0.05).epsilon(1e-9));
        } else {
            ++below;
            CHECK(polygonArea(p.loop) == doctest::Approx(8 * 0.35).epsilon(1e-9));
        }
    }
    CHECK(above == 2);
    CHECK(below == 2);
    // The ground in three strips across y = -0.15 and y = 0.15 (the faces' full lines).
    CHECK(countOf(polygons, 0) == 3);
    CHECK(areaOf(polygons, 0) == doctest::Approx(100.0).epsilon(1e-12));
}

TEST_CASE("polygons that only share edges, lie in one plane or barely rise are left whole") {
    // A room's corner: floor and two walls meeting on their edges; a coplanar neighbour tile;
    // a sliver standing on the floor, rising 1e-6 of its size.
    std::vector<RootPolygon> polygons{
        quad(0, {0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}),
        quad(1, {2, 0, 0}, {4, 0, 0}, {4, 2, 0}, {2, 2, 0}),
        quad(2, {0, 0, 0}, {0, 2, 0}, {0, 2, 2}, {0, 0, 2}),
        quad(3, {2, 0, 0}, {0, 0, 0}, {0, 0, 2}, {2, 0, 2}),
        {4, 0, {DVec3(0.5, 1, 0), DVec3(1.5, 1, 0), DVec3(1, 1, 2e-6)}},
    };
    const std::vector<RootPolygon> before = polygons;
    CHECK(cutAtContacts(polygons, kTolerance, 32) == 0);
    REQUIRE(polygons.size() == before.size());
    for (size_t i = 0; i < polygons.size(); ++i) CHECK(polygons[i].loop == before[i].loop);
}

// A 0.2 m lamp at z = 0.99 facing down in a unit room: its plane crosses the four walls' top
// tiles (z from 0.9375 to 1), each cut into a 1 cm strip above the plane and the lit rest, and
// that rest once more halfway down (its direct light rises from zero at the plane); the
// ceiling (parallel), the floor (not crossed) and a wall beyond the lamp's reach stay whole.
TEST_CASE("the plane of a light source cuts the walls it crosses near it, and nothing else") {
    std::vector<RootPolygon> polygons{
        quad(0, {0.4, 0.4, 0.99}, {0.4, 0.6, 0.99}, {0.6, 0.6, 0.99}, {0.6, 0.4, 0.99}),  // lamp, faces -z
        quad(1, {0, 0, 0.9375}, {0, 0.0625, 0.9375}, {0, 0.0625, 1}, {0, 0, 1}),          // wall x = 0, top tile
        quad(2, {1, 0, 0.9375}, {1, 0, 1}, {1, 0.0625, 1}, {1, 0.0625, 0.9375}),          // wall x = 1, top tile
        quad(3, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}),                              // ceiling
        quad(4, {0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}),                              // floor
        quad(5, {9, 0, 0.9375}, {9, 0.0625, 0.9375}, {9, 0.0625, 1}, {9, 0, 1}),          // 8 m away
    };
    std::vector<bool> emits{true, false, false, false, false, false};
    const std::vector<bool> none(emits.size(), false), all(emits.size(), true);
    CHECK(cutAtSourcePlanes(polygons, emits, none, all, kTolerance, 32) == 4);
    REQUIRE(polygons.size() == 10);
    CHECK(countOf(polygons, 0) == 1);
    for (const uint32_t wall : {1u, 2u}) {
        CAPTURE(wall);
        CHECK(countOf(polygons, wall) == 3);
        CHECK(areaOf(polygons, wall) == doctest::Approx(0.0625 * 0.0625).epsilon(1e-12));
        const double halfway = 0.99 - 0.5 * (0.99 - 0.9375);
        for (const RootPolygon& p : polygons) {
            if (p.mesh != wall) continue;
            double lo = 1.0, hi = 0.0;
            for (const DVec3& v : p.loop) lo = std::min(lo, v.z), hi = std::max(hi, v.z);
            CHECK(((lo == doctest::Approx(0.99) && hi == doctest::Approx(1.0)) ||
                   (lo == doctest::Approx(halfway) && hi == doctest::Approx(0.99)) ||
                   (lo == doctest::Approx(0.9375) && hi == doctest::Approx(halfway))));
        }
    }
    for (const uint32_t whole : {3u, 4u, 5u}) CHECK(countOf(polygons, whole) == 1);
}

// The same lamp as 2 x 2 tiles, 1 cm under a ceiling of 0.25 m tiles: the ceiling tiles that
// straddle the lamp's outline are cut along it (not along the lines between the lamp's own
// tiles), each piece wholly over the lamp or wholly beside it; a ceiling tile beyond the
// lamp's footprint, a parallel panel 0.1 m above the lamp (a gap of a third of its size), and
// the floor it faces stay whole.
TEST_CASE("a surface right behind a light source is cut along the source's outline") {
    std::vector<RootPolygon> polygons;
    std::vector<bool> outlines;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            const double x = 0.4 + 0.1 * i, y = 0.4 + 0.1 * j;
            polygons.push_back(quad(0, {x, y, 0.99}, {x, y + 0.1, 0.99}, {x + 0.1, y + 0.1, 0.99}, {x + 0.1, y, 0.99}));
            outlines.push_back(true);
        }
    // Ceiling tiles facing down (-z), 0.25 m: [0.25, 0.5] and [0.5, 0.75] straddle 0.4 and 0.6.
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const double x = 0.25 * i, y = 0.25 * j;
            polygons.push_back(quad(1, {x, y, 1}, {x, y + 0.25, 1}, {x + 0.25, y + 0.25, 1}, {x + 0.25, y, 1}));
            outlines.push_back(false);
        }
    polygons.push_back(quad(2, {0.3, 0.3, 1.09}, {0.3, 0.7, 1.09}, {0.7, 0.7, 1.09}, {0.7, 0.3, 1.09}));  // far panel
    polygons.push_back(quad(3, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}));                                // floor
    outlines.push_back(false);
    outlines.push_back(false);
    const std::vector<bool> emits(polygons.size(), false), reflects(polygons.size(), true);
    // The four straddling tiles each hold a corner of the lamp: one line cuts it in two, the
    // other both halves (3 cuts, 4 pieces each).
    CHECK(cutAtSourcePlanes(polygons, emits, outlines, reflects, kTolerance, 32) == 12);
    CHECK(countOf(polygons, 0) == 4);
    CHECK(countOf(polygons, 1) == 12 + 4 * 4);
    CHECK(areaOf(polygons, 1) == doctest::Approx(1.0).epsilon(1e-12));
    CHECK(countOf(polygons, 2) == 1);
    CHECK(countOf(polygons, 3) == 1);
    // Every ceiling piece lies wholly over the lamp's footprint or wholly beside it.
    for (const RootPolygon& p : polygons) {
        if (p.mesh != 1) continue;
        double lo_x = 1, hi_x = 0, lo_y = 1, hi_y = 0;
        for (const DVec3& v : p.loop)
            lo_x = std::min(lo_x, v.x), hi_x = std::max(hi_x, v.x), lo_y = std::min(lo_y, v.y), hi_y = std::max(hi_y, v.y);
        const bool inside = lo_x >= 0.4 - 1e-9 && hi_x <= 0.6 + 1e-9 && lo_y >= 0.4 - 1e-9 && hi_y <= 0.6 + 1e-9;
        const bool beside = hi_x <= 0.4 + 1e-9 || lo_x >= 0.6 - 1e-9 || hi_y <= 0.4 + 1e-9 || lo_y >= 0.6 - 1e-9;
        CHECK((inside || beside));
    }
}
