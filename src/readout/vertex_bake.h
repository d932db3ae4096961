#pragma once
// Per-vertex baked light. CONTRACT between the solver side and the exporters.
#include <optional>
#include <span>
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

// bakeVertices in pieces, for a read-out split into shards: the scene's vertices welded into
// points (bit-identical positions of any mesh), in a fixed order, each read on its own, then
// every vertex assembled from its point. Reading points [0, n) in any ranges and assembling
// them gives bakeVertices' values bit for bit.
struct VertexPointLight {
    size_t begin = 0, end = 0;     // welded points read, [begin, end)
    std::vector<uint32_t> groups;  // per point: its normal groups
    std::vector<DVec3> h;          // per point and group: H (W/m^2), flattened
    ReadoutWork work;              // of the link read-out
};
// The estimated cost of reading each welded point (its normal groups), in order.
std::vector<double> vertexPointCosts(const Scene& scene);
// Reads points [begin, end) (clamped to the point count).
VertexPointLight readVertexPoints(const Scene& scene, const Solution& solution, const ReadoutOptions& options,
                                  ParallelRunner& runner, size_t begin, size_t end, Progress* progress = nullptr);
// The vertex values from parts that cover every point once, in order; nullopt when they do not
// (or do not match the scene's points).
std::optional<VertexBake> assembleVertices(const Scene& scene, std::span<const VertexPointLight> parts);

}  // namespace radbake
