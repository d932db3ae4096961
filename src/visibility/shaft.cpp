// Shaft construction (Haines-Wallace boxes, polygon hulls) and box-vs-shaft classification.
#include "visibility/shaft.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "visibility/tolerance.h"

namespace radbake {
namespace {

constexpr int kBoxPlanes = 6;

Plane boxFacePlane(const Aabb& box, int axis, bool positive) {
    Plane plane;
    plane.normal = DVec3(0.0);
    plane.normal[axis] = positive ? 1.0 : -1.0;
    plane.offset = positive ? -box.max[axis] : box.min[axis];
    return plane;
}

// Coordinate of box's face in direction (axis, sign), measured along that direction.
double faceReach(const Aabb& box, int axis, bool positive) {
    return positive ? box.max[axis] : -box.min[axis];
}

double coordinateScale(const Aabb& a, const Aabb& b) {
    double scale = 0.0;
    for (int k = 0; k < 3; ++k) {
        scale = std::max({scale, std::abs(a.min[k]), std::abs(a.max[k]), std::abs(b.min[k]),
                          std::abs(b.max[k])});
    }
    return std::max(scale, std::numeric_limits<double>::min());
}

int largestAxis(const DVec3& v) {
    const DVec3 a = glm::abs(v);
    return a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
}

// The side plane parallel to `axis` through the edge between faces d1 and d2 of the union
// box, when the two faces belong to different boxes (Haines-Wallace); false otherwise.
// Directions are (axis, sign). The plane joins the corner of the owner of d1 at (d1, d2)
// and the corner of the owner of d2 at (d1, d2); its normal points into the (d1 + d2)
// quadrant, so both boxes lie inside it.
bool sidePlane(const Aabb& a, const Aabb& b, int axis1, bool pos1, int axis2, bool pos2,
               Plane& out) {
    const double a1 = faceReach(a, axis1, pos1), b1 = faceReach(b, axis1, pos1);
    const double a2 = faceReach(a, axis2, pos2), b2 = faceReach(b, axis2, pos2);
    // Strict ownership: a tie on either face makes the side plane coincide with a box plane.
    const bool a_owns_1 = a1 > b1, b_owns_1 = b1 > a1;
    const bool a_owns_2 = a2 > b2, b_owns_2 = b2 > a2;
    if (!((a_owns_1 && b_owns_2) || (b_owns_1 && a_owns_2))) return false;
    // In the 2D frame (direction d1, direction d2) the corners are (reach1, reach2).
    const DVec2 pa(a1, a2), pb(b1, b2);
    const DVec2 t = pb - pa;
    DVec2 n2(std::abs(t.y), std::abs(t.x));  // both components >= 0: into the (d1, d2) quadrant
    const double len = glm::length(n2);
    if (!(len > 0.0)) return false;
    n2 /= len;
    out.normal = DVec3(0.0);
    out.normal[axis1] = pos1 ? n2.x : -n2.x;
    out.normal[axis2] = pos2 ? n2.y : -n2.y;
    out.offset = -(n2.x * pa.x + n2.y * pa.y);
    return true;
}

// The "walls" of the channel seen in the projection along `axis`: for transverse direction
// `t` (an axis != axis), the side plane parallel to `axis` whose normal leans most towards
// +t (or -t), else the union box's face. Returns a plane index.
uint8_t wallPlane(const Shaft& shaft, int axis, int t, bool positive) {
    uint8_t best = static_cast<uint8_t>(2 * t + (positive ? 1 : 0));
    double best_lean = 0.0;
    for (uint8_t i = shaft.side_begin[axis]; i < shaft.side_begin[axis + 1]; ++i) {
        const double lean = positive ? shaft.planes[i].normal[t] : -shaft.planes[i].normal[t];
        if (lean > best_lean) {
            best_lean = lean;
            best = i;
        }
    }
    return best;
}

void pushOut(Shaft& shaft) {
    const double tol = shaftTolerance(shaft.scale);
    for (Plane& plane : shaft.planes) plane.offset -= tol;
}

}  // namespace

Shaft shaftBetweenBoxes(const Aabb& source, const Aabb& receiver) {
    Shaft shaft;
    shaft.kind = ShaftKind::Boxes;
    shaft.box = source;
    shaft.box.add(receiver);
    shaft.scale = coordinateScale(source, receiver);
    shaft.link_axis = largestAxis(receiver.center() - source.center());
    shaft.planes.reserve(14);
    for (int k = 0; k < 3; ++k) {
        shaft.planes.push_back(boxFacePlane(shaft.box, k, false));
        shaft.planes.push_back(boxFacePlane(shaft.box, k, true));
    }
    // Side planes parallel to axis k, in cyclic order around k: the edges between the face
    // directions +u, +v, -u, -v (u, v, k right-handed).
    for (int k = 0; k < 3; ++k) {
        shaft.side_begin[k] = static_cast<uint8_t>(shaft.planes.size());
        const int u = (k + 1) % 3, v = (k + 2) % 3;
        const int axes[4] = {u, v, u, v};
        const bool signs[4] = {true, true, false, false};
        for (int e = 0; e < 4; ++e) {
            Plane plane;
            const int f = (e + 1) % 4;
            if (sidePlane(source, receiver, axes[e], signs[e], axes[f], signs[f], plane)) {
                shaft.planes.push_back(plane);
            }
        }
    }
    shaft.side_begin[3] = static_cast<uint8_t>(shaft.planes.size());
    pushOut(shaft);
    // Pairs (reconstruction, see occlusion_obb.cpp): for each transverse direction t of the
    // link, the projection along the remaining axis k shows a 2D channel between a wall on
    // +t and a wall on -t.
    const int d = shaft.link_axis;
    for (int t = 0; t < 3; ++t) {
        if (t == d) continue;
        const int k = 3 - d - t;
        ShaftPair pair;
        pair.first = wallPlane(shaft, k, t, true);
        pair.second = wallPlane(shaft, k, t, false);
        pair.axis = static_cast<uint8_t>(k);
        shaft.pairs.push_back(pair);
    }
    return shaft;
}

Shaft shaftBetweenPolygons(std::span<const DVec3> source, std::span<const DVec3> receiver) {
    Aabb box_s, box_r;
    for (const DVec3& p : source) box_s.add(p);
    for (const DVec3& p : receiver) box_r.add(p);
    if (source.size() < 3 || receiver.size() < 3) return shaftBetweenBoxes(box_s, box_r);

    Shaft shaft;
    shaft.kind = ShaftKind::Polygons;
    shaft.box = box_s;
    shaft.box.add(box_r);
    shaft.scale = coordinateScale(box_s, box_r);
    shaft.link_axis = largestAxis(box_r.center() - box_s.center());
    shaft.side_begin = {0, 0, 0, 0};
    const double tol = shaftTolerance(shaft.scale);
    const double extent = glm::length(shaft.box.extent());

    // A face plane of conv(S u R) holds >= 3 affinely independent points; a face with only
    // source (receiver) points is the source (receiver) plane, any other face holds an edge
    // of one polygon and a vertex of the other. Test every such candidate: keep it if every
    // point lies on one side (within tol), oriented with the points inside.
    auto add_unique = [&](Plane plane) {
        for (const Plane& q : shaft.planes) {
            if (glm::dot(q.normal, plane.normal) > 1.0 - 1e-12 &&
                std::abs(q.offset - plane.offset) <= 4.0 * tol) {
                return;
            }
        }
        shaft.planes.push_back(plane);
    };
    // Plane through a, b, c, oriented so that every point is inside, if one side holds them
    // all (one pass over the points, stopping as soon as both sides hold one).
    auto try_plane = [&](const DVec3& a, const DVec3& b, const DVec3& c) {
        DVec3 n = glm::cross(b - a, c - a);
        const double len = glm::length(n);
        // Degenerate triangles (collinear within rounding) give no reliable direction.
        if (!(len > 1e-12 * extent * extent)) return;
        n /= len;
        const double offset = -glm::dot(n, a);
        bool above = false, below = false;
        auto visit = [&](std::span<const DVec3> points) {
            for (const DVec3& p : points) {
                const double d = glm::dot(n, p) + offset;
                above = above || d > tol;
                below = below || d < -tol;
                if (above && below) return false;
            }
            return true;
        };
        if (!visit(source) || !visit(receiver)) return;
        if (!above) {
            add_unique(Plane{n, offset});
        } else {
            add_unique(Plane{-n, -offset});
        }
    };
    auto edges_with_vertices = [&](std::span<const DVec3> poly, std::span<const DVec3> other) {
        const size_t n = poly.size();
        for (size_t i = 0; i < n; ++i) {
            const DVec3& a = poly[i];
            const DVec3& b = poly[(i + 1) % n];
            for (const DVec3& c : other) try_plane(a, b, c);
        }
    };
    // The polygons' own planes. Real polygons are planar only up to rounding (and a quad may
    // be warped), so try every vertex triple of small polygons, consecutive triples of large
    // ones. Any accepted plane has every point inside, so a face missed here only loosens
    // the shaft (the union box still bounds it in classifyAabb); it never cuts the hull.
    auto own_planes = [&](std::span<const DVec3> poly) {
        const size_t n = poly.size();
        if (n <= 6) {
            for (size_t i = 0; i < n; ++i) {
                for (size_t j = i + 1; j < n; ++j) {
                    for (size_t k = j + 1; k < n; ++k) try_plane(poly[i], poly[j], poly[k]);
                }
            }
        } else {
            for (size_t i = 0; i < n; ++i) try_plane(poly[i], poly[(i + 1) % n], poly[(i + 2) % n]);
        }
    };
    own_planes(source);
    own_planes(receiver);
    edges_with_vertices(source, receiver);
    edges_with_vertices(receiver, source);
    // A closed hull needs >= 4 faces; fewer means the two polygons are coplanar (a flat
    // hull) or degenerate: use the box shaft, which is always valid.
    if (shaft.planes.size() < 4) return shaftBetweenBoxes(box_s, box_r);
    // The tol accepted above lets points sit up to tol outside a plane: push out by 2 tol.
    for (Plane& plane : shaft.planes) plane.offset -= 2.0 * tol;
    return shaft;
}

namespace {

// Min over the box of a plane, by interval arithmetic.
inline double aabbMin(const Plane& plane, const DVec3& center, const DVec3& half) {
    return glm::dot(plane.normal, center) + plane.offset -
           (std::abs(plane.normal.x) * half.x + std::abs(plane.normal.y) * half.y +
            std::abs(plane.normal.z) * half.z);
}

}  // namespace

Side classifyAabb(const Shaft& shaft, const Aabb& box) {
    // The box's own coordinates may be larger than the shaft's: scale by both.
    const double tol =
        shaftTolerance(std::max({shaft.scale, maxAbs(box.min), maxAbs(box.max)}));
    for (int k = 0; k < 3; ++k) {
        if (box.min[k] > shaft.box.max[k] + tol || box.max[k] < shaft.box.min[k] - tol) {
            return Side::Outside;
        }
    }
    const DVec3 center = box.center();
    const DVec3 half = 0.5 * box.extent();
    for (const Plane& plane : shaft.planes) {
        if (aabbMin(plane, center, half) > tol) return Side::Outside;
    }
    return Side::Crossing;
}

BoxSide classifyAabbInside(const Shaft& shaft, const Aabb& box) {
    const double tol =
        shaftTolerance(std::max({shaft.scale, maxAbs(box.min), maxAbs(box.max)}));
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
        if (box.min[k] > shaft.box.max[k] + tol || box.max[k] < shaft.box.min[k] - tol) return BoxSide::Outside;
        inside = inside && box.min[k] >= shaft.box.min[k] && box.max[k] <= shaft.box.max[k];
    }
    const DVec3 center = box.center();
    const DVec3 half = 0.5 * box.extent();
    for (const Plane& plane : shaft.planes) {
        const double at_center = glm::dot(plane.normal, center) + plane.offset;
        const double reach = std::abs(plane.normal.x) * half.x + std::abs(plane.normal.y) * half.y +
                             std::abs(plane.normal.z) * half.z;
        if (at_center - reach > tol) return BoxSide::Outside;
        inside = inside && at_center + reach <= 0.0;
    }
    return inside ? BoxSide::Inside : BoxSide::Crossing;
}

Side classifyObb(const Shaft& shaft, const Obb& box) {
    ObbPlaneCache cache;
    return classifyObb(shaft, box, cache);
}

Side classifyObb(const Shaft& shaft, const Obb& box, ObbPlaneCache& cache) {
    const double box_reach =
        maxAbs(box.center) + box.half_extents.x + box.half_extents.y + box.half_extents.z;
    const double tol = shaftTolerance(std::max(shaft.scale, box_reach));
    cache.origin = box.center;
    for (int i = 0; i < 3; ++i) {
        cache.origin -= box.axes[i] * box.half_extents[i];
        cache.edges[i] = box.axes[i] * (2.0 * box.half_extents[i]);
    }
    const size_t n = shaft.planes.size();
    for (size_t p = 0; p < n; ++p) {
        const Plane& plane = shaft.planes[p];
        const double at_origin = plane.eval(cache.origin);
        const double e0 = glm::dot(plane.normal, cache.edges[0]);
        const double e1 = glm::dot(plane.normal, cache.edges[1]);
        const double e2 = glm::dot(plane.normal, cache.edges[2]);
        if (p < static_cast<size_t>(ObbPlaneCache::kMaxPlanes)) {
            cache.at_origin[p] = at_origin;
            cache.n_dot_edge[p] = {e0, e1, e2};
        }
        const double min_value =
            at_origin + std::min(0.0, e0) + std::min(0.0, e1) + std::min(0.0, e2);
        if (min_value > tol) return Side::Outside;
    }
    return Side::Crossing;
}

}  // namespace radbake
