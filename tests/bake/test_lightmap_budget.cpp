// The default texel density (lightmap_budget.h): 16 texels per metre, raised for a small scene
// to kMinTexelsAcross along its largest side.
#include <doctest/doctest.h>

#include "bake/lightmap_budget.h"

using namespace radbake;

namespace {

Scene boxScene(float side) {
    Scene scene;
    Mesh mesh;
    mesh.positions = {Vec3(0.0f), Vec3(side, 0.0f, 0.0f), Vec3(side, 0.5f * side, 0.0f), Vec3(0.0f, 0.0f, 0.25f * side)};
    scene.meshes.push_back(mesh);
    return scene;
}

}  // namespace

TEST_CASE("the default texel density: 16 per metre, at least 34 texels along a small scene's largest side") {
    CHECK(defaultTexelsPerMetre(boxScene(10.0f)) == doctest::Approx(kDefaultTexelsPerMetre));  // a room: 160 texels across
    CHECK(defaultTexelsPerMetre(boxScene(0.5f)) == doctest::Approx(kMinTexelsAcross / 0.5));  // a model box: 34 across
    CHECK(defaultTexelsPerMetre(boxScene(2.125f)) == doctest::Approx(kDefaultTexelsPerMetre));  // 34 / 16 m: the two meet
    CHECK(defaultTexelsPerMetre(Scene{}) == doctest::Approx(kDefaultTexelsPerMetre));  // nothing to measure
    CHECK(kMinTexelsAcross >= 32.0);  // issue 33: the bundled Cornell Box's walls at least 32 texels across
}
