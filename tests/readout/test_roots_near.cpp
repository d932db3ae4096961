// The polygons a point touches (the gather's lift off them), found down the cluster tree
// (gather.h, forRootsNear), checked against every root.
#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

#include "geometry/polygon.h"
#include "radiosity/elements.h"
#include "readout/gather.h"
#include "../radiosity/test_scenes.h"

using namespace radbake;
using namespace radbake::test;

namespace {

// n x n tiles over [x0, x0 + size]^2 on the floor z = 0, facing up, each its own mesh.
void addFloorTiles(Scene& scene, uint32_t material, int n, float x0, float size) {
    const float step = size / static_cast<float>(n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const float x = x0 + i * step, y = j * step;
            addQuad(scene, material, {x, y, 0.0f}, {x + step, y, 0.0f}, {x + step, y + step, 0.0f}, {x, y + step, 0.0f});
        }
}

// Two closed rooms side by side, 3 m apart, each a tiled floor, walls, a lamp and a block on its
// floor: nothing of one room can light the other.
Scene twoClosedRooms() {
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.7f, 0.6f, 0.5f), Vec3(0.0f));
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(5.0f));
    for (const float x0 : {0.0f, 5.0f}) {
        addFloorTiles(scene, grey, 6, x0, 2.0f);
        Scene walls;
        addInwardBox(walls, grey, Vec3(x0, 0.0f, 0.0f), Vec3(x0 + 2.0f, 2.0f, 2.0f));
        for (size_t k = 1; k < walls.meshes.size(); ++k) {  // all but the floor, which the tiles are
            Mesh m = walls.meshes[k];
            m.material = grey;
            m.name = "wall" + std::to_string(scene.meshes.size());
            scene.meshes.push_back(m);
        }
        addOutwardBox(scene, grey, Vec3(x0 + 0.7f, 0.7f, 0.0f), Vec3(x0 + 1.2f, 1.2f, 0.6f));
        addQuad(scene, lamp, {x0 + 0.8f, 0.8f, 1.99f}, {x0 + 0.8f, 1.2f, 1.99f}, {x0 + 1.2f, 1.2f, 1.99f},
                {x0 + 1.2f, 0.8f, 1.99f});
    }
    return scene;
}

}  // namespace

TEST_CASE("a point's lift finds the polygons it touches down the cluster tree, as a look at every root does") {
    const Scene scene = twoClosedRooms();
    Diagnostics diagnostics;
    const auto solution = solve(scene, SolverOptions::forQuality(Quality::Medium), diagnostics);
    REQUIRE(solution);
    REQUIRE(!solution->clusters.empty());
    const double reach = 2.0 * gather::kLift * solution->scene_extent;
    size_t touching = 0;
    // Every corner of every root, and points just off them: the found roots hold every root
    // within reach (brute force over all of them), in root order.
    for (uint32_t r = 0; r < solution->root_count; ++r) {
        const PolygonView poly = polygonOf(*solution, solution->elements[r]);
        for (const DVec3& corner : poly.vertices)
            for (const double off : {0.0, 0.6 * reach, 3.0 * reach}) {
                const DVec3 p = corner + off * DVec3(0.6, -0.48, 0.64);
                std::vector<uint32_t> found;
                gather::forRootsNear(*solution, p, reach, [&](uint32_t q) { found.push_back(q); });
                CHECK(std::is_sorted(found.begin(), found.end()));
                for (uint32_t q = 0; q < solution->root_count; ++q) {
                    if (!(pointPolygonDistance(p, polygonOf(*solution, solution->elements[q])) < reach)) continue;
                    ++touching;
                    CHECK(std::binary_search(found.begin(), found.end(), q));
                }
                CHECK(found.size() < solution->root_count / 4);
            }
    }
    CHECK(touching > solution->root_count);
}
