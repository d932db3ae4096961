#include "scene/two_sided.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "scene/coplanar.h"
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

// --- backs in contact ------------------------------------------------------------------
//
// A back twin's triangle T (unit normal m) lies in a zero-width gap where another surface S
// touches it from in front: coplanar within kContactRelative of the scene's extent, parallel or
// antiparallel, overlapping, and S's plane at most that far in front of T along m. Nothing
// reaches T there (the gap is closed) and T sends nothing out of it, so the area is dark
// exactly, in the limit of zero distance. Left in, T and the surface it faces would exchange
// nearly all their light across the gap (a form factor near 1 at zero distance): a furnace of
// two surfaces, which the refinement splits to the minimum area and the solve iterates like
// rho ~ 1. Exactly coincident S (within float rounding) is a duplicate when it faces the same
// way as T (a front there already faces that way: T is redundant; of two coincident twins the
// later one is), and the other side of a zero-thickness sheet when it faces the other way (they
// exchange nothing: not a gap).
constexpr double kContactRelative = coplanar::kRelativeTolerance;   // as the overlap warnings'
constexpr double kParallelTolerance = coplanar::kNormalTolerance;  // unit normals' components

// A polygon covered over at most this fraction is left as it is (a sliver along a contact
// line); one covered over at least kCoveredWhole is dark all over.
constexpr double kCoveredNegligible = 0.01;
constexpr double kCoveredWhole = 0.99;

struct PlaneTriangle {
    std::array<DVec3, 3> p;
    DVec3 normal{0.0};  // unit, of the front's winding
    double area = 0.0;
    uint32_t mesh = 0, triangle = 0;
};

// The area of the intersection of two (nearly) coplanar triangles, in a's plane.
double overlapArea(const PlaneTriangle& a, const PlaneTriangle& b) { return coplanar::overlapArea(a.p, a.normal, b.p); }

}  // namespace

std::vector<std::vector<double>> backContactCoverage(const Scene& scene) {
    std::vector<std::vector<double>> covered(scene.meshes.size());
    DVec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    double max_abs = 0.0;
    for (const Mesh& mesh : scene.meshes)
        for (const Vec3& p : mesh.positions) {
            lo = glm::min(lo, DVec3(p)), hi = glm::max(hi, DVec3(p));
            max_abs = std::max(max_abs, double(glm::compMax(glm::abs(p))));
        }
    if (!(lo.x <= hi.x)) return covered;
    const double extent = glm::length(hi - lo);
    const double contact = std::max(kContactRelative * extent, std::numeric_limits<double>::min());
    // Exactly coincident: float positions of one face reached through different transforms.
    const double rounding = 16.0 * double(std::numeric_limits<float>::epsilon()) * max_abs;
    const DVec3 origin = 0.5 * (lo + hi);
    // Triangles of every surface that is not a back twin (a twin has its front's geometry),
    // filed under their plane (normal cell, offset cell) both ways round, so that a query
    // finds parallel and antiparallel ones alike.
    std::vector<PlaneTriangle> tris;
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        if (mesh.back) continue;
        for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
            const UVec3& v = mesh.triangles[t];
            if (v.x >= mesh.positions.size() || v.y >= mesh.positions.size() || v.z >= mesh.positions.size()) continue;
            PlaneTriangle pt;
            pt.p = {DVec3(mesh.positions[v.x]), DVec3(mesh.positions[v.y]), DVec3(mesh.positions[v.z])};
            const DVec3 n = glm::cross(pt.p[1] - pt.p[0], pt.p[2] - pt.p[0]);
            const double len = glm::length(n);
            if (!(len > 0.0)) continue;
            pt.normal = n / len;
            pt.area = 0.5 * len;
            pt.mesh = m, pt.triangle = t;
            tris.push_back(pt);
        }
    }
    const double normal_cell = 4.0 * kParallelTolerance;
    // Offsets from the scene's centre along nearly parallel normals differ by up to
    // kParallelTolerance x the extent: cells that wide, and the neighbours searched.
    const double offset_cell = std::max(4.0 * contact, 2.0 * kParallelTolerance * extent);
    struct Key {
        int64_t x, y, z, d;
        bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z && d == o.d; }
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = uint64_t(k.x) * 0x9E3779B97F4A7C15ull;
            h = (h ^ uint64_t(k.y)) * 0xC2B2AE3D27D4EB4Full;
            h = (h ^ uint64_t(k.z)) * 0x165667B19E3779F9ull;
            h = (h ^ uint64_t(k.d)) * 0x9E3779B97F4A7C15ull;
            return size_t(h ^ (h >> 29));
        }
    };
    const auto keyOf = [&](const DVec3& n, const DVec3& centre) {
        return Key{int64_t(std::floor(n.x / normal_cell)), int64_t(std::floor(n.y / normal_cell)),
                   int64_t(std::floor(n.z / normal_cell)), int64_t(std::floor(glm::dot(n, centre - origin) / offset_cell))};
    };
    std::unordered_map<Key, std::vector<uint32_t>, KeyHash> cells;
    for (uint32_t i = 0; i < tris.size(); ++i) {
        const DVec3 centre = (tris[i].p[0] + tris[i].p[1] + tris[i].p[2]) / 3.0;
        cells[keyOf(tris[i].normal, centre)].push_back(i);
        cells[keyOf(-tris[i].normal, centre)].push_back(i);
    }
    std::vector<uint32_t> seen;
    for (uint32_t i = 0; i < tris.size(); ++i) {
        const PlaneTriangle& front = tris[i];
        const Mesh& mesh = scene.meshes[front.mesh];
        if (mesh.twin == kNoMesh || mesh.twin >= scene.meshes.size()) continue;
        PlaneTriangle t = front;  // the back: the same corners, facing the other way
        t.normal = -front.normal;
        const DVec3 centre = (t.p[0] + t.p[1] + t.p[2]) / 3.0;
        const Key k = keyOf(t.normal, centre);
        seen.clear();
        double area = 0.0;
        for (int64_t dx = -1; dx <= 1; ++dx)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dz = -1; dz <= 1; ++dz)
                    for (int64_t dd = -1; dd <= 1; ++dd) {
                        const auto it = cells.find(Key{k.x + dx, k.y + dy, k.z + dz, k.d + dd});
                        if (it == cells.end()) continue;
                        for (uint32_t j : it->second) {
                            if (j == i || std::find(seen.begin(), seen.end(), j) != seen.end()) continue;
                            seen.push_back(j);
                            const PlaneTriangle& s = tris[j];
                            const double align = glm::dot(s.normal, t.normal);
                            const DVec3 dn = glm::abs(align > 0.0 ? s.normal - t.normal : s.normal + t.normal);
                            if (dn.x > kParallelTolerance || dn.y > kParallelTolerance || dn.z > kParallelTolerance) continue;
                            // S's corners measured from T's plane along T's normal, and back.
                            double d_min = std::numeric_limits<double>::max(), d_max = -d_min, back = 0.0;
                            for (int c = 0; c < 3; ++c) {
                                const double d = glm::dot(t.normal, s.p[c] - t.p[0]);
                                d_min = std::min(d_min, d), d_max = std::max(d_max, d);
                                back = std::max(back, std::abs(glm::dot(s.normal, t.p[c] - s.p[0])));
                            }
                            if (d_min < -contact || d_max > contact || back > contact) continue;
                            const double gap = 0.5 * (d_min + d_max);
                            if (gap < -rounding) continue;  // behind T: T faces away from it
                            if (gap <= rounding) {
                                // Coincident: a duplicate of T's side (a front, or an earlier
                                // twin), or the other side of the sheet (no gap).
                                if (align < 0.0) {
                                    const Mesh& other = scene.meshes[s.mesh];
                                    const bool earlier_twin = other.twin != kNoMesh &&
                                                              (s.mesh < front.mesh || (s.mesh == front.mesh && s.triangle < front.triangle));
                                    if (!earlier_twin) continue;
                                }
                            }
                            area += overlapArea(t, s);
                        }
                    }
        if (!(area > 0.0)) continue;
        const uint32_t twin = mesh.twin;
        const Mesh& back = scene.meshes[twin];
        std::vector<double>& per_polygon = covered[twin];
        if (per_polygon.empty()) per_polygon.assign(back.polygon_count, 0.0);
        const uint32_t polygon = front.triangle < back.triangle_polygon.size() ? back.triangle_polygon[front.triangle] : front.triangle;
        if (polygon < per_polygon.size()) per_polygon[polygon] += std::min(area, t.area);
    }
    // Fractions of each polygon's area.
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        if (covered[m].empty()) continue;
        const Mesh& back = scene.meshes[m];
        std::vector<double> polygon_area(back.polygon_count, 0.0);
        for (uint32_t t = 0; t < back.triangles.size(); ++t) {
            const UVec3& v = back.triangles[t];
            const double a = 0.5 * glm::length(glm::cross(DVec3(back.positions[v.y]) - DVec3(back.positions[v.x]),
                                                          DVec3(back.positions[v.z]) - DVec3(back.positions[v.x])));
            const uint32_t polygon = t < back.triangle_polygon.size() ? back.triangle_polygon[t] : t;
            if (polygon < polygon_area.size()) polygon_area[polygon] += a;
        }
        for (uint32_t p = 0; p < covered[m].size(); ++p)
            covered[m][p] = polygon_area[p] > 0.0 ? std::min(1.0, covered[m][p] / polygon_area[p]) : 0.0;
    }
    return covered;
}

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

size_t coverBacksInContact(Scene& scene) {
    const std::vector<std::vector<double>> covered = backContactCoverage(scene);
    size_t count = 0;
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        if (covered[m].empty()) continue;
        Mesh& back = scene.meshes[m];
        bool any = false;
        for (double f : covered[m]) any = any || f > kCoveredNegligible;
        if (!any) continue;
        // Per polygon from here on (the twin's own copy; its front keeps the material's).
        if (back.polygon_reflectance.size() < back.polygon_count)
            for (uint32_t p = uint32_t(back.polygon_reflectance.size()); p < back.polygon_count; ++p)
                back.polygon_reflectance.push_back(polygonReflectance(scene, back, p));
        if (back.polygon_emission.size() < back.polygon_count)
            for (uint32_t p = uint32_t(back.polygon_emission.size()); p < back.polygon_count; ++p)
                back.polygon_emission.push_back(polygonEmission(scene, back, p));
        for (uint32_t p = 0; p < back.polygon_count; ++p) {
            const double f = covered[m][p];
            if (!(f > kCoveredNegligible)) continue;
            // The covered part neither reflects nor emits: the polygon's mean over its area.
            const float open = f >= kCoveredWhole ? 0.0f : float(1.0 - f);
            back.polygon_reflectance[p] *= open;
            back.polygon_emission[p] *= open;
            ++count;
        }
    }
    scene.covered_back_polygons += count;
    return count;
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
    coverBacksInContact(scene);
    // A scoped light (Light::scope, mesh indices) lights a surface on both sides: the twins
    // just appended carry new indices, so each joins the scope of every light that lights its
    // front. Twins follow every original mesh with increasing indices, so the scope stays sorted.
    if (added > 0)
        for (Light& light : scene.lights) {
            if (!light.scoped) continue;
            const size_t in_scope = light.scope.size();
            for (size_t i = 0; i < in_scope; ++i) {
                const uint32_t front = light.scope[i];
                if (front < original && scene.meshes[front].twin != kNoMesh && !scene.meshes[front].back)
                    light.scope.push_back(scene.meshes[front].twin);
            }
            std::sort(light.scope.begin(), light.scope.end());
            light.scope.erase(std::unique(light.scope.begin(), light.scope.end()), light.scope.end());
        }
    return added;
}

}  // namespace radbake
