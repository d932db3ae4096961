#pragma once
// Occlusion of a link (source polygon -> receiver polygon) by the scene's convex parts, and
// the classification of a link's candidate parts against its shaft (DESIGN.md s.1; Dupuy,
// Paulin, Caubet: "Occlusion evaluation in hierarchical radiosity").
//
// Thread safety: every function here is pure (no shared state); call from any thread.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/parts.h"
#include "geometry/types.h"
#include "visibility/shaft.h"

namespace radbake {

// None = the paper's "AABB" column: shaft culling by the parts' AABBs only, never occluded.
// Obb = AABB then OBB culling + the paper's OBB occlusion test (optimistic: it can claim an
// occlusion that is not real). Exact = AABB then OBB culling + the conservative exact test.
enum class OcclusionTest { None, Obb, Exact };

enum class PartVsShaft { Outside, Crossing, Occluding };

// The paper's occlusion test on the part's OBB against a Haines-Wallace (Boxes) shaft. Uses
// the cache filled by classifyObb(shaft, obb, cache) for this same shaft and box. Optimistic;
// see occlusion_obb.cpp for what it checks and what was reconstructed.
bool occludesObb(const Shaft& box_shaft, const Obb& box, const ObbPlaneCache& cache);
bool occludesObb(const Shaft& box_shaft, const Obb& box);  // fills its own cache

// Conservative: true only if EVERY segment from a point of the source polygon to a point of
// the receiver polygon (convex, vertices in order, world space) passes through the interior
// of the part (closed: its polytope; flat: its polygon, crossed through its plane). A part
// that touches the shaft only on its boundary never occludes. No allocation. See
// occlusion_exact.cpp for the construction and its margins.
bool occludesExact(std::span<const DVec3> source, std::span<const DVec3> receiver,
                   const ConvexPart& part);

struct ShaftQuery {
    std::span<const DVec3> source;    // convex polygon, world space
    std::span<const DVec3> receiver;  // convex polygon, world space
    OcclusionTest test = OcclusionTest::Exact;
    // true: the polygons' hull shaft for culling (tighter); false: the box shaft (the paper's).
    // The paper's OBB occlusion test always runs on the box shaft (it needs its side-plane
    // pairs), after culling by the chosen shaft.
    bool polygon_shaft = true;
    // Parts never tested (e.g. the parts holding the source and receiver polygons: see
    // partsOfPolygon). Sorted or not; expected short.
    std::span<const uint32_t> excluded;
    // Stop at the first occluder (the link is dead; `candidates` is then incomplete).
    bool stop_at_occluder = true;
    // Flat parts lying in one of these planes (within plane_tolerance) are not candidates:
    // an end that lies in such a plane (a flat cluster of a wall) sends every segment off
    // the plane at once, so nothing in the plane can block it.
    std::span<const Plane> ignored_planes;
    double plane_tolerance = 0.0;
    // Only whether any candidate is left: stop at the first (`candidates` then holds it).
    // Needs OcclusionTest::None (an occluder could come later in the list).
    bool first_candidate_only = false;
};

struct ShaftResult {
    bool occluded = false;
    uint32_t occluder = kNoPart;        // the part found occluding (first one)
    // Crossing parts, in input order (a tree node's parts depth first); with
    // OcclusionTest::None, a tree node wholly inside the shaft stays one entry (kPartNode).
    std::vector<uint32_t> candidates;
    // Counters for statistics.
    uint32_t tested = 0;            // parts classified (excluded ones are not counted)
    uint32_t tested_nodes = 0;      // part-tree nodes classified
    uint32_t outside_aabb = 0;      // culled by the AABB test
    uint32_t outside_obb = 0;       // culled by the OBB test after passing the AABB test
    uint32_t occlusion_tests = 0;   // occlusion tests run
    // Classification failed (only allocation can fail): `candidates` is then every input part
    // and no occlusion is claimed, the conservative answer. Callers count and report it.
    bool fell_back = false;
};

// Classifies `parent_candidates` (indices into parts.parts or kPartNode | tree node: the
// parent link's list, or allParts) against the shaft of query.source -> query.receiver. An
// allocation failure gives the conservative answer (fell_back); only failing to allocate
// that answer's candidate list throws (std::bad_alloc, which the solver's boundary reports).
ShaftResult classifyLink(const PartSet& parts, std::span<const uint32_t> parent_candidates,
                         const ShaftQuery& query);
// Same, writing into `result` (its candidate vector's capacity is reused).
void classifyLink(const PartSet& parts, std::span<const uint32_t> parent_candidates,
                  const ShaftQuery& query, ShaftResult& result);

// One part against one shaft (the shaft must be built from query.source/receiver; a Boxes
// shaft is needed for OcclusionTest::Obb: pass it as box_shaft, else null).
PartVsShaft classifyPart(const ConvexPart& part, const Shaft& shaft, const Shaft* box_shaft,
                         std::span<const DVec3> source, std::span<const DVec3> receiver,
                         OcclusionTest test);

// The root candidate list: the tree's root node, or every part index 0..n-1 without a tree.
std::vector<uint32_t> allParts(const PartSet& parts);

// Parts named by a candidate list (a node counts its parts), and the list as part indices.
size_t candidatePartCount(const PartSet& parts, std::span<const uint32_t> candidates);
std::vector<uint32_t> expandCandidates(const PartSet& parts, std::span<const uint32_t> candidates);

// The parts covering polygon `polygon` of mesh `mesh` (normally one; a non-convex polygon
// may be split over several): what a solver excludes for an element of that polygon.
std::vector<uint32_t> partsOfPolygon(const PartSet& parts, uint32_t mesh, uint32_t polygon);

}  // namespace radbake
