#include "geometry/box.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "geometry/hull.h"
#include "geometry/polygon.h"

namespace radbake {

std::array<DVec3, 8> boxCorners(const Aabb& box) {
    std::array<DVec3, 8> corners;
    for (int i = 0; i < 8; ++i)
        corners[i] = DVec3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z);
    return corners;
}

std::array<DVec3, 8> boxCorners(const Obb& box) {
    std::array<DVec3, 8> corners;
    for (int i = 0; i < 8; ++i) {
        DVec3 p = box.center;
        for (int a = 0; a < 3; ++a) p += box.axes[a] * (((i >> a) & 1) ? box.half_extents[a] : -box.half_extents[a]);
        corners[i] = p;
    }
    return corners;
}

Aabb aabbOf(std::span<const DVec3> points) {
    Aabb box;
    for (const DVec3& p : points) box.add(p);
    return box;
}

Aabb aabbOf(const Obb& box) {
    Aabb out;
    DVec3 reach(0.0);
    for (int a = 0; a < 3; ++a) reach += glm::abs(box.axes[a]) * box.half_extents[a];
    out.min = box.center - reach;
    out.max = box.center + reach;
    return out;
}

double obbVolume(const Obb& box) { return 8.0 * box.half_extents.x * box.half_extents.y * box.half_extents.z; }

double obbLargestFaceArea(const Obb& box) {
    const DVec3& h = box.half_extents;
    return 4.0 * std::max({h.x * h.y, h.y * h.z, h.x * h.z});
}

bool contains(const Aabb& box, const DVec3& p, double tolerance) {
    for (int a = 0; a < 3; ++a)
        if (p[a] < box.min[a] - tolerance || p[a] > box.max[a] + tolerance) return false;
    return true;
}

bool contains(const Obb& box, const DVec3& p, double tolerance) {
    const DVec3 d = p - box.center;
    for (int a = 0; a < 3; ++a)
        if (std::abs(glm::dot(d, box.axes[a])) > box.half_extents[a] + tolerance) return false;
    return true;
}

namespace {

// Box with the given orthonormal axes that just contains the points.
Obb boxAlong(std::span<const DVec3> points, const std::array<DVec3, 3>& axes) {
    DVec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const DVec3& p : points)
        for (int a = 0; a < 3; ++a) {
            const double t = glm::dot(p, axes[a]);
            lo[a] = std::min(lo[a], t);
            hi[a] = std::max(hi[a], t);
        }
    Obb box;
    box.axes = axes;
    box.half_extents = 0.5 * (hi - lo);
    const DVec3 mid = 0.5 * (hi + lo);
    box.center = axes[0] * mid.x + axes[1] * mid.y + axes[2] * mid.z;
    return box;
}

// Eigenvectors of a symmetric 3x3 matrix by cyclic Jacobi rotations; columns of `vectors`.
void symmetricEigen(double m[3][3], double vectors[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) vectors[i][j] = i == j ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
        const double diag = m[0][0] * m[0][0] + m[1][1] * m[1][1] + m[2][2] * m[2][2];
        if (off <= 1e-30 * diag || off == 0.0) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (m[p][q] == 0.0) continue;
                const double theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {  // m = J^T m J
                    const double mkp = m[k][p], mkq = m[k][q];
                    m[k][p] = c * mkp - s * mkq;
                    m[k][q] = s * mkp + c * mkq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double mpk = m[p][k], mqk = m[q][k];
                    m[p][k] = c * mpk - s * mqk;
                    m[q][k] = s * mpk + c * mqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double vkp = vectors[k][p], vkq = vectors[k][q];
                    vectors[k][p] = c * vkp - s * vkq;
                    vectors[k][q] = s * vkp + c * vkq;
                }
            }
    }
}

// Orthonormal right-handed frame whose third axis is n.
std::array<DVec3, 3> frameAround(const DVec3& n, const DVec2& u2, const DVec3& u, const DVec3& v) {
    const DVec3 a0 = glm::normalize(u * u2.x + v * u2.y);
    const DVec3 a1 = glm::normalize(glm::cross(n, a0));
    return {a0, a1, n};
}

// Best box with one axis fixed to n: min-area rectangle of the projection onto n's plane.
// Returns the volume (or area when `flat`) and fills `box`.
double boxAroundAxis(std::span<const DVec3> points, const DVec3& n, Obb& box) {
    DVec3 u, v;
    tangentFrame(n, u, v);
    std::vector<DVec2> flat(points.size());
    for (size_t i = 0; i < points.size(); ++i) flat[i] = DVec2(glm::dot(points[i], u), glm::dot(points[i], v));
    const std::vector<uint32_t> ring = convexHull2d(flat);
    std::vector<DVec2> hull2;
    hull2.reserve(ring.size());
    for (uint32_t i : ring) hull2.push_back(flat[i]);
    const Rect2 rect = minAreaRect(hull2);
    box = boxAlong(points, frameAround(n, rect.axis_u, u, v));
    return obbVolume(box);
}

// Canonical key for a direction up to sign, quantised so near-parallel candidates collapse.
std::tuple<long, long, long> directionKey(DVec3 d) {
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-12) continue;
        if (d[a] < 0) d = -d;
        break;
    }
    const double q = 1e6;
    return {std::lround(d.x * q), std::lround(d.y * q), std::lround(d.z * q)};
}

}  // namespace

Obb pcaObb(std::span<const DVec3> points) {
    if (points.empty()) return Obb{};
    DVec3 mean(0.0);
    for (const DVec3& p : points) mean += p;
    mean /= double(points.size());
    double cov[3][3] = {};
    for (const DVec3& p : points) {
        const DVec3 d = p - mean;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) cov[i][j] += d[i] * d[j];
    }
    double vectors[3][3];
    symmetricEigen(cov, vectors);
    DVec3 a0(vectors[0][0], vectors[1][0], vectors[2][0]);
    DVec3 a1(vectors[0][1], vectors[1][1], vectors[2][1]);
    a0 = glm::normalize(a0);
    a1 = glm::normalize(a1 - a0 * glm::dot(a0, a1));
    return boxAlong(points, {a0, a1, glm::cross(a0, a1)});
}

Obb flatObb(std::span<const DVec3> points, const DVec3& normal) {
    Obb box;
    boxAroundAxis(points, normal, box);
    // Rounding leaves a hair of thickness along the normal; a flat box has none. The center
    // stays mid-way between the points' extreme offsets along the normal.
    box.half_extents.z = 0.0;
    return box;
}

Obb fitObb(std::span<const DVec3> points) {
    if (points.empty()) return Obb{};
    return fitObb(quickhull(points, 1e-9 * std::max(pointExtent(points), 1e-30)), points);
}

Obb fitObb(const Hull3& hull, std::span<const DVec3> points) {
    if (points.empty()) return Obb{};
    if (hull.dimension <= 0) {
        Obb box;
        box.center = points[0];
        return box;
    }
    if (hull.dimension == 1) {
        const DVec3 d = glm::normalize(hull.vertices[1] - hull.vertices[0]);
        DVec3 u, v;
        tangentFrame(d, u, v);
        return boxAlong(points, {d, u, v});
    }
    if (hull.dimension == 2) {
        Obb box = flatObb(hull.vertices, hull.planes[0].normal);
        return boxAlong(points, box.axes);  // extents over every point, thickness ~0
    }
    const std::span<const DVec3> h(hull.vertices);
    Obb best = boxAlong(h, pcaObb(points).axes);
    double best_volume = obbVolume(best);
    std::set<std::tuple<long, long, long>> tried;
    auto consider = [&](const DVec3& axis) {
        if (!tried.insert(directionKey(axis)).second) return;
        Obb box;
        const double volume = boxAroundAxis(h, axis, box);
        if (volume < best_volume) best_volume = volume, best = box;
    };
    // Candidate axes: face normals (largest faces first) and hull-edge directions. Big hulls
    // (finely tessellated spheres) are capped so the fit stays near-linear.
    // Each candidate costs a 2D hull of the hull vertices; a budget of ~1e5 projected points
    // per kind keeps a 1000-face sphere near 10 ms, whose box hardly depends on it.
    const size_t kMaxCandidates = std::clamp<size_t>(100000 / std::max<size_t>(h.size(), 1), 8, 64);
    std::vector<std::pair<double, size_t>> by_area;
    for (size_t f = 0; f < hull.faces.size(); ++f) {
        std::vector<DVec3> loop;
        for (uint32_t i : hull.faces[f]) loop.push_back(hull.vertices[i]);
        by_area.push_back({polygonArea(loop), f});
    }
    std::sort(by_area.begin(), by_area.end(), std::greater<>());
    for (size_t k = 0; k < by_area.size() && k < kMaxCandidates; ++k) consider(hull.planes[by_area[k].second].normal);
    std::vector<std::pair<double, DVec3>> edges;
    for (const std::vector<uint32_t>& face : hull.faces)
        for (size_t k = 0; k < face.size(); ++k) {
            const uint32_t a = face[k], b = face[(k + 1) % face.size()];
            if (a < b) {  // each edge once
                const DVec3 d = hull.vertices[b] - hull.vertices[a];
                edges.push_back({glm::length(d), d});
            }
        }
    std::sort(edges.begin(), edges.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    for (size_t k = 0; k < edges.size() && k < kMaxCandidates; ++k)
        if (edges[k].first > 0.0) consider(edges[k].second / edges[k].first);
    // The winner's own axes as fixed axes can improve it further (local refinement).
    for (int round = 0; round < 2; ++round)
        for (int a = 0; a < 3; ++a) {
            Obb box;
            const double volume = boxAroundAxis(h, best.axes[a], box);
            if (volume < best_volume * (1.0 - 1e-12)) best_volume = volume, best = box;
        }
    // Final extents over every input point (hull vertices drop points within tolerance);
    // the PCA box is a candidate, so the result is never larger than it.
    best = boxAlong(points, best.axes);
    const Obb pca = pcaObb(points);
    return obbVolume(pca) < obbVolume(best) ? pca : best;
}

}  // namespace radbake
