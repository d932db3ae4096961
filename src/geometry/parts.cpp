#include "geometry/parts.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <exception>
#include <unordered_map>
#include <unordered_set>

#include "geometry/box.h"
#include "geometry/hull.h"
#include "geometry/polygon.h"
#include "scene/weld.h"

namespace radbake {

namespace {

// Tolerance for a set of points: a fraction of their extent plus the rounding bound of float
// positions (half an ulp per coordinate, a few ulps after differencing), so that planar
// faces far from the origin still test as planar.
double toleranceFor(std::span<const DVec3> points, double relative) {
    double max_abs = 0.0;
    for (const DVec3& p : points) max_abs = std::max({max_abs, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    return relative * pointExtent(points) + 8.0 * FLT_EPSILON * max_abs;
}

uint64_t edgeKey(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; }

// Vertices welded by position (scene/weld.h): adjacency is about positions.
using Welded = WeldedPositions;

// Welded triangles of the mesh with their polygon, without topologically degenerate ones.
struct WTri {
    uint32_t v[3];
    uint32_t polygon;
};

std::vector<WTri> weldedTriangles(const Mesh& mesh, const Welded& w) {
    std::vector<WTri> tris;
    tris.reserve(mesh.triangles.size());
    const bool has_polygons = mesh.triangle_polygon.size() == mesh.triangles.size();
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const UVec3& tri = mesh.triangles[t];
        if (tri.x >= w.id.size() || tri.y >= w.id.size() || tri.z >= w.id.size()) continue;
        WTri out{{w.id[tri.x], w.id[tri.y], w.id[tri.z]}, has_polygons ? mesh.triangle_polygon[t] : uint32_t(t)};
        if (out.v[0] == out.v[1] || out.v[1] == out.v[2] || out.v[0] == out.v[2]) continue;
        tris.push_back(out);
    }
    return tris;
}

// --- closed convex solids -------------------------------------------------------------

// True if the welded triangles form a closed, consistently oriented, convex surface: every
// directed edge once with its reverse once, every edge locally convex, and the enclosed
// volume equal to the hull's (a closed, locally convex surface with its hull's volume is
// that hull).
// Volume (> 0) and area of the enclosed solid when the surface is closed, consistently
// oriented and locally convex; 0 otherwise. Cheap, so it runs before any hull is built.
struct ClosedSurface {
    double volume = 0.0;
    double area = 0.0;
};

ClosedSurface closedConvexSurface(const std::vector<WTri>& tris, const Welded& w, double tolerance) {
    if (tris.size() < 4) return {};
    std::unordered_map<uint64_t, uint32_t> edge_owner;  // directed edge -> triangle
    edge_owner.reserve(tris.size() * 3);
    for (uint32_t t = 0; t < tris.size(); ++t)
        for (int e = 0; e < 3; ++e)
            if (!edge_owner.emplace(edgeKey(tris[t].v[e], tris[t].v[(e + 1) % 3]), t).second) return {};
    double volume6 = 0.0, area2 = 0.0;
    for (uint32_t t = 0; t < tris.size(); ++t) {
        const DVec3 &a = w.points[tris[t].v[0]], &b = w.points[tris[t].v[1]], &c = w.points[tris[t].v[2]];
        const Plane plane = planeFromPoints(a, b, c);
        volume6 += glm::dot(a, glm::cross(b, c));
        area2 += glm::length(glm::cross(b - a, c - a));
        for (int e = 0; e < 3; ++e) {
            const auto it = edge_owner.find(edgeKey(tris[t].v[(e + 1) % 3], tris[t].v[e]));
            if (it == edge_owner.end()) return {};  // open edge
            if (plane.normal == DVec3(0.0)) continue;  // sliver: no plane to test against
            const WTri& other = tris[it->second];
            for (int k = 0; k < 3; ++k)
                if (plane.eval(w.points[other.v[k]]) > tolerance) return {};  // reflex edge
        }
    }
    if (volume6 <= 0.0) return {};
    return {volume6 / 6.0, area2 / 2.0};
}

// A closed, locally convex surface enclosing its hull's volume is that hull. Moving every
// face by the tolerance changes the volume by about area * tolerance.
bool matchesHull(const ClosedSurface& surface, const Hull3& hull, double tolerance) {
    return surface.volume > 0.0 && hull.dimension == 3 &&
           std::abs(hull.volume - surface.volume) <= 2.0 * surface.area * tolerance;
}

ConvexPart closedPart(const Hull3& hull, const std::vector<DVec3>& points) {
    ConvexPart part;
    part.closed = true;
    part.vertices = hull.vertices;
    part.planes = hull.planes;
    part.faces = hull.faces;
    part.volume = hull.volume;
    for (const std::vector<uint32_t>& face : hull.faces) {
        std::vector<DVec3> loop;
        for (uint32_t i : face) loop.push_back(hull.vertices[i]);
        part.area += polygonArea(loop);
    }
    part.aabb = aabbOf(points);
    part.obb = fitObb(hull, points);
    return part;
}

// --- flat pieces ----------------------------------------------------------------------

struct Piece {
    std::vector<uint32_t> loop;  // welded indices, counter-clockwise around the normal
    std::vector<uint32_t> polygons;
    Plane plane;
};

class FlatBuilder {
public:
    FlatBuilder(const Welded& w, const PartOptions& options) : w_(w), options_(options) {}

    // Adds the pieces of one source polygon; false if it is degenerate.
    bool addPolygon(uint32_t polygon, const std::vector<WTri>& tris);
    // Greedy merging across shared edges while the union stays planar and convex. Phase 1
    // joins pieces of the same source polygon (Hertel-Mehlhorn over a non-convex polygon's
    // triangles); phase 2 joins coplanar neighbours of any polygon.
    void merge(bool across_polygons);
    std::vector<Piece> take();

private:
    std::vector<DVec3> positions(const std::vector<uint32_t>& loop) const {
        std::vector<DVec3> out;
        out.reserve(loop.size());
        for (uint32_t i : loop) out.push_back(w_.points[i]);
        return out;
    }
    uint32_t find(uint32_t p) {
        while (parent_[p] != p) p = parent_[p] = parent_[parent_[p]];
        return p;
    }
    bool addPiece(std::vector<uint32_t> loop, uint32_t polygon);
    bool tryMerge(uint32_t a, uint32_t b, bool across_polygons);

    const Welded& w_;
    const PartOptions& options_;
    std::vector<Piece> pieces_;
    std::vector<uint32_t> parent_;
    std::unordered_map<uint64_t, uint32_t> edge_owner_;  // directed edge -> original piece
};

bool FlatBuilder::addPiece(std::vector<uint32_t> loop, uint32_t polygon) {
    const std::vector<DVec3> pts = positions(loop);
    Piece piece;
    piece.plane = planeFromPolygon(pts);
    const double tolerance = toleranceFor(pts, options_.relative_tolerance);
    // Degenerate when its area is no more than a tolerance-wide strip along its perimeter.
    double perimeter = 0.0;
    for (size_t i = 0; i < pts.size(); ++i) perimeter += glm::length(pts[(i + 1) % pts.size()] - pts[i]);
    if (piece.plane.normal == DVec3(0.0) || polygonArea(pts) <= tolerance * perimeter) return false;
    piece.loop = std::move(loop);
    piece.polygons = {polygon};
    const uint32_t id = uint32_t(pieces_.size());
    for (size_t i = 0; i < piece.loop.size(); ++i)
        edge_owner_.emplace(edgeKey(piece.loop[i], piece.loop[(i + 1) % piece.loop.size()]), id);
    pieces_.push_back(std::move(piece));
    parent_.push_back(id);
    return true;
}

bool FlatBuilder::addPolygon(uint32_t polygon, const std::vector<WTri>& tris) {
    if (tris.empty()) return false;
    // Boundary: directed edges whose reverse is not in the polygon.
    std::unordered_set<uint64_t> edges;
    for (const WTri& t : tris)
        for (int e = 0; e < 3; ++e) edges.insert(edgeKey(t.v[e], t.v[(e + 1) % 3]));
    std::unordered_map<uint32_t, uint32_t> next;
    bool simple = true;
    for (uint64_t key : edges) {
        const uint32_t a = uint32_t(key >> 32), b = uint32_t(key);
        if (edges.count(edgeKey(b, a))) continue;
        if (!next.emplace(a, b).second) simple = false;  // two boundary edges leave a
    }
    std::vector<uint32_t> loop;
    if (simple && !next.empty()) {
        const uint32_t first = next.begin()->first;
        uint32_t at = first;
        do {
            loop.push_back(at);
            const auto it = next.find(at);
            if (it == next.end() || loop.size() > next.size()) break;
            at = it->second;
        } while (at != first);
        if (at != first || loop.size() != next.size()) loop.clear();  // holes or pieces
    }
    if (loop.size() >= 3) {
        const std::vector<DVec3> pts = positions(loop);
        const Plane plane = planeFromPolygon(pts);
        const double tolerance = toleranceFor(pts, options_.relative_tolerance);
        bool planar = plane.normal != DVec3(0.0);
        for (const WTri& t : tris)
            for (int k = 0; k < 3 && planar; ++k) planar = std::abs(plane.eval(w_.points[t.v[k]])) <= tolerance;
        if (planar && isConvexPolygon(pts, plane.normal, tolerance)) return addPiece(std::move(loop), polygon);
    }
    // Non-convex, non-planar, holed or fragmented: start from its triangles.
    bool any = false;
    for (const WTri& t : tris) any |= addPiece({t.v[0], t.v[1], t.v[2]}, polygon);
    return any;
}

bool FlatBuilder::tryMerge(uint32_t a, uint32_t b, bool across_polygons) {
    Piece& pa = pieces_[a];
    Piece& pb = pieces_[b];
    if (!across_polygons && (pa.polygons.size() != 1 || pb.polygons != pa.polygons)) return false;
    if (glm::dot(pa.plane.normal, pb.plane.normal) < std::cos(options_.coplanar_angle)) return false;
    // Union loop: every edge of both loops except those shared (u -> v in one, v -> u in the
    // other), which may form a chain (a strip meeting a strip along several edges).
    std::unordered_map<uint64_t, char> edges;
    auto collect = [&](const std::vector<uint32_t>& loop) {
        for (size_t i = 0; i < loop.size(); ++i) {
            const uint32_t u = loop[i], v = loop[(i + 1) % loop.size()];
            if (edges.erase(edgeKey(v, u)) == 0) edges.emplace(edgeKey(u, v), 1);
        }
    };
    collect(pa.loop);
    collect(pb.loop);
    if (edges.size() < 3 || edges.size() >= pa.loop.size() + pb.loop.size()) return false;
    std::unordered_map<uint32_t, uint32_t> next;
    for (const auto& [key, unused] : edges)
        if (!next.emplace(uint32_t(key >> 32), uint32_t(key)).second) return false;  // pinched
    std::vector<uint32_t> joined;
    // Start from pa's first surviving vertex so the result does not depend on hash order.
    uint32_t first = next.begin()->first;
    for (uint32_t i : pa.loop)
        if (next.count(i)) {
            first = i;
            break;
        }
    uint32_t at = first;
    do {
        joined.push_back(at);
        const auto it = next.find(at);
        if (it == next.end() || joined.size() > next.size()) return false;
        at = it->second;
    } while (at != first);
    if (joined.size() != next.size()) return false;  // more than one loop: a hole
    const std::vector<DVec3> pts = positions(joined);
    const Plane plane = planeFromPolygon(pts);
    const double tolerance = toleranceFor(pts, options_.relative_tolerance);
    if (plane.normal == DVec3(0.0)) return false;
    for (const DVec3& p : pts)
        if (std::abs(plane.eval(p)) > tolerance) return false;
    if (!isConvexPolygon(pts, plane.normal, tolerance)) return false;
    pa.loop = std::move(joined);
    pa.plane = plane;
    pa.polygons.insert(pa.polygons.end(), pb.polygons.begin(), pb.polygons.end());
    std::sort(pa.polygons.begin(), pa.polygons.end());
    pa.polygons.erase(std::unique(pa.polygons.begin(), pa.polygons.end()), pa.polygons.end());
    pb.loop.clear();
    pb.polygons.clear();
    parent_[b] = a;
    return true;
}

void FlatBuilder::merge(bool across_polygons) {
    struct Candidate {
        uint32_t a, b;  // original pieces that share an edge
    };
    std::vector<Candidate> queue;
    auto enqueue = [&](uint32_t piece) {
        const std::vector<uint32_t>& loop = pieces_[piece].loop;
        for (size_t i = 0; i < loop.size(); ++i) {
            const uint32_t u = loop[i], v = loop[(i + 1) % loop.size()];
            const auto it = edge_owner_.find(edgeKey(v, u));
            if (it != edge_owner_.end() && find(it->second) != piece) queue.push_back({piece, it->second});
        }
    };
    for (uint32_t p = 0; p < pieces_.size(); ++p)
        if (find(p) == p) enqueue(p);
    // Stack order keeps merges local (a growing piece keeps eating its neighbours), which
    // tends to give fewer, rounder pieces than a breadth-first sweep.
    std::reverse(queue.begin(), queue.end());
    while (!queue.empty()) {
        const Candidate c = queue.back();
        queue.pop_back();
        const uint32_t a = find(c.a), b = find(c.b);
        if (a == b) continue;
        if (tryMerge(a, b, across_polygons)) enqueue(a);
    }
}

std::vector<Piece> FlatBuilder::take() {
    std::vector<Piece> out;
    for (uint32_t p = 0; p < pieces_.size(); ++p)
        if (find(p) == p && !pieces_[p].loop.empty()) out.push_back(std::move(pieces_[p]));
    return out;
}

ConvexPart flatPart(const Piece& piece, const Welded& w, double relative_tolerance) {
    std::vector<DVec3> pts;
    for (uint32_t i : piece.loop) pts.push_back(w.points[i]);
    ConvexPart part;
    part.closed = false;
    // Project onto the supporting plane so the part is exactly the flat polygon its plane
    // and flat box describe; the source deviates from it by at most the tolerance.
    const DVec3 n = piece.plane.normal;
    for (DVec3& p : pts) p -= n * piece.plane.eval(p);
    const double tolerance = toleranceFor(pts, relative_tolerance);
    part.vertices = removeCollinear(pts, tolerance * 1e-3);
    part.inflation = tolerance;
    part.planes = {piece.plane};
    part.area = polygonArea(part.vertices);
    part.aabb = aabbOf(part.vertices);
    part.obb = flatObb(part.vertices, n);
    part.polygons = piece.polygons;
    return part;
}

void addPart(PartSet& set, ConvexPart part, uint32_t mesh) {
    part.mesh = mesh;
    const uint32_t index = uint32_t(set.parts.size());
    for (uint32_t polygon : part.polygons)
        if (polygon < set.polygon_part[mesh].size() && set.polygon_part[mesh][polygon] == kNoPart)
            set.polygon_part[mesh][polygon] = index;
    set.bounds.add(part.aabb);
    set.parts.push_back(std::move(part));
}

void buildMeshParts(const Scene& scene, uint32_t mesh_index, const PartOptions& options, PartSet& set,
                    Diagnostics& diagnostics) {
    const Mesh& mesh = scene.meshes[mesh_index];
    if (mesh.back && mesh.twin < mesh_index) {
        // A back twin is its front's surface: the front's parts stand for it (a coincident
        // copy would only be a potential occluder of every link its own side makes).
        set.part_mesh[mesh_index] = mesh.twin;
        set.polygon_part[mesh_index] = set.polygon_part[mesh.twin];
        return;
    }
    const uint32_t polygon_count = mesh.triangle_polygon.size() == mesh.triangles.size()
                                       ? mesh.polygon_count
                                       : uint32_t(mesh.triangles.size());
    set.polygon_part[mesh_index].assign(polygon_count, kNoPart);
    const Welded w = weldPositions(mesh);
    const std::vector<WTri> tris = weldedTriangles(mesh, w);
    if (tris.empty()) {
        set.stats.degenerate_polygons += polygon_count;
        return;
    }

    // A two-sided surface is seen from inside too: never a solid, whatever its shape.
    const bool two_sided = mesh.twin != kNoMesh;
    if (!two_sided && (mesh.convex_solid || options.detect_convex_solids)) {
        // Only the vertices the triangles use: readers may leave unused ones behind.
        std::vector<char> used(w.points.size(), 0);
        for (const WTri& t : tris) used[t.v[0]] = used[t.v[1]] = used[t.v[2]] = 1;
        std::vector<DVec3> points;
        for (size_t i = 0; i < w.points.size(); ++i)
            if (used[i]) points.push_back(w.points[i]);
        const double tolerance = toleranceFor(points, options.relative_tolerance);
        const double solid_tolerance = toleranceFor(points, options.solid_relative_tolerance);
        // A flagged solid is trusted if it has volume; otherwise the mesh must prove it.
        ClosedSurface surface;
        if (!mesh.convex_solid) surface = closedConvexSurface(tris, w, solid_tolerance);
        Hull3 hull;
        if (mesh.convex_solid || surface.volume > 0.0) hull = quickhull(points, tolerance);
        const bool solid = mesh.convex_solid ? hull.dimension == 3 && hull.volume > 0.0
                                             : matchesHull(surface, hull, solid_tolerance);
        if (solid) {
            ConvexPart part = closedPart(hull, points);
            // A detected solid may be dented by up to solid_tolerance inside its hull.
            part.inflation = mesh.convex_solid ? tolerance : solid_tolerance;
            for (uint32_t p = 0; p < polygon_count; ++p) part.polygons.push_back(p);
            addPart(set, std::move(part), mesh_index);
            ++set.stats.closed_meshes;
            return;
        }
        if (mesh.convex_solid) {
            ++set.stats.degenerate_solids;
            diagnostics.warning(mesh.location, "convex solid '" + mesh.name +
                                                   "' has no volume; using its polygons as flat parts");
        }
    }

    // Open surface (or a non-convex / degenerate closed one): flat convex pieces.
    std::vector<std::vector<WTri>> by_polygon(polygon_count);
    for (const WTri& t : tris)
        if (t.polygon < polygon_count) by_polygon[t.polygon].push_back(t);
    FlatBuilder builder(w, options);
    for (uint32_t p = 0; p < polygon_count; ++p)
        if (!builder.addPolygon(p, by_polygon[p])) ++set.stats.degenerate_polygons;
    builder.merge(false);
    if (options.merge_coplanar) builder.merge(true);
    for (const Piece& piece : builder.take()) addPart(set, flatPart(piece, w, options.relative_tolerance), mesh_index);
}

void computeStats(PartSet& set) {
    PartStats& s = set.stats;
    s.parts = set.parts.size();
    double volume_sum = 0.0, area_sum = 0.0;
    for (const ConvexPart& part : set.parts) {
        const double ratio = obbTightness(part);
        if (part.closed) {
            ++s.closed_parts;
            volume_sum += ratio;
            s.max_obb_volume_ratio = std::max(s.max_obb_volume_ratio, ratio);
        } else {
            ++s.flat_parts;
            area_sum += ratio;
            s.max_obb_area_ratio = std::max(s.max_obb_area_ratio, ratio);
        }
    }
    if (s.closed_parts) s.mean_obb_volume_ratio = volume_sum / double(s.closed_parts);
    if (s.flat_parts) s.mean_obb_area_ratio = area_sum / double(s.flat_parts);
}

}  // namespace

double obbTightness(const ConvexPart& part) {
    if (part.closed) return part.volume > 0.0 ? obbVolume(part.obb) / part.volume : 0.0;
    return part.area > 0.0 ? 4.0 * part.obb.half_extents.x * part.obb.half_extents.y / part.area : 0.0;
}

void fitPartBoxes(ConvexPart& part) {
    part.aabb = aabbOf(part.vertices);
    if (part.closed) {
        part.obb = fitObb(part.vertices);
    } else {
        const DVec3 n = part.planes.empty() ? planeFromPolygon(part.vertices).normal : part.planes[0].normal;
        part.obb = flatObb(part.vertices, n);
    }
}

ConvexPart partFromPoints(const std::vector<DVec3>& points, double relative_tolerance) {
    const double tolerance = toleranceFor(points, relative_tolerance);
    const Hull3 hull = quickhull(points, tolerance);
    if (hull.dimension == 3) return closedPart(hull, points);
    ConvexPart part;
    if (hull.dimension != 2 || hull.vertices.size() < 3) return part;
    Plane plane = planeFromPolygon(hull.vertices);
    part.vertices = hull.vertices;
    for (DVec3& p : part.vertices) p -= plane.normal * plane.eval(p);
    part.planes = {plane};
    part.area = polygonArea(part.vertices);
    part.aabb = aabbOf(part.vertices);
    part.obb = flatObb(part.vertices, plane.normal);
    return part;
}

PartSet buildParts(const Scene& scene, const PartOptions& options, Diagnostics& diagnostics) {
    PartSet set;
    set.polygon_part.resize(scene.meshes.size());
    set.part_mesh.resize(scene.meshes.size());
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) set.part_mesh[m] = m;
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        try {
            buildMeshParts(scene, m, options, set, diagnostics);
        } catch (const std::exception& e) {
            // Out of memory or a library failure: report the mesh and carry on with the rest.
            diagnostics.error(scene.meshes[m].location,
                              "could not build convex parts of mesh '" + scene.meshes[m].name + "': " + e.what());
        }
    }
    for (ConvexPart& part : set.parts)
        part.transmits = part.mesh < scene.meshes.size() && meshTransmittance(scene, scene.meshes[part.mesh]) > 0.0f;
    computeStats(set);
    set.tree = buildPartTree(set.parts);
    return set;
}

}  // namespace radbake
