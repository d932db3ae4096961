#pragma once
// Whether a bundle of directions from a point is blocked by a set of triangles: every ray from
// `apex` whose direction lies in the patch meets one of them. Used to prove a sky quadrature cell
// dark (radiosity/sky_light.h) before trusting its four samples: a gap between two blockers (a slit
// between two roof panels) leaves part of the patch uncovered, however its samples fell.
#include <array>
#include <cstddef>
#include <span>

#include "core/math.h"

namespace radbake {

// `boundary` holds unit directions around the patch, in order, close enough together that the
// patch's outline is straight between them in the gnomonic projection about its centre (a few
// degrees apart); the patch is taken as that outline's bounding rectangle there, widened by 2 %
// (so the test errs towards "not covered"). A patch wider than about 140 degrees is never
// covered. The triangles are opaque, in the same frame as `apex`; a part of one behind the apex's
// plane square to the patch is cut off. Covered when what the triangles leave of the rectangle
// has no area above 1e-9 of it: triangles sharing an edge leave only slivers of rounding.
// `face_ends` groups the triangles into faces (face f ends before face_ends[f]; none: each
// triangle its own): a convex face is taken as one polygon, so its inner seams need no rounding.
bool patchCovered(const DVec3& apex, std::span<const DVec3> boundary, std::span<const std::array<DVec3, 3>> triangles,
                  std::span<const size_t> face_ends = {});

}  // namespace radbake
