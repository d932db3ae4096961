// The OBB (paper) and exact occlusion tests, and classifyLink, on literal configurations.
#include <doctest/doctest.h>

#include <cmath>

#include "part_builders.h"
#include "visibility/occlusion.h"
#include "visibility/reference.h"

using namespace radbake;
using namespace radbake::testing;

namespace {

// Source [0,1]^2 on z = 0, receiver [0,1]^2 on z = 2.
const std::vector<DVec3> kSource = rectangle(2, 0.0, 0.0, 1.0, 0.0, 1.0);
const std::vector<DVec3> kReceiver = rectangle(2, 2.0, 0.0, 1.0, 0.0, 1.0);

Shaft boxShaft(const std::vector<DVec3>& s, const std::vector<DVec3>& r) {
    return shaftBetweenBoxes(boxOfPoints(s), boxOfPoints(r));
}

// Brute force over 13 x 13 sample points: does every segment pass through the interior?
bool everySegmentHits(const std::vector<DVec3>& s, const std::vector<DVec3>& r,
                      const ConvexPart& part) {
    const auto ps = polygonSamplePoints(s, 3), pr = polygonSamplePoints(r, 3);
    const SegmentCount count = countSegmentHits(ps, pr, part);
    return count.hits_strict == count.segments;
}

PartSet partSetOf(std::vector<ConvexPart> parts) {
    PartSet set;
    set.parts = std::move(parts);
    return set;
}

}  // namespace

TEST_CASE("a wall between two patches occludes (both tests)") {
    const ConvexPart wall = boxPart({-0.5, -0.5, 0.9}, {1.5, 1.5, 1.1});
    CHECK(everySegmentHits(kSource, kReceiver, wall));
    CHECK(occludesExact(kSource, kReceiver, wall));
    CHECK(occludesObb(boxShaft(kSource, kReceiver), wall.obb));
    // Reversed roles and reversed windings do not matter.
    CHECK(occludesExact(kReceiver, kSource, wall));
    const std::vector<DVec3> reversed(kSource.rbegin(), kSource.rend());
    CHECK(occludesExact(reversed, kReceiver, wall));
    // The same wall as a flat plate (a flat part) at z = 1.
    const ConvexPart plate = flatPart(rectangle(2, 1.0, -0.5, 1.5, -0.5, 1.5));
    CHECK(occludesExact(kSource, kReceiver, plate));
    CHECK(occludesObb(boxShaft(kSource, kReceiver), plate.obb));
}

TEST_CASE("a wall exactly the size of the shaft's section occludes only when it overlaps") {
    // Cross-section at z = 1 is exactly [0,1]^2: the segments along the shaft's sides graze
    // the wall's side faces, so the wall does not block them (strictly).
    const ConvexPart exact_fit = boxPart({0, 0, 0.9}, {1, 1, 1.1});
    CHECK_FALSE(everySegmentHits(kSource, kReceiver, exact_fit));
    CHECK_FALSE(occludesExact(kSource, kReceiver, exact_fit));
    const ConvexPart wider = boxPart({-1e-9, -1e-9, 0.9}, {1 + 1e-9, 1 + 1e-9, 1.1});
    CHECK(everySegmentHits(kSource, kReceiver, wider));
    CHECK(occludesExact(kSource, kReceiver, wider));
}

TEST_CASE("the exact test shrinks a part by its inflation (a hull may overshoot its mesh)") {
    // Overlapping the shaft's section by 1e-3 occludes; the same box flagged as possibly
    // 2e-3 larger than the surface it stands for must not claim it, a 5e-4 inflation still may.
    ConvexPart wall = boxPart({-1e-3, -1e-3, 0.9}, {1 + 1e-3, 1 + 1e-3, 1.1});
    CHECK(occludesExact(kSource, kReceiver, wall));
    wall.inflation = 2e-3;
    CHECK_FALSE(occludesExact(kSource, kReceiver, wall));
    wall.inflation = 5e-4;
    CHECK(occludesExact(kSource, kReceiver, wall));
    ConvexPart plate = flatPart(rectangle(2, 1.0, -1e-3, 1 + 1e-3, -1e-3, 1 + 1e-3));
    CHECK(occludesExact(kSource, kReceiver, plate));
    plate.inflation = 2e-3;
    CHECK_FALSE(occludesExact(kSource, kReceiver, plate));
}

TEST_CASE("a tilted wall between diverging patches is found through its own face normal") {
    // Receiver larger and shifted; the wall is a thin box tilted 30 degrees around x.
    const std::vector<DVec3> r = rectangle(2, 3.0, -0.5, 2.0, -0.5, 2.5);
    const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
    const ConvexPart wall = orientedBoxPart({0.6, 0.8, 1.0}, {DVec3(1, 0, 0), DVec3(0, c, s),
                                                              DVec3(0, -s, c)},
                                            DVec3(3.0, 3.0, 0.01));
    CHECK(everySegmentHits(kSource, r, wall));
    CHECK(occludesExact(kSource, r, wall));
}

TEST_CASE("a wall behind the receiver does not occlude (Exact); the paper's OBB test says it does") {
    // Receiver tilted: z = 2 + y. A wall parallel to it, 0.3 behind it, large enough to
    // overlap the union box of the two patches.
    const std::vector<DVec3> r = {{0, 0, 2}, {1, 0, 2}, {1, 1, 3}, {0, 1, 3}};
    const double k = 1.0 / std::sqrt(2.0);
    const DVec3 away(0, -k, k), along(0, k, k);
    const ConvexPart wall = orientedBoxPart(DVec3(0.5, 0.5, 2.5) + 0.3 * away,
                                            {DVec3(1, 0, 0), along, away}, DVec3(1.0, 1.0, 0.05));
    const auto ps = polygonSamplePoints(kSource, 3), pr = polygonSamplePoints(r, 3);
    CHECK(countSegmentHits(ps, pr, wall).hits_any == 0);
    CHECK_FALSE(occludesExact(kSource, r, wall));
    // The paper's test works on the box shaft, whose side planes and box cannot tell in front
    // from behind: the OBB crosses the union box and spans both channels.
    const Shaft box = boxShaft(kSource, r);
    CHECK(classifyObb(box, wall.obb) == Side::Crossing);
    CHECK(occludesObb(box, wall.obb));
    // With the polygon shaft (classifyLink's default) the wall is culled before any test.
    CHECK(classifyObb(shaftBetweenPolygons(kSource, r), wall.obb) == Side::Outside);
}

TEST_CASE("a part touching the shaft only at an edge or a face does not occlude") {
    const ConvexPart edge_column = boxPart({1, 1, 0.2}, {2, 2, 1.8});
    const ConvexPart side_wall = boxPart({1, -1, 0.2}, {2, 2, 1.8});
    const ConvexPart under_source = boxPart({-1, -1, -1}, {2, 2, 0});
    const ConvexPart over_receiver = boxPart({-1, -1, 2}, {2, 2, 3});
    const Shaft poly = shaftBetweenPolygons(kSource, kReceiver);
    const Shaft box = boxShaft(kSource, kReceiver);
    for (const ConvexPart* p : {&edge_column, &side_wall, &under_source, &over_receiver}) {
        CHECK(classifyAabb(poly, p->aabb) == Side::Crossing);  // conservative: touching crosses
        CHECK_FALSE(occludesExact(kSource, kReceiver, *p));
        CHECK_FALSE(occludesObb(box, p->obb));
    }
    // A plate lying in the receiver's plane, under it: segments end on it, none crosses it.
    const ConvexPart plate = flatPart(rectangle(2, 2.0, -1.0, 2.0, -1.0, 2.0));
    CHECK_FALSE(occludesExact(kSource, kReceiver, plate));
}

TEST_CASE("two plates leaving a slit do not occlude, each alone or as a link") {
    const double gap = 1e-3;
    const ConvexPart left = flatPart(rectangle(2, 1.0, -1.0, 0.5 - gap, -1.0, 2.0));
    const ConvexPart right = flatPart(rectangle(2, 1.0, 0.5 + gap, 2.0, -1.0, 2.0));
    CHECK_FALSE(occludesExact(kSource, kReceiver, left));
    CHECK_FALSE(occludesExact(kSource, kReceiver, right));
    const PartSet parts = partSetOf({left, right});
    const std::vector<uint32_t> all = allParts(parts);
    for (OcclusionTest test : {OcclusionTest::Exact, OcclusionTest::Obb}) {
        ShaftQuery query;
        query.source = kSource;
        query.receiver = kReceiver;
        query.test = test;
        const ShaftResult result = classifyLink(parts, all, query);
        CHECK_FALSE(result.occluded);
        CHECK(result.candidates == std::vector<uint32_t>{0, 1});
        CHECK(result.occlusion_tests == 2);
    }
    // Closed thin slabs too.
    const ConvexPart left_box = boxPart({-1, -1, 0.99}, {0.5 - gap, 2, 1.01});
    const ConvexPart right_box = boxPart({0.5 + gap, -1, 0.99}, {2, 2, 1.01});
    CHECK_FALSE(occludesExact(kSource, kReceiver, left_box));
    CHECK_FALSE(occludesExact(kSource, kReceiver, right_box));
    CHECK_FALSE(occludesObb(boxShaft(kSource, kReceiver), left_box.obb));
}

TEST_CASE("classifyLink: culling, candidates as a subset in order, first occluder") {
    const PartSet parts = partSetOf({
        boxPart({5, 5, 5}, {6, 6, 6}),                // 0: outside
        boxPart({0.2, 0.2, 0.5}, {0.4, 0.4, 0.7}),    // 1: crossing, small
        boxPart({-0.5, -0.5, 0.9}, {1.5, 1.5, 1.1}),  // 2: occluding wall
        boxPart({0.6, 0.6, 1.5}, {0.8, 0.8, 1.7}),    // 3: crossing, small
    });
    const std::vector<uint32_t> all = allParts(parts);
    ShaftQuery query;
    query.source = kSource;
    query.receiver = kReceiver;

    query.test = OcclusionTest::None;
    ShaftResult none = classifyLink(parts, all, query);
    CHECK_FALSE(none.occluded);
    CHECK(none.candidates == std::vector<uint32_t>{1, 2, 3});
    CHECK(none.outside_aabb == 1);
    CHECK(none.occlusion_tests == 0);

    query.test = OcclusionTest::Exact;
    ShaftResult exact = classifyLink(parts, all, query);
    CHECK(exact.occluded);
    CHECK(exact.occluder == 2);
    CHECK(exact.candidates == std::vector<uint32_t>{1});  // stopped at the occluder
    query.stop_at_occluder = false;
    exact = classifyLink(parts, all, query);
    CHECK(exact.occluded);
    CHECK(exact.candidates == std::vector<uint32_t>{1, 2, 3});
    CHECK(exact.tested == 4);

    // A sub-link (left halves of source and receiver) classifies its parent's candidates only.
    const std::vector<DVec3> half = rectangle(2, 0.0, 0.0, 0.5, 0.0, 1.0);
    const std::vector<DVec3> half_receiver = rectangle(2, 2.0, 0.0, 0.5, 0.0, 1.0);
    query.source = half;
    query.receiver = half_receiver;
    const std::vector<uint32_t> parent = {1, 3};
    ShaftResult child = classifyLink(parts, parent, query);
    CHECK_FALSE(child.occluded);
    CHECK(child.tested == 2);
    CHECK(child.candidates == std::vector<uint32_t>{1});  // part 3 is over the right half
}

TEST_CASE("parts holding the source or receiver polygon are excluded") {
    // The source is the top face of a box (mesh 0, polygon 4); the receiver is below the box
    // (facing up at it), so every segment runs through the box.
    ConvexPart holder = boxPart({0, 0, -1}, {1, 1, 0});
    holder.mesh = 0;
    holder.polygons = {0, 1, 2, 3, 4, 5};
    ConvexPart other = boxPart({3, 3, 3}, {4, 4, 4});
    other.mesh = 1;
    other.polygons = {0};
    const PartSet parts = partSetOf({other, holder});
    const std::vector<DVec3> below = rectangle(2, -3.0, 0.2, 0.8, 0.2, 0.8);
    CHECK(occludesExact(kSource, below, holder));  // physically true: the box is in the way

    ShaftQuery query;
    query.source = kSource;
    query.receiver = below;
    const std::vector<uint32_t> all = allParts(parts);
    CHECK(classifyLink(parts, all, query).occluded);
    const std::vector<uint32_t> excluded = partsOfPolygon(parts, 0, 4);
    CHECK(excluded == std::vector<uint32_t>{1});
    CHECK(partsOfPolygon(parts, 1, 0) == std::vector<uint32_t>{0});
    CHECK(partsOfPolygon(parts, 2, 0).empty());
    query.excluded = excluded;
    const ShaftResult result = classifyLink(parts, all, query);
    CHECK_FALSE(result.occluded);
    CHECK(result.tested == 1);
    CHECK(result.candidates.empty());
}

TEST_CASE("exact test far from the origin keeps its margins") {
    const DVec3 o(2e4, 1e4, -3e4);
    std::vector<DVec3> s = kSource, r = kReceiver;
    for (auto& p : s) p += o;
    for (auto& p : r) p += o;
    CHECK(occludesExact(s, r, boxPart(o + DVec3(-1e-6, -1e-6, 0.9), o + DVec3(1 + 1e-6, 1 + 1e-6, 1.1))));
    CHECK_FALSE(occludesExact(s, r, boxPart(o + DVec3(0, 0, 0.9), o + DVec3(1, 1, 1.1))));
}

TEST_CASE("classifyPart: the three modes on one wall, one column and one far box") {
    const Shaft poly = shaftBetweenPolygons(kSource, kReceiver);
    const Shaft box = boxShaft(kSource, kReceiver);
    const ConvexPart wall = boxPart({-0.5, -0.5, 0.9}, {1.5, 1.5, 1.1});
    const ConvexPart column = boxPart({0.4, 0.4, 0.5}, {0.6, 0.6, 1.5});
    const ConvexPart far = boxPart({4, 4, 4}, {5, 5, 5});
    CHECK(classifyPart(wall, poly, nullptr, kSource, kReceiver, OcclusionTest::None) ==
          PartVsShaft::Crossing);
    CHECK(classifyPart(wall, poly, nullptr, kSource, kReceiver, OcclusionTest::Exact) ==
          PartVsShaft::Occluding);
    CHECK(classifyPart(wall, box, &box, kSource, kReceiver, OcclusionTest::Obb) ==
          PartVsShaft::Occluding);
    CHECK(classifyPart(wall, poly, &box, kSource, kReceiver, OcclusionTest::Obb) ==
          PartVsShaft::Occluding);
    for (OcclusionTest test : {OcclusionTest::None, OcclusionTest::Obb, OcclusionTest::Exact}) {
        CHECK(classifyPart(column, poly, &box, kSource, kReceiver, test) == PartVsShaft::Crossing);
        CHECK(classifyPart(far, poly, &box, kSource, kReceiver, test) == PartVsShaft::Outside);
    }
}

TEST_CASE("reference: segments in a plate's plane touch it only where they meet the polygon") {
    const ConvexPart plate = flatPart(rectangle(2, 1.0, 0.0, 1.0, 0.0, 1.0));
    // In the plane z = 1, crossing the square / passing beside it / ending on its edge.
    CHECK(segmentHitsPart({-1, 0.5, 1}, {2, 0.5, 1}, plate, false));
    CHECK_FALSE(segmentHitsPart({-1, 0.5, 1}, {2, 0.5, 1}, plate, true));
    CHECK_FALSE(segmentHitsPart({-1, 1.5, 1}, {2, 1.5, 1}, plate, false));
    CHECK(segmentHitsPart({-1, 0.5, 1}, {0, 0.5, 1}, plate, false));
    // Through it, and through its edge (contact, not interior).
    CHECK(segmentHitsPart({0.5, 0.5, 0}, {0.5, 0.5, 2}, plate, true));
    CHECK(segmentHitsPart({1, 0.5, 0}, {1, 0.5, 2}, plate, false));
    CHECK_FALSE(segmentHitsPart({1, 0.5, 0}, {1, 0.5, 2}, plate, true));
    // Closed box: through the interior, along a face, missing.
    const ConvexPart cube = boxPart({0, 0, 0}, {1, 1, 1});
    CHECK(segmentHitsPart({-1, 0.5, 0.5}, {2, 0.5, 0.5}, cube, true));
    CHECK(segmentHitsPart({-1, 0.5, 1}, {2, 0.5, 1}, cube, false));
    CHECK_FALSE(segmentHitsPart({-1, 0.5, 1}, {2, 0.5, 1}, cube, true));
    CHECK_FALSE(segmentHitsPart({-1, 0.5, 1.5}, {2, 0.5, 1.5}, cube, false));
}
