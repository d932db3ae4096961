// patchCovered (geometry/cone_cover.h) against brute force: a patch it calls covered has every
// direction inside it blocked by the triangles, and seams between triangles do not open it.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/cone_cover.h"
#include "geometry/polygon.h"

using namespace radbake;

namespace {

using Triangle = std::array<DVec3, 3>;

bool rayHits(const DVec3& o, const DVec3& d, const Triangle& t) {
    const DVec3 e1 = t[1] - t[0], e2 = t[2] - t[0], p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-15) return false;
    const DVec3 s = o - t[0];
    const double u = glm::dot(s, p) / det;
    const DVec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) / det, dist = glm::dot(e2, q) / det;
    return u >= 0.0 && v >= 0.0 && u + v <= 1.0 && dist > 0.0;
}

// A square patch of directions about `axis`, half-angle `half` (radians) along its frame's axes:
// its outline, four points a side, and a dense grid of directions inside it.
struct Patch {
    std::vector<DVec3> outline, inside;
};

Patch squarePatch(const DVec3& axis, double half) {
    DVec3 u, v;
    tangentFrame(axis, u, v);
    const double t = std::tan(half);
    auto at = [&](double a, double b) { return glm::normalize(axis + u * (a * t) + v * (b * t)); };
    Patch patch;
    for (int k = 0; k < 4; ++k) patch.outline.push_back(at(-1 + 0.5 * k, -1));
    for (int k = 0; k < 4; ++k) patch.outline.push_back(at(1, -1 + 0.5 * k));
    for (int k = 0; k < 4; ++k) patch.outline.push_back(at(1 - 0.5 * k, 1));
    for (int k = 0; k < 4; ++k) patch.outline.push_back(at(-1, 1 - 0.5 * k));
    for (int i = 0; i <= 40; ++i)
        for (int j = 0; j <= 40; ++j) patch.inside.push_back(at(-1 + i / 20.0, -1 + j / 20.0));
    return patch;
}

// A wall x = 1 of two triangles per tile, tiles `tile` wide, with a gap `gap` wide about z = 0.
std::vector<Triangle> wall(double tile, double gap) {
    std::vector<Triangle> triangles;
    for (int i = -4; i < 4; ++i)
        for (int j = -4; j < 4; ++j) {
            double z0 = j * tile, z1 = (j + 1) * tile;
            if (j == -1) z1 -= 0.5 * gap;
            if (j == 0) z0 += 0.5 * gap;
            const double y0 = i * tile, y1 = (i + 1) * tile;
            triangles.push_back({DVec3(1, y0, z0), DVec3(1, y1, z0), DVec3(1, y1, z1)});
            triangles.push_back({DVec3(1, y0, z0), DVec3(1, y1, z1), DVec3(1, y0, z1)});
        }
    return triangles;
}

}  // namespace

TEST_CASE("patchCovered: tiles meeting along seams cover a patch; a slit between them does not") {
    const DVec3 apex(0.0);
    const Patch patch = squarePatch(DVec3(1, 0, 0), 0.2);
    CHECK(patchCovered(apex, patch.outline, wall(0.125, 0.0)));
    CHECK(!patchCovered(apex, patch.outline, wall(0.125, 0.01)));
    // Grouped into faces (each tile's two triangles one convex quad): the same answers.
    std::vector<size_t> quads;
    for (size_t end = 2; end <= wall(0.125, 0.0).size(); end += 2) quads.push_back(end);
    CHECK(patchCovered(apex, patch.outline, wall(0.125, 0.0), quads));
    CHECK(!patchCovered(apex, patch.outline, wall(0.125, 0.01), quads));
    // A face that is not convex (an L of three tiles' triangles) is taken triangle by triangle.
    const std::vector<Triangle> tiles = wall(0.5, 0.0);
    std::vector<Triangle> ell;
    for (size_t i = 0; i < tiles.size() && ell.size() < 6; ++i)
        if (std::abs(tiles[i][0].y) < 0.6 && std::abs(tiles[i][0].z) < 0.6 && !(tiles[i][0].y >= 0 && tiles[i][0].z >= 0))
            ell.push_back(tiles[i]);
    REQUIRE(ell.size() == 6);
    const std::vector<size_t> one_face{6};
    const Patch corner = squarePatch(glm::normalize(DVec3(1, 0.25, 0.25)), 0.1);
    CHECK(!patchCovered(apex, corner.outline, ell, one_face));
    // Only the triangles the patch's rays meet are needed, whatever their order.
    std::vector<Triangle> met;
    for (const Triangle& t : wall(0.125, 0.0))
        for (const DVec3& d : patch.inside)
            if (rayHits(apex, d, t)) {
                met.push_back(t);
                break;
            }
    std::reverse(met.begin(), met.end());
    CHECK(patchCovered(apex, patch.outline, met));
    met.pop_back();
    CHECK(!patchCovered(apex, patch.outline, met));
    // Behind the apex: nothing covers.
    CHECK(!patchCovered(DVec3(2, 0, 0), patch.outline, wall(0.125, 0.0)));
}

TEST_CASE("patchCovered against brute force: whatever it calls covered, every ray inside the patch meets a triangle") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    size_t covered = 0, open = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const DVec3 axis = glm::normalize(DVec3(unit(rng), unit(rng), unit(rng)));
        const Patch patch = squarePatch(axis, 0.05 + 0.25 * (unit(rng) + 1.0));
        // A few large triangles around the axis at random distances, some crossing the apex's plane.
        std::vector<Triangle> triangles;
        const int count = 1 + int(3 * (unit(rng) + 1.0));
        for (int k = 0; k < count; ++k) {
            const DVec3 centre = axis * (0.5 + 2.0 * (unit(rng) + 1.0)) + DVec3(unit(rng), unit(rng), unit(rng)) * 0.4;
            Triangle t;
            for (DVec3& corner : t) corner = centre + DVec3(unit(rng), unit(rng), unit(rng)) * 1.5;
            triangles.push_back(t);
        }
        const bool claimed = patchCovered(DVec3(0.0), patch.outline, triangles);
        size_t hit = 0;
        for (const DVec3& d : patch.inside) {
            bool any = false;
            for (const Triangle& t : triangles) any = any || rayHits(DVec3(0.0), d, t);
            hit += any ? 1 : 0;
        }
        if (claimed) {
            ++covered;
            CHECK(hit == patch.inside.size());
        } else if (hit < patch.inside.size()) {
            ++open;
        }
    }
    // Both answers occur, so the check above is not vacuous.
    CHECK(covered > 10);
    CHECK(open > 20);
}
