#pragma once
// Internal to scene validation (validate.cpp and validate_overlap.cpp); not a public contract.
#include <string>
#include <vector>

#include "scene/scene.h"

namespace radbake::validation {

// "mesh 'name'" or "mesh #index" for messages.
std::string describeMesh(const Mesh& mesh, size_t index);

// The scene's extent for tolerances: the largest coordinate magnitude or the bounding
// diagonal, whichever is larger (float rounding grows with the coordinates' magnitude).
double sceneExtent(const std::vector<Mesh>& meshes);

// Whether the overlap check's scratch fits in `max_memory_mb` (<= 0: unbounded); false after
// a located error naming the budget.
bool overlapCheckFits(const Scene& scene, double max_memory_mb, Diagnostics& diagnostics);

// Coplanar faces facing the same way that overlap (duplicates, or partly: z-fighting, and
// light counted twice in radiosity): one warning per mesh pair with the count and a point of
// the overlap. Back-to-back faces and faces that only share an edge or touch are not reported.
// The pairs examined and the overlaps kept are bounded (faces stacked by the thousand in one
// plane would be quadratic): past the bound, a note says the check stopped early.
// Expects cleaned meshes (no degenerate triangles, a valid polygon map).
void reportCoplanarOverlaps(const std::vector<Mesh>& meshes, Diagnostics& diagnostics);

}  // namespace radbake::validation
