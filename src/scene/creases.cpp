#include "scene/creases.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace radbake {
namespace {

// One corner of a triangle around the vertex being split: the triangle's other corner
// `other` (the edge v-other) and the triangle's place in the vertex's incident list.
struct EdgeEnd {
    uint32_t other;
    uint32_t local;
};

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

}  // namespace

size_t splitHardEdges(Mesh& mesh, size_t* split) {
    const size_t n = mesh.positions.size();
    if (!mesh.normals.empty() || mesh.triangles.empty()) return 0;
    for (const UVec3& t : mesh.triangles)
        if (t.x >= n || t.y >= n || t.z >= n) return 0;  // validation drops these; never index past the end
    const size_t triangle_count = mesh.triangles.size();
    const double cos_crease = std::min(std::cos(static_cast<double>(mesh.crease_angle)), 1.0 - kCreaseCoplanar);

    std::vector<DVec3> face_normal(triangle_count, DVec3(0.0));
    for (size_t t = 0; t < triangle_count; ++t) {
        const UVec3& tri = mesh.triangles[t];
        const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
        const DVec3 cross = glm::cross(b - a, c - a);
        const double length = glm::length(cross);
        if (length > 0.0 && std::isfinite(length)) face_normal[t] = cross / length;
    }
    const auto smooth = [&](uint32_t s, uint32_t t) {
        return mesh.triangle_polygon[s] == mesh.triangle_polygon[t] ||
               glm::dot(face_normal[s], face_normal[t]) >= cos_crease;
    };

    // Triangles around each vertex, in triangle order (compressed rows).
    std::vector<uint32_t> row(n + 1, 0);
    for (const UVec3& tri : mesh.triangles)
        for (int k = 0; k < 3; ++k) ++row[tri[k] + 1];
    std::partial_sum(row.begin(), row.end(), row.begin());
    std::vector<uint32_t> incident(row[n]);
    {
        std::vector<uint32_t> fill(row.begin(), row.end() - 1);
        for (uint32_t t = 0; t < triangle_count; ++t)
            for (int k = 0; k < 3; ++k) incident[fill[mesh.triangles[t][k]]++] = t;
    }

    // Faces around a vertex are joined through their shared edges that are smooth; each
    // group but the first (the one of the vertex's first triangle) gets a copy of the vertex.
    std::vector<UVec3> triangles = mesh.triangles;
    std::vector<uint32_t> parent, group_vertex;
    std::vector<EdgeEnd> ends;
    size_t added = 0, shared = 0;
    for (uint32_t v = 0; v < n; ++v) {
        const uint32_t* around = incident.data() + row[v];
        const uint32_t k = row[v + 1] - row[v];
        if (k < 2) continue;
        parent.resize(k);
        std::iota(parent.begin(), parent.end(), 0u);
        ends.clear();
        for (uint32_t i = 0; i < k; ++i)
            for (int c = 0; c < 3; ++c)
                if (mesh.triangles[around[i]][c] != v) ends.push_back({mesh.triangles[around[i]][c], i});
        std::sort(ends.begin(), ends.end(),
                  [](const EdgeEnd& a, const EdgeEnd& b) { return a.other != b.other ? a.other < b.other : a.local < b.local; });
        for (size_t j = 1; j < ends.size(); ++j)
            if (ends[j].other == ends[j - 1].other && smooth(around[ends[j - 1].local], around[ends[j].local]))
                parent[findRoot(parent, ends[j].local)] = findRoot(parent, ends[j - 1].local);
        group_vertex.assign(k, UINT32_MAX);
        bool first = true;
        for (uint32_t i = 0; i < k; ++i) {
            uint32_t& target = group_vertex[findRoot(parent, i)];
            if (target == UINT32_MAX) {
                if (first) {
                    target = v;
                    first = false;
                } else {
                    target = static_cast<uint32_t>(mesh.positions.size());
                    const Vec3 p = mesh.positions[v];
                    mesh.positions.push_back(p);
                    if (!mesh.vertex_colors.empty()) mesh.vertex_colors.push_back(Vec3(mesh.vertex_colors[v]));
                    if (!mesh.uv0.empty()) mesh.uv0.push_back(Vec2(mesh.uv0[v]));
                    ++added;
                }
            }
            for (int c = 0; c < 3; ++c)
                if (mesh.triangles[around[i]][c] == v) triangles[around[i]][c] = target;
        }
        if (std::any_of(group_vertex.begin(), group_vertex.end(), [v](uint32_t g) { return g != UINT32_MAX && g != v; }))
            ++shared;
    }
    mesh.triangles = std::move(triangles);
    if (split) *split = shared;
    return added;
}

void splitHardEdges(Scene& scene) {
    for (Mesh& mesh : scene.meshes) {
        size_t shared = 0;
        const size_t added = splitHardEdges(mesh, &shared);
        if (added == 0) continue;
        ++scene.crease_split.meshes;
        scene.crease_split.vertices += shared;
        scene.crease_split.added += added;
    }
}

}  // namespace radbake
