// The solver's counts add up: every evaluation of the oracle is kept, reopened, occluded,
// dropped or split (SolveStats), with clustering on and off and in every visibility mode.
#include <doctest/doctest.h>

#include "test_scenes.h"

using namespace radbake;
using namespace radbake::test;

namespace {

// A room lit from its ceiling, a block on the floor and a wall part-way across: occluded,
// partial, split and reopened links all occur.
Scene roomWithOccluders() {
    Scene scene;
    const uint32_t grey = addMaterial(scene, Vec3(0.6f), Vec3(0.0f));
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(5.0f));
    addInwardBox(scene, grey, Vec3(0.0f), Vec3(3.0f, 2.0f, 2.0f));
    addOutwardBox(scene, grey, Vec3(0.5f, 0.5f, 0.0f), Vec3(1.0f, 1.0f, 0.5f));
    addOutwardBox(scene, grey, Vec3(1.9f, 0.0f, 0.0f), Vec3(2.0f, 1.5f, 1.8f));
    addQuad(scene, lamp, {0.3f, 0.3f, 1.99f}, {0.3f, 0.7f, 1.99f}, {0.7f, 0.7f, 1.99f}, {0.7f, 0.3f, 1.99f});
    return scene;
}

}  // namespace

TEST_CASE("candidate links = links + reopened + occluded + dropped + split") {
    const Scene scene = roomWithOccluders();
    for (const bool clustering : {true, false})
        for (const LinkVisibility mode : {LinkVisibility::Exact, LinkVisibility::Aabb, LinkVisibility::Rays}) {
            CAPTURE(clustering);
            CAPTURE(toString(mode));
            SolverOptions options = SolverOptions::forQuality(Quality::Medium);
            options.clustering = clustering;
            options.visibility = mode;
            Diagnostics diagnostics;
            const auto solution = solve(scene, options, diagnostics);
            REQUIRE(solution);
            const SolveStats& s = solution->stats;
            CHECK(s.links == s.element_links + s.cluster_links);
            CHECK(s.element_links == solution->links.size());
            CHECK(s.candidate_links ==
                  s.links + s.reopened_links + s.occluded_links + s.dropped_links + s.split_links);
            CHECK(s.split_links > 0);
            CHECK(s.dropped_links > 0);  // the blocks' faces that face away from each other
            if (mode != LinkVisibility::Aabb) CHECK(s.occluded_links > 0);
            CHECK(s.partial_links <= s.element_links);
        }
}
