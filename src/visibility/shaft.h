#pragma once
// Shafts (Haines-Wallace 1991) and the outside/crossing classification of boxes against them
// (Dupuy, Paulin, Caubet: "Occlusion evaluation in hierarchical radiosity"; DESIGN.md s.1).
//
// A shaft is a convex region bounded by planes with outward normals: a point p is inside when
// plane.eval(p) <= 0 for every plane. It contains every segment joining a point of the source
// to a point of the receiver, so a part outside the shaft cannot occlude the link.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/types.h"

namespace radbake {

// Two "opposite" side planes of a Haines-Wallace shaft seen in the projection along `axis`
// (both planes are parallel to that axis). The paper's OBB occlusion test checks that an
// occluder spans the channel between them. See occlusion.h.
struct ShaftPair {
    uint8_t first = 0;   // index into Shaft::planes
    uint8_t second = 0;  // index into Shaft::planes
    uint8_t axis = 0;    // projection axis (0 x, 1 y, 2 z)
};

enum class ShaftKind { Boxes, Polygons };

struct Shaft {
    ShaftKind kind = ShaftKind::Boxes;
    Aabb box;                   // union of the two ends' boxes (both kinds)
    std::vector<Plane> planes;  // all bounding planes, outward unit normals, conservative
                                // (pushed out by a rounding tolerance; see shaft.cpp)
    // Boxes kind only: planes[0..5] are the union box's faces (-x,+x,-y,+y,-z,+z); the side
    // planes follow, grouped by the axis they are parallel to (x, then y, then z) and, within
    // an axis, in cyclic order around it. At most 6 + 8 = 14 planes.
    std::array<uint8_t, 4> side_begin{6, 6, 6, 6};  // side planes parallel to axis k:
                                                    // planes[side_begin[k] .. side_begin[k+1])
    // Boxes kind only: one pair of opposite walls per direction transverse to link_axis (2
    // pairs), each seen in the projection along the remaining axis; a wall is a side plane
    // parallel to that axis, or the union box's face where the two boxes tie.
    std::vector<ShaftPair> pairs;
    int link_axis = 0;             // axis of largest separation between the two ends' centres
    // Magnitude of the coordinates involved (max |coordinate| of both ends): rounding-error
    // tolerances of every test against this shaft are multiples of it.
    double scale = 1.0;
};

// Haines-Wallace shaft: the union box plus the side planes joining the two boxes' edges.
// Works for any two boxes (overlapping, nested, touching, equal).
Shaft shaftBetweenBoxes(const Aabb& source, const Aabb& receiver);

// The convex hull of the two convex polygons (vertices in order, 3 or more each, world
// space): its face planes (at most |S| + |R| + 2 for planar polygons). Never larger than the
// box shaft of the polygons' boxes. Falls back to that box shaft when the hull is flat
// (coplanar polygons) or degenerate. Cost: ~1.5 us for two quads (every edge-vertex plane is
// tried), against ~0.3 us for shaftBetweenBoxes; see tools/bench_visibility.
Shaft shaftBetweenPolygons(std::span<const DVec3> source, std::span<const DVec3> receiver);

enum class Side { Outside, Crossing };

// Interval arithmetic: outside when the minimum of some plane function over the box is
// positive (beyond a tolerance on the safe side, so never Outside for a box that touches or
// crosses the shaft, even with rounding).
Side classifyAabb(const Shaft& shaft, const Aabb& box);

// The same test, and also whether the box lies wholly inside the shaft (every plane's
// maximum over the box at most 0: then every box inside it is Crossing for classifyAabb).
// For tree nodes of parts (part_tree.h): Outside drops every part below, Inside keeps them.
enum class BoxSide { Outside, Crossing, Inside };
BoxSide classifyAabbInside(const Shaft& shaft, const Aabb& box);

// The paper's OBB form: the box as a corner origin plus three edge vectors E_i, and the
// minimum of each plane as P(origin) + sum_i min(0, N.E_i).
Side classifyObb(const Shaft& shaft, const Obb& box);

// Per (shaft, OBB) cache of the plane values the crossing test computes and the paper's
// occlusion test reuses ("the cache of plane values").
// Left uninitialised on purpose (it lives on the stack of every OBB test); filled for the
// first kMaxPlanes planes, which covers every box shaft (<= 14 planes).
struct ObbPlaneCache {
    static constexpr int kMaxPlanes = 16;
    std::array<double, kMaxPlanes> at_origin;                  // P(origin corner)
    std::array<std::array<double, 3>, kMaxPlanes> n_dot_edge;  // N . E_i
    DVec3 origin;
    std::array<DVec3, 3> edges;                                // E_i = 2 h_i a_i
};

// classifyObb that also fills the cache (for every plane up to kMaxPlanes).
Side classifyObb(const Shaft& shaft, const Obb& box, ObbPlaneCache& cache);

}  // namespace radbake
