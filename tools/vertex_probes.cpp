// vertex_probes: a probe file (`radbake bake --probes`, `reference_mc`) with one probe at every
// vertex of the scene's meshes, for the per-vertex accuracy yardstick (issue 13: a vertex on an
// edge holds the limit of the value from inside its own face).
//
//   vertex_probes SCENE OUT.probes [--nudge F=1e-4] [--unit-scale U=1]
//
// For each mesh vertex, the triangles around it are grouped by plane (normals within 0.01 rad:
// one group for a vertex inside a flat face or on its border, one per face for a vertex that
// faces with different normals share, as at a VRML Box's corners). Each (vertex, plane) pair
// is a probe: normal = the plane's area-weighted normal; position = the vertex moved F x the
// scene's diagonal (F = 1e-4 by default) into its own face, along the mean of the unit
// directions from the vertex to its group's triangle centroids (projected into the plane),
// checked to land inside one of those triangles (else towards the centroid of the first one,
// at most half way). A vertex in the middle of a flat face stays where it is. Degenerate
// triangles are ignored; a vertex no triangle uses gets no probe.
//
// Each line is `x y z nx ny nz # mesh M vertex V` (positions in the scene file's units, as
// probe files are): `#` starts a comment in probe files, so readers see six numbers and a
// human sees which vertex it was. Prints the probe count and the nudge on stderr.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "io/import.h"
#include "scene/two_sided.h"

namespace {

using namespace radbake;

int usage() {
    std::fprintf(stderr, "usage: vertex_probes SCENE OUT.probes [--nudge F=1e-4] [--unit-scale U=1]\n");
    return 2;
}

struct Group {
    DVec3 normal_sum{0.0};   // area-weighted
    DVec3 first_normal{0.0};  // unit, what later triangles are compared with
    DVec3 direction{0.0};    // sum of unit directions to centroids
    std::vector<uint32_t> triangles;
};

// Is p inside triangle (a, b, c) (normal n), edges included up to a relative tolerance?
bool insideTriangle(const DVec3& p, const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& n) {
    const double tolerance = -1e-9;
    const double area2 = glm::dot(glm::cross(b - a, c - a), n);
    if (!(area2 > 0.0)) return false;
    const double u = glm::dot(glm::cross(c - b, p - b), n) / area2;
    const double v = glm::dot(glm::cross(a - c, p - c), n) / area2;
    const double w = glm::dot(glm::cross(b - a, p - a), n) / area2;
    return u >= tolerance && v >= tolerance && w >= tolerance;
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene_path, out_path;
    double nudge_fraction = 1e-4;
    ImportOptions import;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        const char* v = nullptr;
        if (arg == "--nudge" && (v = value())) nudge_fraction = std::strtod(v, nullptr);
        else if (arg == "--unit-scale" && (v = value())) import.unit_scale = std::strtof(v, nullptr);
        else if (!arg.empty() && arg[0] != '-' && scene_path.empty()) scene_path = arg;
        else if (!arg.empty() && arg[0] != '-' && out_path.empty()) out_path = arg;
        else return usage();
    }
    if (scene_path.empty() || out_path.empty() || !(nudge_fraction >= 0.0) || !(import.unit_scale > 0.0f))
        return usage();

    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic& d) {
        if (d.severity != Severity::Note) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
    };
    std::optional<Scene> scene = importScene(scene_path, import, diagnostics);
    if (!scene) return 1;
    addBackTwins(*scene);  // a two-sided mesh's back vertices are vertices of the bake too

    // The scene's diagonal over every vertex a triangle uses (world units, as reference_mc's).
    DVec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Mesh& mesh : scene->meshes)
        for (const UVec3& tri : mesh.triangles)
            for (uint32_t index : {tri.x, tri.y, tri.z})
                if (index < mesh.positions.size()) {
                    lo = glm::min(lo, DVec3(mesh.positions[index]));
                    hi = glm::max(hi, DVec3(mesh.positions[index]));
                }
    const double extent = lo.x <= hi.x ? glm::length(hi - lo) : 0.0;
    const double nudge = nudge_fraction * extent;
    const double coplanar_cos = std::cos(0.01);
    const double to_file = 1.0 / double(import.unit_scale);

    std::ostringstream out;
    out << "# vertex probes of " << scene_path << ": every (vertex, plane) of every mesh, nudged "
        << nudge_fraction << " x the scene's diagonal into its own face (tools/vertex_probes)\n";
    size_t probes = 0, moved = 0, fallbacks = 0;
    char line[256];
    for (size_t m = 0; m < scene->meshes.size(); ++m) {
        const Mesh& mesh = scene->meshes[m];
        const size_t n = mesh.positions.size();
        std::vector<std::vector<uint32_t>> around(n);
        std::vector<DVec3> normals(mesh.triangles.size(), DVec3(0.0));
        std::vector<double> areas(mesh.triangles.size(), 0.0);
        for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
            const UVec3& tri = mesh.triangles[t];
            if (tri.x >= n || tri.y >= n || tri.z >= n) continue;
            const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
            const DVec3 cross = glm::cross(b - a, c - a);
            const double length = glm::length(cross);
            if (!(length > 0.0) || !std::isfinite(length)) continue;
            normals[t] = cross / length;
            areas[t] = 0.5 * length;
            for (uint32_t index : {tri.x, tri.y, tri.z}) around[index].push_back(t);
        }
        for (uint32_t v = 0; v < n; ++v) {
            if (around[v].empty()) continue;
            const DVec3 p(mesh.positions[v]);
            std::vector<Group> groups;
            for (uint32_t t : around[v]) {
                Group* group = nullptr;
                for (Group& g : groups)
                    if (glm::dot(g.first_normal, normals[t]) >= coplanar_cos) group = &g;
                if (!group) {
                    groups.push_back({});
                    group = &groups.back();
                    group->first_normal = normals[t];
                }
                const UVec3& tri = mesh.triangles[t];
                const DVec3 centroid =
                    (DVec3(mesh.positions[tri.x]) + DVec3(mesh.positions[tri.y]) + DVec3(mesh.positions[tri.z])) / 3.0;
                const DVec3 to = centroid - p;
                const double length = glm::length(to);
                if (length > 0.0) group->direction += to / length;
                group->normal_sum += normals[t] * areas[t];
                group->triangles.push_back(t);
            }
            for (const Group& g : groups) {
                const DVec3 normal = glm::normalize(g.normal_sum);
                DVec3 d = g.direction - normal * glm::dot(g.direction, normal);
                DVec3 q = p;
                // A fan that closes around the vertex sums to about zero: the vertex is inside
                // its face already. 0.1 of one unit direction is far from either case.
                if (glm::length(d) > 0.1 && nudge > 0.0) {
                    q = p + glm::normalize(d) * nudge;
                    bool inside = false;
                    for (uint32_t t : g.triangles) {
                        const UVec3& tri = mesh.triangles[t];
                        inside = inside || insideTriangle(q, DVec3(mesh.positions[tri.x]), DVec3(mesh.positions[tri.y]),
                                                          DVec3(mesh.positions[tri.z]), normals[t]);
                    }
                    if (!inside) {
                        const UVec3& tri = mesh.triangles[g.triangles.front()];
                        const DVec3 centroid = (DVec3(mesh.positions[tri.x]) + DVec3(mesh.positions[tri.y]) +
                                                DVec3(mesh.positions[tri.z])) / 3.0;
                        const DVec3 to = centroid - p;
                        q = p + to * std::min(0.5, nudge / glm::length(to));
                        ++fallbacks;
                    }
                    ++moved;
                }
                const DVec3 f = q * to_file;
                std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g %.9g %.9g # mesh %zu vertex %u\n", f.x, f.y, f.z,
                              normal.x, normal.y, normal.z, m, v);
                out << line;
                ++probes;
            }
        }
    }
    std::ofstream file(out_path + ".tmp", std::ios::binary);
    file << out.str();
    file.close();
    if (!file || std::rename((out_path + ".tmp").c_str(), out_path.c_str()) != 0) {
        std::fprintf(stderr, "vertex_probes: error: cannot write %s\n", out_path.c_str());
        return 1;
    }
    std::fprintf(stderr,
                 "vertex_probes: %zu probes (%zu nudged by %.3g, %zu of them towards a centroid), %zu meshes, "
                 "scene diagonal %.6g\n",
                 probes, moved, nudge, fallbacks, scene->meshes.size(), extent);
    return 0;
}
