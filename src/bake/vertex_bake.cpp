// Per-vertex bake: the solution gathered at each original vertex, so values are smooth and
// independent of the element quadtree.
#include "bake/vertex_bake.h"

#include <algorithm>
#include <atomic>
#include <map>


#include "radiosity/solution.h"
#include "scene/scene.h"

namespace radbake {
namespace {

// Face normals closer than this (1 - cos angle) count as one plane at a vertex.
constexpr double kSameNormal = 1e-6;

struct Incident {
    DVec3 normal;
    double weight;
};

// The vertex's incident faces grouped by normal: one H per group, averaged by area.
DVec3 bakeVertex(const Solution& solution, const DVec3& p, const std::vector<Incident>& faces) {
    std::vector<Incident> groups;
    for (const Incident& f : faces) {
        auto it = std::find_if(groups.begin(), groups.end(),
                               [&](const Incident& g) { return glm::dot(g.normal, f.normal) > 1.0 - kSameNormal; });
        if (it == groups.end()) groups.push_back(f);
        else it->weight += f.weight;
    }
    DVec3 sum(0.0);
    double weight = 0.0;
    for (const Incident& g : groups) {
        sum += g.weight * probeIrradiance(solution, p, g.normal);
        weight += g.weight;
    }
    return weight > 0.0 ? sum / weight : DVec3(0.0);
}

}  // namespace

VertexBake bakeVertices(const Scene& scene, const Solution& solution, ParallelRunner& runner, Progress* progress) {
    VertexBake bake;
    bake.values.resize(scene.meshes.size());
    size_t total = 0;
    for (const Mesh& mesh : scene.meshes) total += mesh.positions.size();
    std::atomic<size_t> done{0};
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        std::vector<std::vector<Incident>> incident(mesh.positions.size());
        for (const UVec3& t : mesh.triangles) {
            if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size()) continue;
            const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
            const DVec3 n = glm::cross(b - a, c - a);
            const double len = glm::length(n);
            if (!(len > 0.0)) continue;
            for (uint32_t v : {t.x, t.y, t.z}) incident[v].push_back({n / len, 0.5 * len});
        }
        std::vector<Vec3>& values = bake.values[m];
        values.assign(mesh.positions.size(), Vec3(0.0f));
        // Each vertex writes its own slot: the result does not depend on the thread count.
        runner.forRanges(mesh.positions.size(), 16, [&](size_t begin, size_t end) {
            for (size_t v = begin; v < end; ++v) {
                if (incident[v].empty()) continue;
                const DVec3 h = bakeVertex(solution, DVec3(mesh.positions[v]), incident[v]);
                values[v] = Vec3(h / kPi);
            }
            if (progress) progress->update(static_cast<double>(done += end - begin) / static_cast<double>(total));
        });
    }
    return bake;
}

}  // namespace radbake
