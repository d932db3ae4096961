// Classification of a link's candidate parts against its shaft.
#include <algorithm>
#include <array>
#include <cmath>
#include <exception>

#include "visibility/occlusion.h"

namespace radbake {
namespace {

Aabb boxOf(std::span<const DVec3> points) {
    Aabb box;
    for (const DVec3& p : points) box.add(p);
    return box;
}

bool isExcluded(std::span<const uint32_t> excluded, uint32_t index) {
    return std::find(excluded.begin(), excluded.end(), index) != excluded.end();
}

bool inIgnoredPlane(const ConvexPart& part, const ShaftQuery& query) {
    if (part.closed) return false;
    for (const Plane& plane : query.ignored_planes) {
        bool in_plane = true;
        for (const DVec3& p : part.vertices)
            if (!(std::abs(plane.eval(p)) <= query.plane_tolerance)) {
                in_plane = false;
                break;
            }
        if (in_plane) return true;
    }
    return false;
}

// A node whose box meets an ignored plane may hold parts in it: it is opened, not kept whole.
bool meetsIgnoredPlane(const PartNode& node, const ShaftQuery& query) {
    if (!node.any_flat) return false;
    const DVec3 centre = node.box.center(), half = 0.5 * node.box.extent();
    for (const Plane& plane : query.ignored_planes) {
        const double at = plane.eval(centre);
        const double reach = std::abs(plane.normal.x) * half.x + std::abs(plane.normal.y) * half.y +
                             std::abs(plane.normal.z) * half.z;
        if (!(at - reach > query.plane_tolerance || at + reach < -query.plane_tolerance)) return true;
    }
    return false;
}

}  // namespace

PartVsShaft classifyPart(const ConvexPart& part, const Shaft& shaft, const Shaft* box_shaft,
                         std::span<const DVec3> source, std::span<const DVec3> receiver,
                         OcclusionTest test) {
    if (classifyAabb(shaft, part.aabb) == Side::Outside) return PartVsShaft::Outside;
    if (test == OcclusionTest::None) return PartVsShaft::Crossing;
    ObbPlaneCache cache;
    if (classifyObb(shaft, part.obb, cache) == Side::Outside) return PartVsShaft::Outside;
    if (test == OcclusionTest::Obb && box_shaft != nullptr) {
        // The paper's test runs on the box shaft; reuse the cache when it is the same shaft.
        if (box_shaft == &shaft) {
            if (occludesObb(*box_shaft, part.obb, cache)) return PartVsShaft::Occluding;
        } else if (occludesObb(*box_shaft, part.obb)) {
            return PartVsShaft::Occluding;
        }
    } else if (test == OcclusionTest::Exact) {
        if (occludesExact(source, receiver, part)) return PartVsShaft::Occluding;
    }
    return PartVsShaft::Crossing;
}

void classifyLink(const PartSet& parts, std::span<const uint32_t> parent_candidates,
                  const ShaftQuery& query, ShaftResult& result) {
    result.occluded = false;
    result.fell_back = false;
    result.occluder = kNoPart;
    result.candidates.clear();
    result.tested = result.tested_nodes = result.outside_aabb = result.outside_obb = result.occlusion_tests = 0;
    try {
        const Shaft shaft = query.polygon_shaft
                                ? shaftBetweenPolygons(query.source, query.receiver)
                                : shaftBetweenBoxes(boxOf(query.source), boxOf(query.receiver));
        Shaft box_shaft_storage;
        const Shaft* box_shaft = nullptr;
        if (query.test == OcclusionTest::Obb) {
            if (shaft.kind == ShaftKind::Boxes) {
                box_shaft = &shaft;
            } else {
                box_shaft_storage =
                    shaftBetweenBoxes(boxOf(query.source), boxOf(query.receiver));
                box_shaft = &box_shaft_storage;
            }
        }
        result.candidates.reserve(std::min<size_t>(parent_candidates.size(), 1024));
        // One part: AABB, then OBB culling and the occlusion test. True to stop (occluded).
        const bool first_only = query.first_candidate_only && query.test == OcclusionTest::None;
        auto visit_part = [&](uint32_t index, const Aabb& box) {
            if (index >= parts.parts.size() || isExcluded(query.excluded, index)) return false;
            ++result.tested;
            if (classifyAabb(shaft, box) == Side::Outside) {
                ++result.outside_aabb;
                return false;
            }
            const ConvexPart& part = parts.parts[index];
            if (!query.ignored_planes.empty() && inIgnoredPlane(part, query)) return false;
            if (query.test != OcclusionTest::None) {
                ObbPlaneCache cache;
                if (classifyObb(shaft, part.obb, cache) == Side::Outside) {
                    ++result.outside_obb;
                    return false;
                }
                ++result.occlusion_tests;
                bool occludes = false;
                if (query.test == OcclusionTest::Exact) {
                    occludes = occludesExact(query.source, query.receiver, part);
                } else if (box_shaft == &shaft) {
                    occludes = occludesObb(shaft, part.obb, cache);
                } else {
                    occludes = occludesObb(*box_shaft, part.obb);
                }
                occludes = occludes && !part.transmits;
                if (occludes && !result.occluded) {
                    result.occluded = true;
                    result.occluder = index;
                    if (query.stop_at_occluder) return true;
                }
            }
            result.candidates.push_back(index);
            return first_only;
        };
        // A tree node (part_tree.h): outside drops every part below it with one test; wholly
        // inside it stays one entry when only boxes are tested (no part below is excluded);
        // otherwise its children are classified in turn, depth first.
        const PartTree& tree = parts.tree;
        std::array<uint32_t, 128> stack;
        for (uint32_t entry : parent_candidates) {
            if (!(entry & kPartNode)) {
                if (entry < parts.parts.size() && visit_part(entry, parts.parts[entry].aabb)) return;
                continue;
            }
            if ((entry & ~kPartNode) >= tree.nodes.size()) continue;
            size_t top = 0;
            stack[top++] = entry & ~kPartNode;
            while (top > 0) {
                const uint32_t index = stack[--top];
                const PartNode& node = tree.nodes[index];
                ++result.tested_nodes;
                const BoxSide side = classifyAabbInside(shaft, node.box);
                if (side == BoxSide::Outside) continue;
                if (side == BoxSide::Inside && query.test == OcclusionTest::None &&
                    std::none_of(query.excluded.begin(), query.excluded.end(),
                                 [&](uint32_t part) { return tree.holds(index, part); }) &&
                    !meetsIgnoredPlane(node, query)) {
                    result.candidates.push_back(index | kPartNode);
                    if (first_only) return;
                    continue;
                }
                // A leaf, or deeper than the stack (never for a balanced tree): part by part.
                if (node.isLeaf() || top + 2 > stack.size()) {
                    for (uint32_t k = node.first; k < node.first + node.count; ++k)
                        if (visit_part(tree.order[k], tree.boxes[k])) return;
                    continue;
                }
                stack[top++] = node.first_child + 1;
                stack[top++] = node.first_child;
            }
        }
    } catch (const std::exception&) {
        // Only allocation can throw here. Keep every input part as a candidate and claim no
        // occlusion: the conservative answer (rays then decide the link's visibility), flagged
        // so that the solver counts these links and warns instead of hiding a slower solve.
        result.occluded = false;
        result.occluder = kNoPart;
        result.fell_back = true;
        result.candidates.assign(parent_candidates.begin(), parent_candidates.end());
    }
}

ShaftResult classifyLink(const PartSet& parts, std::span<const uint32_t> parent_candidates,
                         const ShaftQuery& query) {
    ShaftResult result;
    classifyLink(parts, parent_candidates, query, result);
    return result;
}

std::vector<uint32_t> allParts(const PartSet& parts) {
    if (!parts.tree.empty()) return {kPartNode};  // the tree's root
    std::vector<uint32_t> all(parts.parts.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
    return all;
}

size_t candidatePartCount(const PartSet& parts, std::span<const uint32_t> candidates) {
    size_t count = 0;
    for (uint32_t entry : candidates) {
        const uint32_t node = entry & ~kPartNode;
        count += !(entry & kPartNode) ? 1 : node < parts.tree.nodes.size() ? parts.tree.nodes[node].count : 0;
    }
    return count;
}

std::vector<uint32_t> expandCandidates(const PartSet& parts, std::span<const uint32_t> candidates) {
    std::vector<uint32_t> out;
    for (uint32_t entry : candidates) {
        const uint32_t node = entry & ~kPartNode;
        if (!(entry & kPartNode)) {
            out.push_back(entry);
        } else if (node < parts.tree.nodes.size()) {
            const PartNode& n = parts.tree.nodes[node];
            out.insert(out.end(), parts.tree.order.begin() + n.first, parts.tree.order.begin() + n.first + n.count);
        }
    }
    return out;
}

std::vector<uint32_t> partsOfPolygon(const PartSet& parts, uint32_t mesh, uint32_t polygon) {
    if (mesh < parts.part_mesh.size()) mesh = parts.part_mesh[mesh];  // a back twin: its front's parts
    std::vector<uint32_t> found;
    for (size_t i = 0; i < parts.parts.size(); ++i) {
        const ConvexPart& part = parts.parts[i];
        if (part.mesh != mesh) continue;
        if (std::find(part.polygons.begin(), part.polygons.end(), polygon) !=
            part.polygons.end()) {
            found.push_back(static_cast<uint32_t>(i));
        }
    }
    return found;
}

}  // namespace radbake
