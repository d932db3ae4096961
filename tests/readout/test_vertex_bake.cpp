// Per-vertex bake: H / pi at the original vertices, smooth across faces.
#include <doctest/doctest.h>

#include "readout/vertex_bake.h"
#include "../radiosity/test_scenes.h"

using namespace radbake;
using namespace radbake::test;

TEST_CASE("closed emitting box: every vertex, corners included, holds L_e / (1 - rho)") {
    Scene scene;
    const uint32_t m = addMaterial(scene, Vec3(0.5f), Vec3(1.0f));
    addInwardBox(scene, m, Vec3(0.0f), Vec3(1.0f));
    Diagnostics diagnostics;
    SolverOptions options = SolverOptions::forQuality(Quality::Medium);
    const auto solution = solve(scene, options, diagnostics, 1);
    REQUIRE(solution);
    const VertexBake bake =
        bakeVertices(scene, *solution, ReadoutOptions::forQuality(solution->options.quality), test::testRunner());
    REQUIRE(bake.values.size() == 6);
    for (const auto& mesh_values : bake.values) {
        REQUIRE(mesh_values.size() == 4);
        // H / pi = L_e / (1 - rho) = 2; at a corner the two adjacent walls fill half the
        // sky each side, which only the in-plane limit gets right (else ~1.0 here).
        for (const Vec3& v : mesh_values) CHECK(v.x == doctest::Approx(2.0).epsilon(0.01));
    }
}

TEST_CASE("coincident vertices of neighbouring faces with the same normal get the same value") {
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.5f), Vec3(0.0f));
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(3.0f));
    // Two floor tiles sharing the edge x = 1 (separate meshes, duplicated vertices), a lamp.
    addQuad(scene, grey, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    addQuad(scene, grey, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0});
    addQuad(scene, lamp, {0.5f, 0.2f, 1}, {0.5f, 0.8f, 1}, {1.7f, 0.8f, 1}, {1.7f, 0.2f, 1});
    Diagnostics diagnostics;
    SolverOptions options = SolverOptions::forQuality(Quality::Medium);
    const auto solution = solve(scene, options, diagnostics, 2);
    REQUIRE(solution);
    const VertexBake bake =
        bakeVertices(scene, *solution, ReadoutOptions::forQuality(solution->options.quality), test::testRunner());
    // Tile 0's vertices 1 (1,0,0) and 2 (1,1,0) are tile 1's vertices 0 and 3.
    CHECK(bake.values[0][1] == bake.values[1][0]);
    CHECK(bake.values[0][2] == bake.values[1][3]);
    CHECK(bake.values[0][1].x > 0.0f);
    // The value is the link reconstruction's H / pi at that point and normal, on the first
    // face there (tile 0's), and close to the exhaustive gather's.
    const LinkReconstruction links(*solution, ReadoutOptions::forQuality(solution->options.quality),
                                   test::testRunner());
    const DVec3 h = links.irradiance(0, 0, {1, 0, 0}, {0, 0, 1});
    CHECK(bake.values[0][1].x == doctest::Approx(h.x / kPi).epsilon(1e-6));
    const DVec3 reference =
        probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality), {1, 0, 0}, {0, 0, 1});
    CHECK(h.x == doctest::Approx(reference.x).epsilon(0.02));
    // The reference mode is the exhaustive gather itself.
    const VertexBake exhaustive = bakeVertices(scene, *solution, ReadoutOptions{.gather = GatherMode::Exhaustive},
                                                  test::testRunner());
    CHECK(exhaustive.values[0][1].x == doctest::Approx(reference.x / kPi).epsilon(1e-6));
    CHECK(exhaustive.values[0][1] == exhaustive.values[1][0]);
}
