#pragma once
#include "scene/scene.h"

namespace radbake {

// Checks a freshly read scene before anything else sees it. Non-finite numbers are located
// errors; degenerate triangles, out-of-range indices and unused vertices are dropped and
// counted in one warning per mesh; reflectance >= 1 is clamped below 1 with a warning naming
// the material; duplicate or partly overlapping coplanar faces facing the same way are reported (back-to-back faces are not). False when an error was reported.
// The overlap check's scratch is asked of `max_memory_mb` (> 0; 0: unbounded) first: a scene
// it cannot hold is an error; its pairwise work is bounded (a note says when it stopped early).
bool validateScene(Scene& scene, Diagnostics& diagnostics, double max_memory_mb = 0.0);

}  // namespace radbake
