#include "radiosity/elements.h"

#include <algorithm>
#include <map>
#include <unordered_map>

#include "geometry/polygon.h"
#include "radiosity/contact_cuts.h"

namespace radbake {
namespace {

// A light source's plane cuts the polygons near it when its mesh sends at least this share of
// the scene's emitted power (contact_cuts.h, cutAtSourcePlanes).
constexpr double kSourcePlaneShare = 0.05;

// Roots with more corners than this are split into their triangles instead (keeps the
// fixed-size buffers of the form-factor code small).
constexpr size_t kMaxRootVertices = 32;

// Roots are cut where another polygon touches or crosses them within this fraction of the
// scene's extent (contact_cuts.h): the gather's lift off touching surfaces (gather.h kLift),
// above float rounding of coordinates.
constexpr double kContactTolerance = 1e-5;

// Boundary loop of a polygon given as triangles [t0, t1): the directed edges whose reverse
// is absent, chained. Empty when they do not form exactly one loop.
std::vector<uint32_t> boundaryLoop(const Mesh& mesh, size_t t0, size_t t1) {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t t = t0; t < t1; ++t) {
        const UVec3& tri = mesh.triangles[t];
        const uint32_t v[3] = {tri.x, tri.y, tri.z};
        for (int k = 0; k < 3; ++k) edges[{v[k], v[(k + 1) % 3]}] += 1;
    }
    std::unordered_map<uint32_t, uint32_t> next;
    size_t boundary = 0;
    for (const auto& [edge, count] : edges) {
        if (edges.count({edge.second, edge.first})) continue;
        if (count != 1 || next.count(edge.first)) return {};
        next[edge.first] = edge.second;
        ++boundary;
    }
    if (boundary < 3) return {};
    std::vector<uint32_t> loop;
    uint32_t start = next.begin()->first;
    // Start from the smallest index so the loop does not depend on hash order.
    for (const auto& [from, to] : next) start = std::min(start, from);
    uint32_t v = start;
    do {
        loop.push_back(v);
        auto it = next.find(v);
        if (it == next.end() || loop.size() > boundary) return {};
        v = it->second;
    } while (v != start);
    if (loop.size() != boundary) return {};
    return loop;
}

bool childrenConvex(std::span<const DVec3> loop, double tolerance) {
    for (const auto& child : splitPolygon(loop)) {
        const DVec3 n = newellNormal(child);
        const double len = glm::length(n);
        if (!(len > 0.0) || !isConvexPolygon(child, n / len, tolerance)) return false;
    }
    return true;
}

void addRoot(Solution& solution, const Scene& scene, uint32_t mesh_index, uint32_t polygon,
             std::span<const DVec3> loop) {
    const Mesh& mesh = scene.meshes[mesh_index];
    Element element;
    element.first_vertex = static_cast<uint32_t>(solution.vertices.size());
    element.vertex_count = static_cast<uint32_t>(loop.size());
    solution.vertices.insert(solution.vertices.end(), loop.begin(), loop.end());
    setElementGeometry(element, loop);
    element.mesh = mesh_index;
    element.polygon = polygon;
    element.root = static_cast<uint32_t>(solution.elements.size());
    // Per polygon: a texture may give each polygon its own (scene.h).
    // A transmitting surface lets its share through; the rest meets it as an opaque surface.
    element.reflectance = DVec3(polygonReflectance(scene, mesh, polygon)) * (1.0 - meshTransmittance(scene, mesh));
    element.emission = kPi * DVec3(polygonEmission(scene, mesh, polygon));
    solution.elements.push_back(element);
}

}  // namespace

void setElementGeometry(Element& element, std::span<const DVec3> loop) {
    const DVec3 n = newellNormal(loop);
    const double len = glm::length(n);
    element.normal = len > 0.0 ? n / len : DVec3(0.0, 0.0, 1.0);
    element.area = 0.5 * len;
    element.centroid = polygonCentroid(loop);
    element.radius = 0.0;
    for (const DVec3& p : loop) element.radius = std::max(element.radius, glm::length(p - element.centroid));
}

std::vector<std::vector<DVec3>> splitPolygon(std::span<const DVec3> loop) {
    const size_t n = loop.size();
    std::vector<std::vector<DVec3>> children;
    if (n == 4) {
        const double len02 = glm::length(loop[1] - loop[0]) + glm::length(loop[3] - loop[2]);
        const double len13 = glm::length(loop[2] - loop[1]) + glm::length(loop[0] - loop[3]);
        if (len02 > 2.0 * len13 || len13 > 2.0 * len02) {
            // Binary split across the long direction: halve the two long edges.
            const int a = len02 > len13 ? 0 : 1;  // first long edge: a -> a+1, second: a+2 -> a+3
            const DVec3& p0 = loop[a];
            const DVec3& p1 = loop[(a + 1) % 4];
            const DVec3& p2 = loop[(a + 2) % 4];
            const DVec3& p3 = loop[(a + 3) % 4];
            const DVec3 m01 = 0.5 * (p0 + p1), m23 = 0.5 * (p2 + p3);
            children.push_back({p0, m01, m23, p3});
            children.push_back({m01, p1, p2, m23});
            return children;
        }
    }
    const DVec3 centre = n == 4 ? 0.25 * (loop[0] + loop[1] + loop[2] + loop[3]) : polygonCentroid(loop);
    for (size_t i = 0; i < n; ++i) {
        const DVec3& v = loop[i];
        const DVec3 next_mid = 0.5 * (v + loop[(i + 1) % n]);
        const DVec3 prev_mid = 0.5 * (v + loop[(i + n - 1) % n]);
        children.push_back({v, next_mid, centre, prev_mid});
    }
    return children;
}

uint32_t ensureChildren(Solution& solution, uint32_t index) {
    if (solution.elements[index].child_count > 0) return solution.elements[index].child_count;
    const Element parent = solution.elements[index];
    const std::vector<DVec3> loop(solution.vertices.begin() + parent.first_vertex,
                                  solution.vertices.begin() + parent.first_vertex + parent.vertex_count);
    const auto children = splitPolygon(loop);
    const uint32_t first = static_cast<uint32_t>(solution.elements.size());
    for (const auto& child_loop : children) {
        Element child = parent;
        child.first_vertex = static_cast<uint32_t>(solution.vertices.size());
        child.vertex_count = static_cast<uint32_t>(child_loop.size());
        solution.vertices.insert(solution.vertices.end(), child_loop.begin(), child_loop.end());
        setElementGeometry(child, child_loop);
        child.normal = parent.normal;  // exactly the parent's plane, whatever the rounding
        child.parent = index;
        child.first_child = kNoElement;
        child.child_count = 0;
        child.depth = parent.depth + 1;
        child.radiosity = parent.radiosity;
        child.gathered = DVec3(0.0);
        solution.elements.push_back(child);
    }
    solution.elements[index].first_child = first;
    solution.elements[index].child_count = static_cast<uint32_t>(children.size());
    return static_cast<uint32_t>(children.size());
}

void buildRootElements(const Scene& scene, Solution& solution) {
    const SceneSummary summary = summarize(scene);
    solution.scene_extent = glm::length(DVec3(summary.bounds_max) - DVec3(summary.bounds_min));
    if (!(solution.scene_extent > 0.0)) solution.scene_extent = 1.0;
    // Polygons smaller than this are dust: (1e-7 of the scene's extent)^2, far below float
    // resolution of positions relative to the scene.
    const double min_area = 1e-14 * solution.scene_extent * solution.scene_extent;
    std::vector<RootPolygon> roots;
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        size_t t0 = 0;
        while (t0 < mesh.triangles.size()) {
            const uint32_t polygon = mesh.triangle_polygon.empty() ? static_cast<uint32_t>(t0)
                                                                   : mesh.triangle_polygon[t0];
            size_t t1 = t0 + 1;
            while (t1 < mesh.triangles.size() && !mesh.triangle_polygon.empty() &&
                   mesh.triangle_polygon[t1] == polygon)
                ++t1;
            double triangle_area = 0.0;
            for (size_t t = t0; t < t1; ++t) triangle_area += triangleArea(mesh, t);
            bool as_one = false;
            std::vector<DVec3> loop;
            if (triangle_area > min_area) {
                for (uint32_t v : boundaryLoop(mesh, t0, t1)) loop.emplace_back(mesh.positions[v]);
                const double extent = pointExtent(loop);
                // Planarity/convexity tolerance: 1e-5 of the polygon's size, above float
                // rounding of its coordinates (~1e-7 relative) and below anything visible.
                const double tolerance = 1e-5 * extent;
                if (loop.size() >= 3) loop = removeCollinear(loop, tolerance);
                if (loop.size() >= 3 && loop.size() <= kMaxRootVertices) {
                    const Plane plane = planeFromPolygon(loop);
                    bool planar = glm::length(plane.normal) > 0.5;
                    for (const DVec3& p : loop) planar = planar && std::abs(plane.eval(p)) <= tolerance;
                    as_one = planar && isConvexPolygon(loop, plane.normal, tolerance) &&
                             std::abs(polygonArea(loop) - triangle_area) <= 1e-6 * triangle_area &&
                             (loop.size() <= 4 || childrenConvex(loop, tolerance));
                }
            }
            if (as_one) {
                roots.push_back({m, polygon, std::move(loop)});
            } else {
                for (size_t t = t0; t < t1; ++t) {
                    if (!(triangleArea(mesh, t) > min_area)) continue;
                    const UVec3& tri = mesh.triangles[t];
                    roots.push_back({m, polygon, {DVec3(mesh.positions[tri.x]), DVec3(mesh.positions[tri.y]),
                                                  DVec3(mesh.positions[tri.z])}});
                }
            }
            t0 = t1;
        }
    }
    solution.stats.contact_cuts = cutAtContacts(roots, kContactTolerance * solution.scene_extent, kMaxRootVertices);
    // Sources whose plane cuts: one-sided (a two-sided source, its twin emitting too, lights both
    // sides of its plane) and bright, a mesh sending at least kSourcePlaneShare of the scene's
    // emitted power (office.wrl's many small emitting parts cut 28k polygons otherwise).
    std::vector<double> mesh_power(scene.meshes.size(), 0.0);
    std::vector<bool> emits(roots.size()), reflects(roots.size());
    double total_power = 0.0;
    for (size_t i = 0; i < roots.size(); ++i) {
        const Mesh& mesh = scene.meshes[roots[i].mesh];
        const Vec3 e = polygonEmission(scene, mesh, roots[i].polygon);
        const Vec3 rho = polygonReflectance(scene, mesh, roots[i].polygon);
        reflects[i] = std::max({rho.x, rho.y, rho.z}) > 0.0f;
        const double power = polygonArea(roots[i].loop) * std::max({e.x, e.y, e.z});
        mesh_power[roots[i].mesh] += power;
        total_power += power;
        emits[i] = power > 0.0 && mesh.twin == kNoMesh;
    }
    // The outline cuts whatever the source's power: they are few (only what lies right behind a
    // source), and a dim room's lamp must cut the same beside a bright room as alone; and only
    // what reflects (a black ceiling is dark either way, and a dim lamp in a black room must not
    // change the rest's hierarchy).
    const std::vector<bool> outlines = emits;
    for (size_t i = 0; i < roots.size(); ++i)
        emits[i] = emits[i] && mesh_power[roots[i].mesh] >= kSourcePlaneShare * total_power;
    solution.stats.contact_cuts +=
        cutAtSourcePlanes(roots, emits, outlines, reflects, kContactTolerance * solution.scene_extent, kMaxRootVertices);
    for (const RootPolygon& root : roots) addRoot(solution, scene, root.mesh, root.polygon, root.loop);
    solution.root_count = static_cast<uint32_t>(solution.elements.size());
    solution.total_area = 0.0;
    for (const Element& e : solution.elements) solution.total_area += e.area;
}

}  // namespace radbake
