#pragma once
// Coplanar triangles: the tolerances and the 2-D clipping shared by the overlap warnings
// (validate_overlap.cpp) and the backs in contact (two_sided.cpp). Internal to src/scene.
#include <array>
#include <cmath>

#include "scene/scene.h"

namespace radbake::coplanar {

// Coplanar means every vertex of each triangle lies within this fraction of the scene's
// extent from the other's plane: far above float rounding of the same vertices reached
// through different transforms (2^-24 of the extent), far below any deliberate offset.
inline constexpr double kRelativeTolerance = 1e-5;
// ... and their unit normals agree within this in every component (about 0.006 degrees).
// Copies of one face agree to rounding over its size, so copies of faces larger than about
// 1e-4 of the extent are caught; tilted near-coplanar slivers are not faces given twice.
inline constexpr double kNormalTolerance = 1e-4;

// The axis a plane with normal n is projected along (its largest component).
inline int dominantAxis(const DVec3& n) {
    const DVec3 a = glm::abs(n);
    return a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
}

// p with coordinate `axis` dropped, the other two in cyclic order (keeps orientation).
inline DVec2 project(const DVec3& p, int axis) {
    return axis == 0 ? DVec2(p.y, p.z) : (axis == 1 ? DVec2(p.z, p.x) : DVec2(p.x, p.y));
}

inline double cross2(const DVec2& a, const DVec2& b) { return a.x * b.y - a.y * b.x; }

// A triangle clipped by three half-planes has at most 6 corners; with rounding, the signs
// along a nearly flat polygon may change more than twice, each clip at most doubling the
// corners: 3 * 2^3 bounds every case.
using Polygon2 = std::array<DVec2, 24>;

// Clips `poly` (n corners) by the left side of the directed line a -> b (Sutherland-Hodgman).
inline int clipByEdge(const Polygon2& poly, int n, const DVec2& a, const DVec2& b, Polygon2& out) {
    int count = 0;
    const DVec2 edge = b - a;
    for (int i = 0; i < n; ++i) {
        const DVec2& p = poly[i];
        const DVec2& q = poly[(i + 1) % n];
        const double sp = cross2(edge, p - a);
        const double sq = cross2(edge, q - a);
        if (sp >= 0.0) out[count++] = p;
        if ((sp >= 0.0) != (sq >= 0.0)) out[count++] = p + (q - p) * (sp / (sp - sq));
    }
    return count;
}

// Triangle tb clipped to triangle ta (both 2-D, counter-clockwise): the intersection's
// corners in *result (one of the two buffers), their count returned.
inline int clipTriangle(const std::array<DVec2, 3>& ta, const std::array<DVec2, 3>& tb, Polygon2 (&buffers)[2],
                        Polygon2*& result) {
    Polygon2* poly = &buffers[0];
    Polygon2* next = &buffers[1];
    int count = 3;
    for (int k = 0; k < 3; ++k) (*poly)[k] = tb[k];
    for (int k = 0; k < 3 && count > 0; ++k) {
        count = clipByEdge(*poly, count, ta[k], ta[(k + 1) % 3], *next);
        std::swap(poly, next);
    }
    result = poly;
    return count;
}

// Twice the signed area of a 2-D polygon.
inline double twiceArea(const Polygon2& poly, int count) {
    double twice = 0.0;
    for (int k = 0; count >= 3 && k < count; ++k) twice += cross2(poly[k], poly[(k + 1) % count]);
    return twice;
}

// The area of the intersection of two (nearly) coplanar triangles a and b, measured in a's
// plane (unit normal a_normal), projected along a's dominant axis.
inline double overlapArea(const std::array<DVec3, 3>& a, const DVec3& a_normal, const std::array<DVec3, 3>& b) {
    const int axis = dominantAxis(a_normal);
    std::array<DVec2, 3> ta, tb;
    for (int k = 0; k < 3; ++k) {
        ta[k] = project(a[k] - a[0], axis);
        tb[k] = project(b[k] - a[0], axis);
    }
    if (cross2(ta[1] - ta[0], ta[2] - ta[0]) < 0.0) std::swap(ta[1], ta[2]);
    Polygon2 buffers[2];
    Polygon2* poly = nullptr;
    const int count = clipTriangle(ta, tb, buffers, poly);
    if (count < 3) return 0.0;
    return 0.5 * std::abs(twiceArea(*poly, count)) / std::abs(a_normal[axis]);
}

}  // namespace radbake::coplanar
