#pragma once
// Root polygons cut along the lines where another surface touches or crosses them.
//
// A floor polygon partly under a block that stands on it, or a beam's side face partly below
// the ground it goes into, is otherwise one element whose radiosity is the mean over a lit
// part and a part nothing can see. Whatever sees the lit part then reads it too dark twice
// over (the mean, and rays that find the hidden rest blocked): a vertex on a block's bottom
// edge came out about half its path-traced value. And the element's own few visibility
// samples can all land on the hidden part: the strip of a beam above the ground read black.
// Cut along the contact, each piece is lit or hidden as a whole, and refinement needs no
// elements at the scale of the contact to find the line.
#include <cstdint>
#include <vector>

#include "geometry/types.h"

namespace radbake {

struct RootPolygon {
    uint32_t mesh = 0;
    uint32_t polygon = 0;
    std::vector<DVec3> loop;  // convex, planar, counter-clockwise around its normal
};

// Replaces each polygon that another one touches or crosses (along a segment that enters
// its interior by more than `tolerance`, the other rising at least 1e-3 of its size from its
// plane; the piece behind the other's plane at least 1 % of its area, the piece in front of it
// at least 0.1 %: a lit sliver beside a block's foot is most of what the foot's edge sees) by
// its pieces on either side of that polygon's plane, in place and in order (a polygon's pieces
// follow each other). Polygons sharing only
// an edge (a room's corner, a box's own faces) or lying in one plane are left whole. Pieces
// stay convex, at most `max_vertices` corners. Returns the number of cuts made.
// Deterministic; O(n log n) plus the touching pairs.
size_t cutAtContacts(std::vector<RootPolygon>& polygons, double tolerance, size_t max_vertices);

// Replaces each polygon that the plane of a light source near it crosses (emits[i]: polygon i
// is such a source; near: within twice the diagonal of the box of its mesh's sources) by its
// pieces on either side of that plane, with the same 1 % floor. A one-sided source sends nothing behind its plane, so direct
// light falls to zero at the plane and stays zero past it: a wall's top strip above a ceiling
// lamp is dark, and a tile spanning the plane read the mean of the two sides, which is what the
// room's corners saw there (+30 % at the tessellated Cornell box's ceiling corners). Sources
// are not cut. The lit piece touching the plane is cut again halfway up (its direct light
// rises from zero at the plane). `polygons` and `emits` are indexed alike (emits is not
// updated). And each polygon of `reflects` facing the back of a source of `outlines`
// (one-sided, of any power) across a gap under a tenth of its mesh's size (a ceiling above a
// lamp hung under it) by its pieces on either side of the planes through that source's
// outline, square to it: it is dark where the source hides it and lit beside it (a black one
// is dark everywhere: not cut). Returns the cuts.
size_t cutAtSourcePlanes(std::vector<RootPolygon>& polygons, const std::vector<bool>& emits,
                         const std::vector<bool>& outlines, const std::vector<bool>& reflects, double tolerance,
                         size_t max_vertices);

}  // namespace radbake
