#pragma once
// Meshes built in code for the geometry tests.
#include <cmath>
#include <vector>

#include "scene/scene.h"

namespace radbake::test {

// Appends a planar polygon (fan-triangulated from its first vertex) as the mesh's next
// polygon. Vertices are not shared with earlier polygons, as many readers do it; the parts
// stage welds them.
inline void addPolygon(Mesh& mesh, const std::vector<Vec3>& loop) {
    const uint32_t base = uint32_t(mesh.positions.size());
    for (const Vec3& p : loop) mesh.positions.push_back(p);
    for (uint32_t i = 1; i + 1 < loop.size(); ++i) {
        mesh.triangles.push_back(UVec3(base, base + i, base + i + 1));
        mesh.triangle_polygon.push_back(mesh.polygon_count);
    }
    ++mesh.polygon_count;
}

inline Vec3 apply(const Quat& q, const Vec3& p, const Vec3& t) { return q * p + t; }

// Axis-aligned box [-h, h] rotated by q and moved by t; faces counter-clockwise from outside.
inline Mesh boxMesh(Vec3 h, Quat q = Quat(1, 0, 0, 0), Vec3 t = Vec3(0), bool skip_top = false) {
    Mesh mesh;
    mesh.name = "box";
    auto c = [&](int sx, int sy, int sz) { return apply(q, Vec3(sx * h.x, sy * h.y, sz * h.z), t); };
    addPolygon(mesh, {c(-1, -1, -1), c(-1, 1, -1), c(1, 1, -1), c(1, -1, -1)});  // -z
    if (!skip_top) addPolygon(mesh, {c(-1, -1, 1), c(1, -1, 1), c(1, 1, 1), c(-1, 1, 1)});  // +z
    addPolygon(mesh, {c(-1, -1, -1), c(1, -1, -1), c(1, -1, 1), c(-1, -1, 1)});  // -y
    addPolygon(mesh, {c(-1, 1, -1), c(-1, 1, 1), c(1, 1, 1), c(1, 1, -1)});      // +y
    addPolygon(mesh, {c(-1, -1, -1), c(-1, -1, 1), c(-1, 1, 1), c(-1, 1, -1)});  // -x
    addPolygon(mesh, {c(1, -1, -1), c(1, 1, -1), c(1, 1, 1), c(1, -1, 1)});      // +x
    return mesh;
}

// Cylinder around z, radius r, from z = 0 to z = height, `segments` side quads and two caps.
inline Mesh cylinderMesh(float r, float height, int segments) {
    Mesh mesh;
    mesh.name = "cylinder";
    auto ring = [&](int i, float z) {
        // i modulo segments: the seam must reuse the exact same positions to close.
        const double a = 2.0 * 3.14159265358979323846 * (i % segments) / segments;
        return Vec3(float(r * std::cos(a)), float(r * std::sin(a)), z);
    };
    std::vector<Vec3> top, bottom;
    for (int i = 0; i < segments; ++i) {
        top.push_back(ring(i, height));
        bottom.push_back(ring(segments - i, 0.0f));  // reversed: faces down
        addPolygon(mesh, {ring(i, 0.0f), ring(i + 1, 0.0f), ring(i + 1, height), ring(i, height)});
    }
    addPolygon(mesh, top);
    addPolygon(mesh, bottom);
    return mesh;
}

// UV sphere with shared pole vertices; coordinates rounded to `decimals` places as files
// print them (0 = no rounding).
inline Mesh sphereMesh(float r, int slices, int stacks, int decimals) {
    Mesh mesh;
    mesh.name = "sphere";
    const double scale = std::pow(10.0, decimals);
    auto round = [&](double x) { return decimals > 0 ? float(std::round(x * scale) / scale) : float(x); };
    auto point = [&](int i, int j) {  // j = 0 south pole ... stacks north pole
        const double theta = 3.14159265358979323846 * j / stacks - 1.5707963267948966;
        const double phi = 2.0 * 3.14159265358979323846 * (i % slices) / slices;
        if (j == 0) return Vec3(0, 0, -r);
        if (j == stacks) return Vec3(0, 0, r);
        return Vec3(round(r * std::cos(theta) * std::cos(phi)), round(r * std::cos(theta) * std::sin(phi)),
                    round(r * std::sin(theta)));
    };
    for (int j = 0; j < stacks; ++j)
        for (int i = 0; i < slices; ++i) {
            if (j == 0) addPolygon(mesh, {point(i, 0), point(i + 1, 1), point(i, 1)});
            else if (j == stacks - 1) addPolygon(mesh, {point(i, j), point(i + 1, j), point(i, stacks)});
            else {
                addPolygon(mesh, {point(i, j), point(i + 1, j), point(i + 1, j + 1)});
                addPolygon(mesh, {point(i, j), point(i + 1, j + 1), point(i, j + 1)});
            }
        }
    return mesh;
}

inline Scene sceneOf(std::vector<Mesh> meshes) {
    Scene scene;
    scene.meshes = std::move(meshes);
    scene.materials.push_back(Material{});
    return scene;
}

}  // namespace radbake::test
