#include "scene/scene_budget.h"

#include <algorithm>
#include <cstdio>

#include "scene/scene.h"

namespace radbake {

double meshBytesEstimate(double vertices, double triangles) {
    // Per vertex: position, normal, colour, UV; per triangle: its indices and polygon, up to
    // three vertex copies at hard edges, and validation's per-triangle scratch.
    constexpr double kMeshBytes = sizeof(Mesh) + 512.0, kVertexBytes = 48.0, kTriangleBytes = 3 * 48.0 + 64.0;
    return kMeshBytes + vertices * kVertexBytes + triangles * kTriangleBytes;
}

std::string overBudgetMessage(const std::string& what, double meshes, double triangles, double bytes,
                              const MemoryGauge& memory) {
    char counts[96];
    std::snprintf(counts, sizeof counts, "%.0f triangles in %.0f mesh%s", triangles, meshes, meshes == 1 ? "" : "es");
    return what + " expands to " + counts + ", about " + bytesText(bytes) + ", more than the memory budget leaves (" +
           bytesText(std::max(memory.roomBytes(), 0.0)) + " of " + bytesText(memory.budgetMegabytes() * 1048576.0) +
           "; --max-memory)";
}

}  // namespace radbake
