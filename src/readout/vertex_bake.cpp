// Per-vertex bake: the solution read at each original vertex, so values are smooth and
// independent of the element quadtree.
#include "readout/vertex_bake.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <map>
#include <cstdint>
#include <optional>
#include <span>

#include "readout/reconstruct.h"
#include "radiosity/solution.h"
#include "scene/scene.h"

namespace radbake {
namespace {

// Face normals closer than this (1 - cos angle) count as one plane at a vertex: the
// reconstruction's, so that its SideLights match these groups.
constexpr double kSameNormal = LinkReconstruction::kSameNormal;

struct Incident {
    DVec3 normal;
    double weight;
    uint32_t mesh, triangle;
};

// Faces grouped by normal, in first-seen order: one H per group.
std::vector<Incident> groupByNormal(const std::vector<Incident>& faces) {
    std::vector<Incident> groups;
    for (const Incident& f : faces) {
        auto it = std::find_if(groups.begin(), groups.end(),
                               [&](const Incident& g) { return glm::dot(g.normal, f.normal) > 1.0 - kSameNormal; });
        if (it == groups.end()) groups.push_back(f);
        else it->weight += f.weight;
    }
    return groups;
}

// One point of the scene where vertices of any mesh coincide: H per normal group of every
// face around it, each evaluated once on the group's first face, so coincident vertices of
// neighbouring meshes (duplicated at a material boundary) get the same light.
struct WeldedPoint {
    DVec3 p;
    std::vector<Incident> faces;   // of every vertex there
    std::vector<Incident> groups;  // faces grouped by normal
    std::vector<DVec3> h;          // per group
};

// The irradiance the solve gave a leaf: what its own links and its ancestors' gathered (a
// root's includes its cluster links), max channel.
double solvedIrradiance(const Solution& solution, uint32_t leaf) {
    DVec3 h(0.0);
    for (uint32_t e = leaf; e != kNoElement; e = solution.elements[e].parent) h += solution.elements[e].gathered;
    return std::max({h.x, h.y, h.z});
}

// Where the solve lit the leaves of the faces around a vertex (in `group`'s plane) very
// unequally (the dimmest below kUnequalLeaves of the brightest), a shadow or contact line runs
// through the vertex, and each leaf's links carry visibility averaged over a leaf mostly on one
// side of it: read through one face's links, a vertex beside a block took the light of a tile
// mostly under it, and a ceiling vertex over a lamp hung just below it the light of a tile
// reaching past the lamp's shadow (the mean over the leaves, too, read it twice its light). There
// the vertex takes the exhaustive gather, which reads every root with rays at the point. (A
// leaf's links read with rays at the vertex for every source cost a third as much, but read a
// lit room's furniture vertices darker than a path tracer does, where the exhaustive gather
// agrees with it: docs/readout.md.)
constexpr double kUnequalLeaves = 0.5;

DVec3 irradianceAt(const Solution& solution, const LinkReconstruction& links, const WeldedPoint& point,
                   const Incident& group) {
    std::array<uint32_t, 16> leaves{};
    size_t count = 0;
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (const Incident& f : point.faces) {
        if (!(glm::dot(f.normal, group.normal) > 1.0 - kSameNormal)) continue;
        const uint32_t leaf = links.leafAt(f.mesh, f.triangle, point.p);
        if (leaf == kNoElement || std::find(leaves.begin(), leaves.begin() + count, leaf) != leaves.begin() + count)
            continue;
        if (count == leaves.size()) break;
        leaves[count++] = leaf;
        const double h = solvedIrradiance(solution, leaf);
        lo = std::min(lo, h);
        hi = std::max(hi, h);
    }
    if (count < 2 || !(hi > 0.0) || lo >= kUnequalLeaves * hi)
        return links.irradianceUncorrected(group.mesh, group.triangle, point.p, group.normal);
    return links.irradianceExhaustive(group.mesh, group.triangle, point.p, group.normal);
}

// The direction into the group's faces at the point: the mean of the unit directions to its
// triangles' centroids, in its plane (what tools/vertex_probes nudges a vertex's probe along).
DVec3 interiorOf(const Scene& scene, const WeldedPoint& point, const Incident& group) {
    DVec3 sum(0.0);
    for (const Incident& f : point.faces) {
        if (!(glm::dot(f.normal, group.normal) > 1.0 - kSameNormal)) continue;
        const Mesh& mesh = scene.meshes[f.mesh];
        const UVec3& t = mesh.triangles[f.triangle];
        const DVec3 c = (DVec3(mesh.positions[t.x]) + DVec3(mesh.positions[t.y]) + DVec3(mesh.positions[t.z])) / 3.0;
        DVec3 d = c - point.p;
        d -= glm::dot(d, group.normal) * group.normal;
        if (glm::length(d) > 0.0) sum += glm::normalize(d);
    }
    return glm::length(sum) > 1e-6 ? glm::normalize(sum) : DVec3(0.0);
}

// The edge correction (reconstruct.cpp) of each normal group at a point, the faces beside read
// from the other groups' H where they have vertices there (a room's edges and corners): read
// once more through their own links instead, the correction cost about 2.4 x house.wrl's
// vertex time, where most faces beside have no vertex at the point. Each group's correction
// depends on the others' corrected H (a corner darkens each of its faces, and each face's H
// there reads the others): the groups are corrected together.
void correctEdges(const Scene& scene, const LinkReconstruction& links, WeldedPoint& point) {
    std::vector<LinkReconstruction::SideLight> side;
    for (size_t g = 0; g < point.groups.size(); ++g) side.push_back({point.groups[g].normal, point.h[g]});
    std::vector<LinkReconstruction::EdgeTerms> terms;
    bool any = false;
    for (size_t g = 0; g < point.groups.size(); ++g) {
        const Incident& group = point.groups[g];
        terms.push_back(
            links.edgeTermsAt(group.mesh, group.triangle, point.p, group.normal, side[g].h, side, interiorOf(scene, point, group)));
        any = any || !terms.back().faces.empty();
    }
    if (!any) return;
    const std::vector<DVec3> uncorrected = point.h;
    LinkReconstruction::correctTogether(side, uncorrected, terms);
    for (size_t g = 0; g < point.groups.size(); ++g) point.h[g] = side[g].h;
}

}  // namespace

namespace {

// Every vertex's incident faces, and the welded point each is at.
struct Welded {
    std::vector<std::vector<std::vector<Incident>>> incident;  // [mesh][vertex]
    std::vector<std::vector<uint32_t>> point_of;              // [mesh][vertex]: kNoElement when it has no face
    std::vector<WeldedPoint> points;
};

Welded weldVertices(const Scene& scene) {
    Welded w;
    w.incident.resize(scene.meshes.size());
    w.point_of.resize(scene.meshes.size());
    std::map<std::array<float, 3>, uint32_t> point_ids;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        w.incident[m].resize(mesh.positions.size());
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const UVec3& tri = mesh.triangles[t];
            if (tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() || tri.z >= mesh.positions.size())
                continue;
            const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
            const DVec3 n = glm::cross(b - a, c - a);
            const double len = glm::length(n);
            if (!(len > 0.0)) continue;
            for (uint32_t v : {tri.x, tri.y, tri.z})
                w.incident[m][v].push_back({n / len, 0.5 * len, static_cast<uint32_t>(m), static_cast<uint32_t>(t)});
        }
        w.point_of[m].assign(mesh.positions.size(), kNoElement);
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
            if (w.incident[m][v].empty()) continue;
            const Vec3& p = mesh.positions[v];
            const auto [it, added] = point_ids.emplace(std::array<float, 3>{p.x, p.y, p.z}, uint32_t(w.points.size()));
            if (added) w.points.push_back({DVec3(p), {}, {}, {}});
            WeldedPoint& point = w.points[it->second];
            point.faces.insert(point.faces.end(), w.incident[m][v].begin(), w.incident[m][v].end());
            w.point_of[m][v] = it->second;
        }
    }
    for (WeldedPoint& point : w.points) point.groups = groupByNormal(point.faces);
    return w;
}

}  // namespace

std::vector<double> vertexPointCosts(const Scene& scene) {
    const Welded w = weldVertices(scene);
    std::vector<double> costs;
    costs.reserve(w.points.size());
    for (const WeldedPoint& point : w.points) costs.push_back(static_cast<double>(point.groups.size()));
    return costs;
}

VertexPointLight readVertexPoints(const Scene& scene, const Solution& solution, const ReadoutOptions& options,
                                  ParallelRunner& runner, size_t begin, size_t end, Progress* progress) {
    Welded w = weldVertices(scene);
    VertexPointLight out;
    out.begin = std::min(begin, w.points.size());
    out.end = std::clamp(end, out.begin, w.points.size());
    std::optional<LinkReconstruction> links;
    const bool lit = carriesLight(solution);
    if (lit && options.gather == GatherMode::Links) links.emplace(solution, options, runner);
    std::atomic<size_t> done{0};
    const size_t count = out.end - out.begin;
    // Each welded point writes its own slot: the result does not depend on the thread count.
    runner.forRanges(count, 16, [&](size_t from, size_t to) {
        for (size_t k = out.begin + from; k < out.begin + to; ++k) {
            WeldedPoint& point = w.points[k];
            for (const Incident& g : point.groups)
                point.h.push_back(!lit   ? DVec3(0.0)
                                  : links ? irradianceAt(solution, *links, point, g)
                                          : surfaceIrradiance(solution, options, point.p, g.normal, g.mesh, g.triangle));
            if (links && options.edge_correction != EdgeCorrection::Off) correctEdges(scene, *links, point);
        }
        if (progress) progress->update(static_cast<double>(done += to - from) / static_cast<double>(count));
    });
    if (runner.cancelled()) return out;
    if (links) out.work = links->work();
    for (size_t k = out.begin; k < out.end; ++k) {
        out.groups.push_back(static_cast<uint32_t>(w.points[k].h.size()));
        out.h.insert(out.h.end(), w.points[k].h.begin(), w.points[k].h.end());
    }
    return out;
}

std::optional<VertexBake> assembleVertices(const Scene& scene, std::span<const VertexPointLight> parts) {
    Welded w = weldVertices(scene);
    VertexBake bake;
    size_t next = 0;  // the parts cover the points in order, each once
    for (const VertexPointLight& part : parts) {
        if (part.begin != next || part.end < part.begin || part.end > w.points.size() ||
            part.groups.size() != part.end - part.begin)
            return std::nullopt;
        size_t at = 0;
        for (size_t k = part.begin; k < part.end; ++k) {
            const uint32_t groups = part.groups[k - part.begin];
            if (groups != w.points[k].groups.size() || at + groups > part.h.size()) return std::nullopt;
            w.points[k].h.assign(part.h.begin() + static_cast<std::ptrdiff_t>(at),
                                 part.h.begin() + static_cast<std::ptrdiff_t>(at + groups));
            at += groups;
        }
        if (at != part.h.size()) return std::nullopt;
        next = part.end;
        bake.work += part.work;
    }
    if (next != w.points.size()) return std::nullopt;
    // A vertex: its own faces' normal groups, area-weighted, each read from its welded group.
    bake.values.resize(scene.meshes.size());
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        std::vector<Vec3>& values = bake.values[m];
        values.assign(scene.meshes[m].positions.size(), Vec3(0.0f));
        for (size_t v = 0; v < values.size(); ++v) {
            if (w.point_of[m][v] == kNoElement) continue;
            const WeldedPoint& point = w.points[w.point_of[m][v]];
            DVec3 sum(0.0);
            double weight = 0.0;
            for (const Incident& own : groupByNormal(w.incident[m][v])) {
                size_t g = 0;
                while (g + 1 < point.groups.size() && !(glm::dot(point.groups[g].normal, own.normal) > 1.0 - kSameNormal))
                    ++g;
                sum += own.weight * point.h[g];
                weight += own.weight;
            }
            if (weight > 0.0) values[v] = Vec3(sum / weight / kPi);
        }
    }
    return bake;
}

VertexBake bakeVertices(const Scene& scene, const Solution& solution, const ReadoutOptions& options,
                        ParallelRunner& runner, Progress* progress) {
    const VertexPointLight all = readVertexPoints(scene, solution, options, runner, 0, SIZE_MAX, progress);
    if (runner.cancelled()) return VertexBake{};
    return *assembleVertices(scene, std::span<const VertexPointLight>(&all, 1));
}

}  // namespace radbake
