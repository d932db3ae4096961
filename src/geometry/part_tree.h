#pragma once
// A bounding-box tree over a PartSet's parts, so that a shaft culls a whole group of parts
// with one box test instead of one test per part (issue 11: flat candidate lists of
// thousands of parts were 35-45 % of a clustered solve). Candidate lists (occlusion.h) may
// hold tree nodes (kPartNode | node) besides part indices.
#include <cstdint>
#include <vector>

#include "geometry/types.h"

namespace radbake {

// Set on a candidate-list entry that names a tree node rather than a part.
inline constexpr uint32_t kPartNode = 0x80000000u;
inline constexpr uint32_t kNoPartNode = 0xffffffffu;

struct PartNode {
    Aabb box;                           // of its parts' AABBs
    uint32_t first_child = kNoPartNode;  // two children, contiguous; kNoPartNode for a leaf
    uint32_t first = 0;                 // its parts: PartTree::order[first .. first + count)
    uint32_t count = 0;
    bool any_closed = false;            // some part below is a closed solid
    bool any_flat = false;              // some part below is flat
    bool isLeaf() const { return first_child == kNoPartNode; }
};

struct PartTree {
    std::vector<PartNode> nodes;     // nodes[0] is the root; children follow their parent
    std::vector<uint32_t> order;     // part indices, grouped by node
    std::vector<uint32_t> position;  // per part: its index in `order`
    std::vector<Aabb> boxes;         // per slot of `order`: that part's AABB (contiguous, so a
                                     // leaf's parts are culled without touching the parts)
    bool empty() const { return nodes.empty(); }
    // True when part `part` is below node `node`.
    bool holds(uint32_t node, uint32_t part) const {
        const PartNode& n = nodes[node];
        return part < position.size() && position[part] >= n.first && position[part] < n.first + n.count;
    }
};

// Top-down median split of the parts' box centres along the widest axis, leaves of at most
// kPartLeafSize parts; ties by index, so the same parts give the same tree.
inline constexpr uint32_t kPartLeafSize = 4;
PartTree buildPartTree(const std::vector<ConvexPart>& parts);

}  // namespace radbake
