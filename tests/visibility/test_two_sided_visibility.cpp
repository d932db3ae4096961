// Two-sided meshes (scene/two_sided.h) in the parts and the ray caster: a back twin makes no
// parts of its own (its front's stand for it, and are excluded with it), a two-sided closed
// mesh is never a solid, rays are blocked once, and a hit from behind names the back twin.
#include <doctest/doctest.h>

#include "../geometry/mesh_builders.h"
#include "geometry/parts.h"
#include "scene/two_sided.h"
#include "visibility/occlusion.h"
#include "visibility/ray_caster.h"

using namespace radbake;
using namespace radbake::test;

namespace {

Scene twoSidedBox() {
    Scene scene;
    scene.materials.push_back(Material{});
    Mesh box = boxMesh(Vec3(0.5f), Quat(1, 0, 0, 0), Vec3(0.5f));  // [0,1]^3, faces out
    box.solid = false;
    scene.meshes.push_back(box);
    // Lit inside, so it keeps its back twin (a closed two-sided mesh dark inside needs none).
    Light light;
    light.position = Vec3(0.5f);
    scene.lights.push_back(light);
    addBackTwins(scene);
    return scene;
}

}  // namespace

TEST_CASE("parts: a two-sided closed box is flat parts, and its back twin shares them") {
    const Scene scene = twoSidedBox();
    REQUIRE(scene.meshes.size() == 2);
    Diagnostics diagnostics;
    const PartSet parts = buildParts(scene, PartOptions{}, diagnostics);
    CHECK(parts.stats.closed_parts == 0);  // seen from inside: no occluding volume
    CHECK(parts.stats.flat_parts == 6);
    for (const ConvexPart& part : parts.parts) CHECK(part.mesh == 0);
    REQUIRE(parts.part_mesh.size() == 2);
    CHECK(parts.part_mesh[1] == 0);
    CHECK(parts.polygon_part[1] == parts.polygon_part[0]);
    for (uint32_t p = 0; p < 6; ++p) CHECK(partsOfPolygon(parts, 1, p) == partsOfPolygon(parts, 0, p));

    // The one-sided box stays a solid.
    Scene one_sided;
    one_sided.materials.push_back(Material{});
    one_sided.meshes.push_back(boxMesh(Vec3(0.5f), Quat(1, 0, 0, 0), Vec3(0.5f)));
    addBackTwins(one_sided);
    CHECK(buildParts(one_sided, PartOptions{}, diagnostics).stats.closed_parts == 1);

    // So does the two-sided box dark inside: it gets no twin and is baked one-sided.
    Scene dark;
    dark.materials.push_back(Material{});
    dark.meshes.push_back(boxMesh(Vec3(0.5f), Quat(1, 0, 0, 0), Vec3(0.5f)));
    dark.meshes[0].solid = false;
    CHECK(addBackTwins(dark) == 0);
    CHECK(dark.meshes[0].closed_two_sided);
    CHECK(buildParts(dark, PartOptions{}, diagnostics).stats.closed_parts == 1);
}

TEST_CASE("rays: a back twin is not cast against twice, and a hit from behind names it") {
    const Scene scene = twoSidedBox();
    Diagnostics diagnostics;
    const auto caster = RayCaster::build(scene, diagnostics, 1);
    REQUIRE(caster);
    CHECK(caster->triangleCount() == 12);  // the front's 12 triangles only
    // From outside towards -z onto the top face (z = 1): its front.
    std::optional<RayHit> hit = caster->closestHit(DVec3(0.3, 0.6, 2.0), DVec3(0, 0, -1), 10.0);
    REQUIRE(hit);
    CHECK(hit->triangle.mesh == 0);
    CHECK(hit->t == doctest::Approx(1.0));
    // From inside upwards onto the same face: its back, the twin's triangle of the same index,
    // whose barycentrics give the same point.
    std::optional<RayHit> inside = caster->closestHit(DVec3(0.3, 0.6, 0.5), DVec3(0, 0, 1), 10.0);
    REQUIRE(inside);
    CHECK(inside->triangle.mesh == 1);
    CHECK(inside->t == doctest::Approx(0.5));
    const Mesh& back = scene.meshes[1];
    const UVec3& tri = back.triangles[inside->triangle.triangle];
    const DVec3 p = (1.0 - inside->u - inside->v) * DVec3(back.positions[tri.x]) + inside->u * DVec3(back.positions[tri.y]) +
                    inside->v * DVec3(back.positions[tri.z]);
    CHECK(p.x == doctest::Approx(0.3).epsilon(1e-5));
    CHECK(p.y == doctest::Approx(0.6).epsilon(1e-5));
    CHECK(p.z == doctest::Approx(1.0).epsilon(1e-5));
    // A segment between the box's inner faces is open; one through a wall is blocked.
    CHECK_FALSE(caster->segmentBlocked(DVec3(0.5, 0.5, 0.0), DVec3(0.5, 0.5, 1.0)));
    CHECK(caster->segmentBlocked(DVec3(0.5, 0.5, 0.5), DVec3(0.5, 0.5, 1.5)));
}
