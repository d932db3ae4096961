#pragma once
// The parts stage: a Scene's meshes -> convex parts (closed convex solids and flat convex
// polygons), each with an AABB and a tight OBB. These are the potential occluders that
// shafts test (DESIGN.md section 1).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/part_tree.h"
#include "geometry/types.h"
#include "scene/scene.h"

namespace radbake {

struct PartOptions {
    // Merge coplanar neighbouring polygons (sharing an edge) while their union stays convex.
    bool merge_coplanar = true;
    // Detect closed convex meshes that the reader did not flag (Mesh::convex_solid).
    bool detect_convex_solids = true;
    // Plane tolerance as a fraction of the part's (or polygon's) largest extent: points this
    // close to a plane count as on it. 1e-5 sits well above float rounding of positions
    // (~6e-8 relative) and well below any feature a lighting baker resolves.
    double relative_tolerance = 1e-5;
    // Tolerance (fraction of the mesh's extent) for detecting that a closed mesh is convex.
    // Files often print 4-6 significant digits, which dents a tessellated sphere by ~2e-4 of
    // its size; 1e-3 accepts such dents. The part is then the mesh's hull, which overshoots
    // the mesh by at most this much (a sliver no lighting result can see).
    double solid_relative_tolerance = 1e-3;
    // Two polygon normals count as coplanar when the angle between them is below this
    // (radians), and the planes' offsets agree within the tolerance above.
    double coplanar_angle = 1e-3;
};

struct PartStats {
    size_t parts = 0;
    size_t closed_parts = 0;
    size_t flat_parts = 0;
    size_t closed_meshes = 0;           // meshes that became one closed part
    size_t degenerate_polygons = 0;     // zero-area polygons/triangles that made no part
    size_t degenerate_solids = 0;       // convex_solid meshes that fell back to flat parts
    // Tightness: OBB volume / hull volume over closed parts, OBB area / polygon area over
    // flat parts (1 is perfect). 0 when there are no parts of that kind.
    double mean_obb_volume_ratio = 0.0;
    double max_obb_volume_ratio = 0.0;
    double mean_obb_area_ratio = 0.0;
    double max_obb_area_ratio = 0.0;
};

inline constexpr uint32_t kNoPart = std::numeric_limits<uint32_t>::max();

struct PartSet {
    std::vector<ConvexPart> parts;
    PartStats stats;
    // polygon_part[mesh][polygon]: the part covering that source polygon, kNoPart when the
    // polygon is degenerate. A non-convex polygon may span several parts; this holds one.
    std::vector<std::vector<uint32_t>> polygon_part;
    // part_mesh[mesh]: the mesh whose parts stand for it, itself or, for a back twin
    // (scene/two_sided.h), its front (a twin makes no parts of its own). Empty for a
    // hand-made set: every mesh stands for itself.
    std::vector<uint32_t> part_mesh;
    Aabb bounds;  // of every part
    // Boxes over the parts, for shaft culling (part_tree.h); built by buildParts. Empty for
    // a hand-made set: candidate lists are then plain part indices.
    PartTree tree;
};

// Never throws; problems (degenerate solids, ...) are reported as warnings/notes.
PartSet buildParts(const Scene& scene, const PartOptions& options, Diagnostics& diagnostics);

// Builds one part from a point set: closed hull if the points span a volume, else a flat
// polygon (their 2D hull); nullopt-like empty part (no vertices) when fully degenerate.
// Useful for tests and for callers with their own geometry (e.g. shaft ends).
ConvexPart partFromPoints(const std::vector<DVec3>& points, double relative_tolerance = 1e-5);

// Fills aabb and obb of a part from its vertices (closed: tight 3D OBB; flat: flat OBB).
void fitPartBoxes(ConvexPart& part);

// Tightness of a part's OBB: volume ratio (closed) or area ratio (flat); 0 if degenerate.
double obbTightness(const ConvexPart& part);

}  // namespace radbake
