#pragma once
// Per-vertex baked light. CONTRACT between the solver side and the exporters.
#include <vector>

#include "core/math.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "readout/reconstruct.h"

namespace radbake {

struct Scene;
struct Solution;

// values[m][v]: the baked quantity at vertex v of Scene::meshes[m]; by default H / pi
// (DESIGN.md section 2), linear, may exceed 1.
struct VertexBake {
    std::vector<std::vector<Vec3>> values;
    ReadoutWork work;  // of the link read-out (none with the exhaustive gather)
};

// On the runner's threads; each vertex writes its own slot, so the values do not depend on
// the thread count. A cancelled runner leaves vertices unevaluated (discard the bake).
// `progress`, when given, moves with the vertices done. Vertices of any meshes at one
// position (bit for bit) share their light per face normal. `options.gather`: the link
// reconstruction, or the exhaustive gather (the reference, for --texel-tolerance 0).
VertexBake bakeVertices(const Scene& scene, const Solution& solution, const ReadoutOptions& options,
                        ParallelRunner& runner, Progress* progress = nullptr);

}  // namespace radbake
