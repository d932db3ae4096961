// The part tree (geometry/part_tree.h) and classifyLink over tree nodes, against the flat
// candidate list it replaces: same crossing parts, same occlusion verdicts.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>

#include "geometry/part_tree.h"
#include "part_builders.h"
#include "visibility/occlusion.h"

using namespace radbake;
using namespace radbake::testing;

namespace {

// Boxes and plates scattered over [0, 10]^3, some large, some tiny.
std::vector<ConvexPart> scatteredParts(uint32_t seed, int count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> at(0.0, 10.0), size(0.01, 1.5);
    std::vector<ConvexPart> parts;
    for (int i = 0; i < count; ++i) {
        const DVec3 c(at(rng), at(rng), at(rng));
        const DVec3 h(size(rng), size(rng), size(rng));
        if (i % 3 == 0) {
            const int axis = i % 2 == 0 ? 1 : 2;
            parts.push_back(flatPart(rectangle(axis, c[axis], c[(axis + 1) % 3] - h.x, c[(axis + 1) % 3] + h.x,
                                               c[(axis + 2) % 3] - h.y, c[(axis + 2) % 3] + h.y)));
        } else {
            parts.push_back(boxPart(c - 0.2 * h, c + 0.2 * h));
        }
    }
    return parts;
}

std::multiset<uint32_t> asSet(const PartSet& parts, const std::vector<uint32_t>& list) {
    const std::vector<uint32_t> expanded = expandCandidates(parts, list);
    return {expanded.begin(), expanded.end()};
}

}  // namespace

TEST_CASE("part tree: every part in one leaf, boxes nested, deterministic") {
    const std::vector<ConvexPart> parts = scatteredParts(1, 301);
    const PartTree tree = buildPartTree(parts);
    REQUIRE(!tree.empty());
    CHECK(tree.nodes[0].count == parts.size());
    std::vector<int> seen(parts.size(), 0);
    for (size_t i = 0; i < tree.nodes.size(); ++i) {
        const PartNode& node = tree.nodes[i];
        bool closed = false;
        for (uint32_t k = node.first; k < node.first + node.count; ++k) {
            const Aabb& box = parts[tree.order[k]].aabb;
            CHECK(tree.boxes[k].min == box.min);
            for (int a = 0; a < 3; ++a) {
                CHECK(box.min[a] >= node.box.min[a]);
                CHECK(box.max[a] <= node.box.max[a]);
            }
            closed = closed || parts[tree.order[k]].closed;
            CHECK(tree.holds(static_cast<uint32_t>(i), tree.order[k]));
            if (node.isLeaf()) ++seen[tree.order[k]];
        }
        CHECK(node.any_closed == closed);
        if (node.isLeaf()) {
            CHECK(node.count <= kPartLeafSize);
        } else {
            const PartNode& a = tree.nodes[node.first_child];
            const PartNode& b = tree.nodes[node.first_child + 1];
            CHECK(node.first_child > i);
            CHECK(a.first == node.first);
            CHECK(a.count + b.count == node.count);
            CHECK(b.first == a.first + a.count);
        }
    }
    for (int count : seen) CHECK(count == 1);
    const PartTree again = buildPartTree(parts);
    CHECK(again.order == tree.order);
}

TEST_CASE("classifyLink over the tree keeps exactly the parts a flat list keeps") {
    PartSet flat;
    flat.parts = scatteredParts(7, 400);
    PartSet treed = flat;
    treed.tree = buildPartTree(treed.parts);
    const std::vector<uint32_t> every = allParts(flat);
    REQUIRE(every.size() == flat.parts.size());
    REQUIRE(allParts(treed) == std::vector<uint32_t>{kPartNode});
    CHECK(candidatePartCount(treed, allParts(treed)) == flat.parts.size());

    std::mt19937 rng(3);
    std::uniform_real_distribution<double> at(0.0, 10.0), size(0.05, 3.0);
    int inside_nodes = 0, occluded = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const double x = at(rng), z = at(rng), w = size(rng);
        const std::vector<DVec3> source = rectangle(1, at(rng) * 0.3, x, x + w, z, z + w);
        const double x2 = at(rng), z2 = at(rng), w2 = size(rng);
        const std::vector<DVec3> receiver = rectangle(1, 7.0 + at(rng) * 0.3, x2, x2 + w2, z2, z2 + w2);
        for (OcclusionTest test : {OcclusionTest::None, OcclusionTest::Exact, OcclusionTest::Obb}) {
            for (bool polygon_shaft : {false, true}) {
                ShaftQuery query;
                query.source = source;
                query.receiver = receiver;
                query.test = test;
                query.polygon_shaft = polygon_shaft;
                query.stop_at_occluder = false;
                const std::vector<uint32_t> excluded{uint32_t(trial % 400), uint32_t((trial * 7) % 400)};
                query.excluded = excluded;
                const ShaftResult a = classifyLink(flat, every, query);
                const ShaftResult b = classifyLink(treed, allParts(treed), query);
                CHECK(a.occluded == b.occluded);
                occluded += a.occluded ? 1 : 0;
                CHECK(asSet(flat, a.candidates) == asSet(treed, b.candidates));
                for (uint32_t entry : b.candidates) {
                    if (!(entry & kPartNode)) continue;
                    ++inside_nodes;
                    CHECK(test == OcclusionTest::None);  // only box culling keeps whole nodes
                    for (uint32_t part : excluded) CHECK_FALSE(treed.tree.holds(entry & ~kPartNode, part));
                }
                // A child link classifies its parent's list: the same as from every part.
                const ShaftResult c = classifyLink(treed, b.candidates, query);
                CHECK(asSet(treed, c.candidates) == asSet(treed, b.candidates));
                if (test == OcclusionTest::None) CHECK(b.tested + b.tested_nodes < a.tested);
            }
        }
    }
    // The trials must exercise both: whole nodes kept, and occluded links.
    CHECK(inside_nodes > 0);
    CHECK(occluded > 0);
}
