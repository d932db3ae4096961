#include "io/vrml/primitives.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <utility>
#include <vector>

namespace radbake::vrml {
namespace {

uint32_t addVertex(Mesh& mesh, Vec3 p) {
    mesh.positions.push_back(p);
    return static_cast<uint32_t>(mesh.positions.size() - 1);
}

// Appends one convex polygon (a fan from its first corner) as the next polygon id.
void addConvexPolygon(Mesh& mesh, const std::vector<uint32_t>& loop) {
    for (size_t i = 1; i + 1 < loop.size(); ++i) {
        mesh.triangles.push_back(UVec3(loop[0], loop[i], loop[i + 1]));
        mesh.triangle_polygon.push_back(mesh.polygon_count);
    }
    ++mesh.polygon_count;
}

void addConvexPolygon(Mesh& mesh, std::initializer_list<uint32_t> loop) {
    addConvexPolygon(mesh, std::vector<uint32_t>(loop));
}

// A ring of kRoundSegments vertices at height y; angle phi measured from +Z towards +X, so
// that walking the ring in index order is counter-clockwise seen from +Y.
uint32_t addRing(Mesh& mesh, float radius, float y) {
    const uint32_t first = static_cast<uint32_t>(mesh.positions.size());
    for (int j = 0; j < kRoundSegments; ++j) {
        const double phi = 2.0 * kPi * j / kRoundSegments;
        mesh.positions.push_back(Vec3(static_cast<float>(radius * std::sin(phi)), y,
                                      static_cast<float>(radius * std::cos(phi))));
    }
    return first;
}

uint32_t ringIndex(uint32_t first, int j) { return first + static_cast<uint32_t>(j % kRoundSegments); }

// Quads between a lower and an upper ring, counter-clockwise seen from outside.
void addBand(Mesh& mesh, uint32_t lower, uint32_t upper) {
    for (int j = 0; j < kRoundSegments; ++j)
        addConvexPolygon(mesh, {ringIndex(lower, j), ringIndex(lower, j + 1), ringIndex(upper, j + 1),
                                ringIndex(upper, j)});
}

// A cap n-gon over a ring: facing +Y keeps ring order, facing -Y reverses it.
void addCap(Mesh& mesh, uint32_t ring, bool facing_up) {
    std::vector<uint32_t> loop(kRoundSegments);
    for (int j = 0; j < kRoundSegments; ++j)
        loop[static_cast<size_t>(j)] = ringIndex(ring, facing_up ? j : kRoundSegments - 1 - j);
    addConvexPolygon(mesh, loop);
}

bool positiveFinite(float v) { return std::isfinite(v) && v > 0.0f; }

void markRound(Mesh& mesh) { mesh.crease_angle = std::max(mesh.crease_angle, kRoundCreaseAngle); }

// The texture coordinate of a box corner `p` on the face whose outward normal is `n`.
Vec2 boxUv(DVec3 p, DVec3 n, Vec3 size) {
    const DVec3 q = p / DVec3(size);  // each coordinate in [-0.5, 0.5]
    if (n.z > 0.5) return Vec2(0.5 + q.x, 0.5 + q.y);   // front: +X right, +Y up
    if (n.z < -0.5) return Vec2(0.5 - q.x, 0.5 + q.y);  // back, seen from -Z
    if (n.x > 0.5) return Vec2(0.5 - q.z, 0.5 + q.y);   // right, seen from +X
    if (n.x < -0.5) return Vec2(0.5 + q.z, 0.5 + q.y);  // left, seen from -X
    if (n.y > 0.5) return Vec2(0.5 + q.x, 0.5 - q.z);   // top, seen from above with -Z up
    return Vec2(0.5 + q.x, 0.5 + q.z);                  // bottom, seen from below with +Z up
}

// The fraction of a turn from -Z, counter-clockwise seen from above (through -X, +Z, +X).
double turnFromBack(DVec3 p) { return 0.5 + std::atan2(p.x, p.z) / (2.0 * kPi); }

}  // namespace

void appendBox(Mesh& mesh, Vec3 size) {
    const bool was_empty = mesh.triangles.empty();
    const Vec3 h = size * 0.5f;
    // Corner c has x = +h.x when bit 0 is set, y when bit 1, z when bit 2.
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
    for (int c = 0; c < 8; ++c)
        addVertex(mesh, Vec3((c & 1) ? h.x : -h.x, (c & 2) ? h.y : -h.y, (c & 4) ? h.z : -h.z));
    for (int axis = 0; axis < 3; ++axis) {
        // u, v follow axis cyclically, so (u, v) walked (-,-) (+,-) (+,+) (-,+) turns
        // counter-clockwise seen from the +axis side.
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (int sign = 1; sign >= 0; --sign) {
            auto corner = [&](int bu, int bv) {
                return base + static_cast<uint32_t>((sign << axis) | (bu << u) | (bv << v));
            };
            if (sign)
                addConvexPolygon(mesh, {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)});
            else
                addConvexPolygon(mesh, {corner(0, 1), corner(1, 1), corner(1, 0), corner(0, 0)});
        }
    }
    if (was_empty) mesh.convex_solid = positiveFinite(size.x) && positiveFinite(size.y) && positiveFinite(size.z);
    else mesh.convex_solid = false;
}

void appendSphere(Mesh& mesh, float radius) {
    const bool was_empty = mesh.triangles.empty();
    const uint32_t north = addVertex(mesh, Vec3(0.0f, radius, 0.0f));
    std::vector<uint32_t> rings;  // bands 1..kSphereBands-1, north to south
    for (int k = 1; k < kSphereBands; ++k) {
        const double theta = kPi * k / kSphereBands;
        rings.push_back(addRing(mesh, static_cast<float>(radius * std::sin(theta)),
                                static_cast<float>(radius * std::cos(theta))));
    }
    const uint32_t south = addVertex(mesh, Vec3(0.0f, -radius, 0.0f));
    for (int j = 0; j < kRoundSegments; ++j)
        addConvexPolygon(mesh, {ringIndex(rings.front(), j), ringIndex(rings.front(), j + 1), north});
    for (size_t k = 0; k + 1 < rings.size(); ++k) addBand(mesh, rings[k + 1], rings[k]);
    for (int j = 0; j < kRoundSegments; ++j)
        addConvexPolygon(mesh, {south, ringIndex(rings.back(), j + 1), ringIndex(rings.back(), j)});
    mesh.convex_solid = was_empty && positiveFinite(radius);
    markRound(mesh);
}

void appendCylinder(Mesh& mesh, float radius, float height, bool side, bool top, bool bottom) {
    const bool was_empty = mesh.triangles.empty();
    if (!side && !top && !bottom) return;
    const uint32_t lower = addRing(mesh, radius, -0.5f * height);
    const uint32_t upper = addRing(mesh, radius, 0.5f * height);
    if (side) addBand(mesh, lower, upper);
    if (top) addCap(mesh, upper, true);
    if (bottom) addCap(mesh, lower, false);
    mesh.convex_solid = was_empty && side && top && bottom && positiveFinite(radius) && positiveFinite(height);
    if (side) markRound(mesh);
}

void appendCone(Mesh& mesh, float bottom_radius, float height, bool side, bool bottom) {
    const bool was_empty = mesh.triangles.empty();
    if (!side && !bottom) return;
    const uint32_t ring = addRing(mesh, bottom_radius, -0.5f * height);
    if (side) {
        const uint32_t apex = addVertex(mesh, Vec3(0.0f, 0.5f * height, 0.0f));
        for (int j = 0; j < kRoundSegments; ++j)
            addConvexPolygon(mesh, {ringIndex(ring, j), ringIndex(ring, j + 1), apex});
        markRound(mesh);
    }
    if (bottom) addCap(mesh, ring, false);
    mesh.convex_solid = was_empty && side && bottom && positiveFinite(bottom_radius) && positiveFinite(height);
}

void primitiveTextureCoordinates(Mesh& mesh, Primitive kind, Vec3 size) {
    const double radius = size.x, height = kind == Primitive::Sphere ? 2.0 * size.x : size.y;
    // Per polygon: its outward normal and its centre's turn (a side's s away from the seam).
    std::vector<DVec3> normal(mesh.polygon_count, DVec3(0.0)), centre(mesh.polygon_count, DVec3(0.0));
    std::vector<int> corners(mesh.polygon_count, 0);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const UVec3& tri = mesh.triangles[t];
        const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
        const uint32_t polygon = mesh.triangle_polygon[t];
        normal[polygon] += glm::cross(b - a, c - a);
        centre[polygon] += a + b + c;
        corners[polygon] += 3;
    }
    const auto uvOf = [&](uint32_t polygon, DVec3 p) -> Vec2 {
        const DVec3 n = glm::normalize(normal[polygon]);
        if (kind == Primitive::Box) return boxUv(p, n, size);
        if (kind != Primitive::Sphere && std::fabs(n.y) > 0.999) {  // a cap, upright seen tilted towards the viewer
            const double sign = n.y > 0.0 ? -1.0 : 1.0;
            return Vec2(0.5 + p.x / (2.0 * radius), 0.5 + sign * p.z / (2.0 * radius));
        }
        const double middle = turnFromBack(centre[polygon] / static_cast<double>(corners[polygon]));
        double s = turnFromBack(p);
        if (std::hypot(p.x, p.z) < 1e-6 * radius) s = middle;  // a pole or the apex: its own triangle's turn
        s += std::round(middle - s);                          // the side of the seam its polygon is on
        const double t = kind == Primitive::Sphere ? 1.0 - std::acos(std::clamp(p.y / radius, -1.0, 1.0)) / kPi
                                                   : 0.5 + p.y / height;
        return Vec2(s, t);
    };
    std::map<std::pair<uint32_t, std::pair<float, float>>, uint32_t> split;  // (vertex, uv) -> vertex
    std::vector<Vec3> positions;
    std::vector<Vec2> uvs;
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t& v = mesh.triangles[t][k];
            const Vec2 uv = uvOf(mesh.triangle_polygon[t], DVec3(mesh.positions[v]));
            const auto [it, added] = split.try_emplace({v, {uv.x, uv.y}}, static_cast<uint32_t>(positions.size()));
            if (added) {
                positions.push_back(mesh.positions[v]);
                uvs.push_back(uv);
            }
            v = it->second;
        }
    mesh.positions = std::move(positions);
    mesh.uv0 = std::move(uvs);
}

}  // namespace radbake::vrml
