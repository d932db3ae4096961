#pragma once
// Mesh vertices welded by exact position: readers split vertices by normal or UV, but
// adjacency (closed surfaces, shared edges) is about positions. Used by the convex parts
// (geometry/parts.cpp) and the closed two-sided meshes (scene/two_sided.cpp).
#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace radbake {

struct WeldedPositions {
    std::vector<DVec3> points;  // each distinct position once
    std::vector<uint32_t> id;   // mesh vertex -> index into points
};

// -0 and +0 weld; anything else must be bit-equal.
WeldedPositions weldPositions(const Mesh& mesh);

}  // namespace radbake
