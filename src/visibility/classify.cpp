// Classification of a link's candidate parts against its shaft.
#include <algorithm>
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
    result.tested = result.outside_aabb = result.outside_obb = result.occlusion_tests = 0;
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
        result.candidates.reserve(parent_candidates.size());
        for (uint32_t index : parent_candidates) {
            if (index >= parts.parts.size() || isExcluded(query.excluded, index)) continue;
            const ConvexPart& part = parts.parts[index];
            ++result.tested;
            if (classifyAabb(shaft, part.aabb) == Side::Outside) {
                ++result.outside_aabb;
                continue;
            }
            if (query.test != OcclusionTest::None) {
                ObbPlaneCache cache;
                if (classifyObb(shaft, part.obb, cache) == Side::Outside) {
                    ++result.outside_obb;
                    continue;
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
                if (occludes && !result.occluded) {
                    result.occluded = true;
                    result.occluder = index;
                    if (query.stop_at_occluder) return;
                }
            }
            result.candidates.push_back(index);
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
    std::vector<uint32_t> all(parts.parts.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
    return all;
}

std::vector<uint32_t> partsOfPolygon(const PartSet& parts, uint32_t mesh, uint32_t polygon) {
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
