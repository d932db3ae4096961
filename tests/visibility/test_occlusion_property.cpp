// Property test: random configurations against a brute-force segment test.
//   - Exact must show ZERO false occlusions (claims where some sampled segment misses);
//   - the AABB and OBB crossing tests, on both shaft kinds, must never say Outside for a
//     part that some sampled segment touches.
// The paper's OBB test is optimistic: its false occlusions are counted and reported only.
#include <doctest/doctest.h>

#include <array>

#include "random_configs.h"
#include "visibility/occlusion.h"
#include "visibility/reference.h"

using namespace radbake;
using namespace radbake::testing;

TEST_CASE("property: exact never claims a false occlusion; crossing never misses a hit") {
    constexpr int kConfigurations = 12000;
    ConfigurationGenerator generator(20261122);
    size_t exact_claims = 0, exact_false = 0, exact_missed = 0;
    size_t obb_claims = 0, obb_false = 0, obb_missed = 0;
    size_t real_occlusions = 0, touched = 0, false_outside = 0;
    std::array<size_t, static_cast<int>(OccluderKind::Count)> claims_by_kind{};
    for (int i = 0; i < kConfigurations; ++i) {
        const Configuration c = generator.next();
        const auto ps = polygonSamplePoints(c.source, 3);
        const auto pr = polygonSamplePoints(c.receiver, 3);
        const SegmentCount count = countSegmentHits(ps, pr, c.occluder);
        const bool all_hit = count.hits_strict == count.segments;
        real_occlusions += all_hit;

        const Shaft poly = shaftBetweenPolygons(c.source, c.receiver);
        const Shaft box = shaftBetweenBoxes(boxOfPoints(c.source), boxOfPoints(c.receiver));
        if (count.hits_any > 0) {
            ++touched;
            for (const Shaft* shaft : {&poly, &box}) {
                if (classifyAabb(*shaft, c.occluder.aabb) == Side::Outside ||
                    classifyObb(*shaft, c.occluder.obb) == Side::Outside) {
                    ++false_outside;
                }
            }
        }
        const bool exact = occludesExact(c.source, c.receiver, c.occluder);
        exact_claims += exact;
        if (exact) ++claims_by_kind[static_cast<int>(c.kind)];
        if (exact && !all_hit) {
            ++exact_false;
            MESSAGE("false exact occlusion at configuration " << i);
        }
        exact_missed += all_hit && !exact;
        const bool obb = occludesObb(box, c.occluder.obb);
        obb_claims += obb;
        obb_false += obb && !all_hit;
        obb_missed += all_hit && !obb;
    }
    MESSAGE("configurations " << kConfigurations << ", real occlusions (all "
            << "sampled segments hit) " << real_occlusions << ", touched " << touched);
    MESSAGE("exact: claims " << exact_claims << ", false " << exact_false << ", missed "
            << exact_missed);
    MESSAGE("obb:   claims " << obb_claims << ", false " << obb_false << ", missed "
            << obb_missed);
    MESSAGE("exact claims by kind (axis box, rotated box, thin plate, tilted polygon, touching): "
            << claims_by_kind[0] << " " << claims_by_kind[1] << " " << claims_by_kind[2] << " "
            << claims_by_kind[3] << " " << claims_by_kind[4]);
    CHECK(exact_false == 0);
    CHECK(false_outside == 0);
    // The generator must exercise the tests: many real occlusions, most of them found.
    CHECK(real_occlusions > kConfigurations / 20);
    CHECK(exact_claims > real_occlusions / 2);
    for (size_t k = 0; k < claims_by_kind.size(); ++k) CHECK(claims_by_kind[k] > 0);
}
