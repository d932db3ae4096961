#include "geometry/part_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace radbake {

PartTree buildPartTree(const std::vector<ConvexPart>& parts) {
    PartTree tree;
    const uint32_t n = static_cast<uint32_t>(parts.size());
    if (n == 0) return tree;
    tree.order.resize(n);
    std::iota(tree.order.begin(), tree.order.end(), 0u);
    tree.nodes.reserve(2 * (n / kPartLeafSize + 1));
    tree.nodes.push_back({});
    tree.nodes[0].count = n;
    // Iterative top-down build: children are allocated in pairs right after a split, so they
    // are contiguous and follow their parent.
    std::vector<uint32_t> todo{0};
    while (!todo.empty()) {
        const uint32_t index = todo.back();
        todo.pop_back();
        const uint32_t first = tree.nodes[index].first, count = tree.nodes[index].count;
        if (count <= kPartLeafSize) continue;
        Aabb centres;
        for (uint32_t k = first; k < first + count; ++k) centres.add(parts[tree.order[k]].aabb.center());
        const DVec3 extent = centres.extent();
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (extent[k] > extent[axis]) axis = k;
        const uint32_t half = count / 2;
        auto begin = tree.order.begin() + first;
        std::nth_element(begin, begin + half, begin + count, [&](uint32_t a, uint32_t b) {
            const double ca = parts[a].aabb.center()[axis], cb = parts[b].aabb.center()[axis];
            return ca < cb || (ca == cb && a < b);
        });
        const uint32_t child = static_cast<uint32_t>(tree.nodes.size());
        tree.nodes[index].first_child = child;
        PartNode lo, hi;
        lo.first = first;
        lo.count = half;
        hi.first = first + half;
        hi.count = count - half;
        tree.nodes.push_back(lo);
        tree.nodes.push_back(hi);
        todo.push_back(child + 1);
        todo.push_back(child);
    }
    // Boxes bottom-up (children follow their parents).
    for (size_t i = tree.nodes.size(); i-- > 0;) {
        PartNode& node = tree.nodes[i];
        if (node.isLeaf()) {
            for (uint32_t k = node.first; k < node.first + node.count; ++k) {
                node.box.add(parts[tree.order[k]].aabb);
                node.any_closed = node.any_closed || parts[tree.order[k]].closed;
                node.any_flat = node.any_flat || !parts[tree.order[k]].closed;
            }
        } else {
            for (uint32_t c = 0; c < 2; ++c) {
                node.box.add(tree.nodes[node.first_child + c].box);
                node.any_closed = node.any_closed || tree.nodes[node.first_child + c].any_closed;
                node.any_flat = node.any_flat || tree.nodes[node.first_child + c].any_flat;
            }
        }
    }
    tree.position.assign(n, 0);
    tree.boxes.resize(n);
    for (uint32_t k = 0; k < n; ++k) {
        tree.position[tree.order[k]] = k;
        tree.boxes[k] = parts[tree.order[k]].aabb;
    }
    return tree;
}

}  // namespace radbake
