#include "scene/two_sided.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <utility>

#include "scene/weld.h"

namespace radbake {
namespace {

Mesh backTwinOf(const Mesh& front) {
    Mesh back = front;
    back.name = front.name + kBackSuffix;
    for (Vec3& n : back.normals) n = -n;
    // Reversed winding: (a, c, b) keeps corner 0, so barycentrics (u, v) of the front are
    // (v, u) on the back.
    for (UVec3& t : back.triangles) std::swap(t.y, t.z);
    back.convex_solid = false;  // its inside is seen
    back.back = true;
    return back;
}

// --- closed meshes ------------------------------------------------------------------------
//
// A closed, consistently oriented mesh whose fronts all face out bounds a volume that only its
// own backs face: light reaches those backs only from inside that volume (the surface is
// opaque; nothing passes through it). So when nothing inside emits, every back is dark (H = 0
// exactly) and the mesh needs no back twin.

struct Triangle3 {
    DVec3 a, b, c;
};

struct Box3 {
    DVec3 lo{std::numeric_limits<double>::max()}, hi{-std::numeric_limits<double>::max()};
    void add(const DVec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    bool contains(const DVec3& p, double tol) const {
        return p.x >= lo.x - tol && p.y >= lo.y - tol && p.z >= lo.z - tol && p.x <= hi.x + tol && p.y <= hi.y + tol &&
               p.z <= hi.z + tol;
    }
    bool overlaps(const Box3& o, double tol) const {
        return lo.x <= o.hi.x + tol && lo.y <= o.hi.y + tol && lo.z <= o.hi.z + tol && o.lo.x <= hi.x + tol &&
               o.lo.y <= hi.y + tol && o.lo.z <= hi.z + tol;
    }
};

// The closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
DVec3 closestPointOnTriangle(const DVec3& p, const Triangle3& t) {
    const DVec3 ab = t.b - t.a, ac = t.c - t.a, ap = p - t.a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return t.a;
    const DVec3 bp = p - t.b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return t.b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return t.a + ab * (d1 / (d1 - d3));
    const DVec3 cp = p - t.c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return t.c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return t.a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) return t.b + (t.c - t.b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denom = va + vb + vc;
    if (!(std::abs(denom) > 0.0)) return t.a;  // degenerate: its corner is as good as any point
    return t.a + ab * (vb / denom) + ac * (vc / denom);
}

// True if segment pq meets triangle t or passes within `tol` of it (conservative: a segment
// lying in the triangle's plane near it counts as meeting it).
bool segmentTouchesTriangle(const DVec3& p, const DVec3& q, const Triangle3& t, double tol) {
    const DVec3 n = glm::cross(t.b - t.a, t.c - t.a);
    const double len = glm::length(n);
    if (!(len > 0.0)) return false;  // a sliver: its neighbours close the surface
    const DVec3 u = n / len;
    const double dp = glm::dot(p - t.a, u), dq = glm::dot(q - t.a, u);
    if ((dp > tol && dq > tol) || (dp < -tol && dq < -tol)) return false;
    // The point of pq nearest the plane (its crossing, or an end when both lie near it), and
    // for a segment along the plane both ends: near the triangle means touching it.
    if (std::abs(dp - dq) <= tol) {
        const double d = std::min(glm::length(closestPointOnTriangle(p, t) - p), glm::length(closestPointOnTriangle(q, t) - q));
        if (d <= tol) return true;
        // In the plane but beyond both ends: the segment may still cross the triangle.
        const DVec3 m = (p + q) * 0.5;
        return glm::length(closestPointOnTriangle(m, t) - m) <= tol + 0.5 * glm::length(q - p);
    }
    const DVec3 x = p + (q - p) * std::clamp(dp / (dp - dq), 0.0, 1.0);
    return glm::length(closestPointOnTriangle(x, t) - x) <= tol;
}

// The solid angle triangle t subtends at p over 4 pi, signed by its orientation (Van Oosterom
// and Strackee): summed over a closed surface, the winding number of p (1 inside an
// outward-oriented surface, 0 outside).
double windingOf(const DVec3& p, const Triangle3& t) {
    const DVec3 a = t.a - p, b = t.b - p, c = t.c - p;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double det = glm::dot(a, glm::cross(b, c));
    const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
    return std::atan2(det, den) / (2.0 * kPi);
}

struct ClosedMesh {
    std::vector<Triangle3> triangles;
    std::vector<std::pair<DVec3, DVec3>> edges;  // each undirected edge once
    Box3 box;
    double tol = 0.0;

    // Inside the volume, or on (within tol of) its surface.
    bool reaches(const DVec3& p) const {
        if (!box.contains(p, tol)) return false;
        double winding = 0.0;
        for (const Triangle3& t : triangles) {
            if (glm::length(closestPointOnTriangle(p, t) - p) <= tol) return true;
            winding += windingOf(p, t);
        }
        return std::abs(winding) > 0.5;  // 1 inside, 0 outside; rounding is far below 0.5
    }

    // Triangle e lies partly inside the volume or meets its surface.
    bool reaches(const Triangle3& e) const {
        Box3 e_box;
        e_box.add(e.a), e_box.add(e.b), e_box.add(e.c);
        if (!box.overlaps(e_box, tol)) return false;
        if (reaches(e.a) || reaches(e.b) || reaches(e.c) || reaches((e.a + e.b + e.c) / 3.0)) return true;
        // Every corner outside: e is wholly outside unless it crosses the surface.
        for (const Triangle3& t : triangles)
            if (segmentTouchesTriangle(e.a, e.b, t, tol) || segmentTouchesTriangle(e.b, e.c, t, tol) ||
                segmentTouchesTriangle(e.c, e.a, t, tol))
                return true;
        for (const auto& [p, q] : edges)
            if (segmentTouchesTriangle(p, q, e, tol)) return true;
        return false;
    }
};

// The mesh as a closed surface whose fronts face out, or nothing: after welding vertices by
// position, every directed edge must appear once and its reverse once (closed, edge-manifold,
// consistently oriented), and every edge-connected piece must enclose a positive volume (its
// fronts face out; an inside-out piece, or a flat one, is refused). A surface that crosses
// itself with a piece turned inside out could pass; readers do not make those.
std::optional<ClosedMesh> closedOutward(const Mesh& mesh) {
    if (mesh.triangles.size() < 4) return std::nullopt;
    const WeldedPositions welded = weldPositions(mesh);
    const std::vector<DVec3>& points = welded.points;
    const std::vector<uint32_t>& id = welded.id;
    std::vector<UVec3> tris;
    for (const UVec3& t : mesh.triangles) {
        if (t.x >= id.size() || t.y >= id.size() || t.z >= id.size()) return std::nullopt;
        const UVec3 w(id[t.x], id[t.y], id[t.z]);
        if (w.x == w.y || w.y == w.z || w.x == w.z) continue;  // no area, no edges of its own
        tris.push_back(w);
    }
    const auto edge_key = [](uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; };
    std::unordered_map<uint64_t, uint32_t> owner;  // directed edge -> triangle
    owner.reserve(tris.size() * 3);
    for (uint32_t t = 0; t < tris.size(); ++t)
        for (int e = 0; e < 3; ++e)
            if (!owner.emplace(edge_key(tris[t][e], tris[t][(e + 1) % 3]), t).second) return std::nullopt;
    // Pieces: triangles joined across edges (union-find).
    std::vector<uint32_t> parent(tris.size());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto find = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    ClosedMesh closed;
    for (uint32_t t = 0; t < tris.size(); ++t)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = tris[t][e], b = tris[t][(e + 1) % 3];
            const auto it = owner.find(edge_key(b, a));
            if (it == owner.end()) return std::nullopt;  // an open edge
            parent[find(t)] = find(it->second);
            if (a < b) closed.edges.emplace_back(points[a], points[b]);
        }
    std::unordered_map<uint32_t, double> volume6;  // per piece, about its first corner's frame
    std::unordered_map<uint32_t, DVec3> origin;
    for (uint32_t t = 0; t < tris.size(); ++t) {
        const uint32_t piece = find(t);
        const DVec3 o = origin.emplace(piece, points[tris[t].x]).first->second;
        const DVec3 a = points[tris[t].x] - o, b = points[tris[t].y] - o, c = points[tris[t].z] - o;
        volume6[piece] += glm::dot(a, glm::cross(b, c));
        closed.triangles.push_back({points[tris[t].x], points[tris[t].y], points[tris[t].z]});
        closed.box.add(points[tris[t].x]), closed.box.add(points[tris[t].y]), closed.box.add(points[tris[t].z]);
    }
    const double extent = glm::length(closed.box.hi - closed.box.lo);
    if (!(extent > 0.0)) return std::nullopt;
    // A piece thinner than rounding is flat, not a volume.
    for (const auto& [piece, v6] : volume6)
        if (!(v6 > 1e-9 * extent * extent * extent)) return std::nullopt;
    // Float positions: a few ulps of the largest coordinate, and a millionth of the extent.
    const double max_abs = std::max(glm::compMax(glm::abs(closed.box.lo)), glm::compMax(glm::abs(closed.box.hi)));
    closed.tol = 1e-6 * extent + 8.0 * double(std::numeric_limits<float>::epsilon()) * max_abs;
    return closed;
}

bool emits(const Scene& scene, const Mesh& mesh) {
    for (uint32_t p = 0; p < mesh.polygon_count; ++p) {
        const Vec3 e = polygonEmission(scene, mesh, p);
        if (e.x > 0.0f || e.y > 0.0f || e.z > 0.0f) return true;
    }
    return false;
}

}  // namespace

size_t settleClosedTwoSided(Scene& scene) {
    // What can light a volume from inside: punctual lights other than directional ones (those
    // come from infinitely far, outside every volume), and emitting triangles.
    std::vector<DVec3> lights;
    for (const Light& light : scene.lights)
        if (light.type != LightType::Directional) lights.push_back(DVec3(light.position));
    std::vector<Triangle3> emitters;
    for (const Mesh& mesh : scene.meshes) {
        if (mesh.back) continue;  // its front is the same triangles
        const bool has_polygons = mesh.triangle_polygon.size() == mesh.triangles.size();
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const UVec3& tri = mesh.triangles[t];
            if (tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() || tri.z >= mesh.positions.size()) continue;
            const Vec3 e = polygonEmission(scene, mesh, has_polygons ? mesh.triangle_polygon[t] : uint32_t(t));
            if (e.x > 0.0f || e.y > 0.0f || e.z > 0.0f)
                emitters.push_back({DVec3(mesh.positions[tri.x]), DVec3(mesh.positions[tri.y]), DVec3(mesh.positions[tri.z])});
        }
    }
    size_t settled = 0;
    for (Mesh& mesh : scene.meshes) {
        if (mesh.solid || mesh.back || mesh.twin != kNoMesh) continue;
        // A two-sided emitter emits from its backs into its own volume too: lit inside (the
        // outward two-sided furnace is H = 2 pi in there). It keeps its twin.
        if (emits(scene, mesh)) continue;
        const std::optional<ClosedMesh> closed = closedOutward(mesh);
        if (!closed) continue;
        bool lit = std::any_of(lights.begin(), lights.end(), [&](const DVec3& p) { return closed->reaches(p); });
        for (size_t e = 0; e < emitters.size() && !lit; ++e) lit = closed->reaches(emitters[e]);
        if (lit) continue;
        mesh.solid = true;  // its backs are dark: baked one-sided, exactly
        mesh.closed_two_sided = true;
        ++settled;
    }
    return settled;
}

size_t addBackTwins(Scene& scene) {
    settleClosedTwoSided(scene);
    const size_t original = scene.meshes.size();
    size_t added = 0;
    for (size_t m = 0; m < original; ++m) {
        if (scene.meshes[m].solid || scene.meshes[m].twin != kNoMesh || scene.meshes[m].back) continue;
        if (scene.meshes[m].triangles.empty()) continue;
        Mesh back = backTwinOf(scene.meshes[m]);
        back.twin = static_cast<uint32_t>(m);
        scene.meshes[m].twin = static_cast<uint32_t>(scene.meshes.size());
        scene.meshes[m].convex_solid = false;  // a surface seen from inside is no occluding volume
        scene.meshes.push_back(std::move(back));
        ++added;
    }
    return added;
}

}  // namespace radbake
