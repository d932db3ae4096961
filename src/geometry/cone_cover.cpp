#include "geometry/cone_cover.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "geometry/polygon.h"

namespace radbake {
namespace {

// A convex polygon of at most kMaxCorners corners, on the stack: the test runs for every dark
// sky cell, so it allocates nothing.
constexpr int kMaxCorners = 24;
struct Polygon2 {
    std::array<DVec2, kMaxCorners> v;
    int n = 0;
    bool overflow = false;
    void push(const DVec2& p) {
        if (n < kMaxCorners) v[n++] = p;
        else overflow = true;
    }
};

double area(const Polygon2& p) {
    double twice = 0.0;
    for (int i = 0; i < p.n; ++i) {
        const DVec2& a = p.v[i];
        const DVec2& b = p.v[(i + 1) % p.n];
        twice += a.x * b.y - a.y * b.x;
    }
    return 0.5 * twice;
}

// The part of convex `p` where n . x + c >= 0 (inside) or <= 0 (!inside).
Polygon2 clipHalfPlane(const Polygon2& p, const DVec2& n, double c, bool inside) {
    Polygon2 out;
    out.overflow = p.overflow;
    const double sign = inside ? 1.0 : -1.0;
    for (int i = 0; i < p.n; ++i) {
        const DVec2& a = p.v[i];
        const DVec2& b = p.v[(i + 1) % p.n];
        const double da = sign * (glm::dot(n, a) + c), db = sign * (glm::dot(n, b) + c);
        if (da >= 0.0) out.push(a);
        if ((da >= 0.0) != (db >= 0.0)) out.push(a + (b - a) * (da / (da - db)));
    }
    return out;
}

// Appends to `out` the pieces of convex `piece` outside convex counter-clockwise `cover`.
void subtract(const Polygon2& piece, const Polygon2& cover, double min_area, std::vector<Polygon2>& out) {
    Polygon2 rest = piece;
    for (int i = 0; i < cover.n && rest.n >= 3; ++i) {
        const DVec2& a = cover.v[i];
        const DVec2& b = cover.v[(i + 1) % cover.n];
        const DVec2 n(a.y - b.y, b.x - a.x);  // inward for counter-clockwise
        const double c = -glm::dot(n, a);
        Polygon2 outside = clipHalfPlane(rest, n, c, false);
        if (outside.n >= 3 && (outside.overflow || std::abs(area(outside)) > min_area)) out.push_back(outside);
        rest = clipHalfPlane(rest, n, c, true);
    }
}

}  // namespace

namespace {

// The convex hull of `points` (Andrew's monotone chain), counter-clockwise; n = 0 when it has
// more than kMaxCorners corners.
Polygon2 convexHull(std::vector<DVec2>& points) {
    std::sort(points.begin(), points.end(), [](const DVec2& a, const DVec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    std::vector<DVec2> hull(2 * points.size());
    size_t k = 0;
    auto turn = [](const DVec2& o, const DVec2& a, const DVec2& b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    for (size_t i = 0; i < points.size(); ++i) {
        while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
        hull[k++] = points[i];
    }
    for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
        hull[k++] = points[i];
    }
    Polygon2 out;
    if (k < 2 || k - 1 > size_t(kMaxCorners)) return out;
    for (size_t i = 0; i + 1 < k; ++i) out.push(hull[i]);
    return out;
}

}  // namespace

bool patchCovered(const DVec3& apex, std::span<const DVec3> boundary, std::span<const std::array<DVec3, 3>> triangles,
                  std::span<const size_t> face_ends) {
    if (boundary.empty() || triangles.empty()) return false;
    DVec3 sum(0.0);
    for (const DVec3& d : boundary) sum += d;
    if (!(glm::length(sum) > 0.0)) return false;
    const DVec3 axis = glm::normalize(sum);
    DVec3 e1, e2;
    tangentFrame(axis, e1, e2);
    // The patch's bounding rectangle in the gnomonic plane at distance 1 along `axis`.
    DVec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const DVec3& d : boundary) {
        const double along = glm::dot(d, axis);
        if (!(along > 0.35)) return false;  // wider than about 140 degrees
        const DVec2 g(glm::dot(d, e1) / along, glm::dot(d, e2) / along);
        lo = glm::min(lo, g), hi = glm::max(hi, g);
    }
    const DVec2 margin = 0.02 * (hi - lo) + DVec2(1e-12);
    lo -= margin, hi += margin;
    const double rectangle_area = (hi.x - lo.x) * (hi.y - lo.y);
    const double min_area = 1e-9 * rectangle_area;
    Polygon2 rectangle;
    for (const DVec2& corner : {lo, DVec2(hi.x, lo.y), hi, DVec2(lo.x, hi.y)}) rectangle.push(corner);
    std::vector<Polygon2> pieces{rectangle}, left;

    // The triangle relative to the apex, cut to the half-space in front of it, projected (at
    // most 4 corners: a triangle cut by one plane), counter-clockwise; n = 0 when seen edge on.
    auto project = [&](const std::array<DVec3, 3>& triangle) {
        double scale = 0.0;
        std::array<DVec3, 3> q;
        for (int i = 0; i < 3; ++i) q[i] = triangle[i] - apex, scale = std::max(scale, glm::length(q[i]));
        const double front = 1e-9 * scale;
        auto onPlane = [&](const DVec3& x) {
            const double along = glm::dot(x, axis);
            return DVec2(glm::dot(x, e1) / along, glm::dot(x, e2) / along);
        };
        Polygon2 projected;
        for (int i = 0; i < 3; ++i) {
            const DVec3& a = q[i];
            const DVec3& b = q[(i + 1) % 3];
            const double da = glm::dot(a, axis) - front, db = glm::dot(b, axis) - front;
            if (da >= 0.0) projected.push(onPlane(a));
            if ((da >= 0.0) != (db >= 0.0)) projected.push(onPlane(a + (b - a) * (da / (da - db))));
        }
        const double signed_area = projected.n >= 3 ? area(projected) : 0.0;
        if (std::abs(signed_area) <= min_area) projected.n = 0;
        else if (signed_area < 0.0) std::reverse(projected.v.begin(), projected.v.begin() + projected.n);
        return projected;
    };
    // Takes `cover` out of every piece left; true once nothing is.
    auto takeOut = [&](const Polygon2& cover) {
        DVec2 cover_lo(std::numeric_limits<double>::infinity()), cover_hi(-std::numeric_limits<double>::infinity());
        for (int i = 0; i < cover.n; ++i) cover_lo = glm::min(cover_lo, cover.v[i]), cover_hi = glm::max(cover_hi, cover.v[i]);
        if (cover_hi.x <= lo.x || cover_lo.x >= hi.x || cover_hi.y <= lo.y || cover_lo.y >= hi.y) return false;
        left.clear();
        for (const Polygon2& piece : pieces) subtract(piece, cover, min_area, left);
        pieces.swap(left);
        return pieces.empty();
    };

    std::vector<Polygon2> face;
    std::vector<DVec2> corners;
    for (size_t start = 0, f = 0; start < triangles.size(); ++f) {
        const size_t end = f < face_ends.size() ? std::min(face_ends[f], triangles.size()) : start + 1;
        if (end <= start) break;
        // A convex face (a quad's two triangles) is taken out whole: one polygon, no seam.
        face.clear(), corners.clear();
        double face_area = 0.0;
        for (size_t t = start; t < end; ++t) {
            const Polygon2 projected = project(triangles[t]);
            if (projected.n == 0) continue;
            face.push_back(projected);
            face_area += area(projected);
            corners.insert(corners.end(), projected.v.begin(), projected.v.begin() + projected.n);
        }
        start = end;
        if (face.empty()) continue;
        if (face.size() > 1) {
            const Polygon2 hull = convexHull(corners);
            if (hull.n >= 3 && std::abs(area(hull) - face_area) <= 1e-9 * std::max(face_area, rectangle_area)) {
                face.assign(1, hull);
            }
        }
        for (const Polygon2& cover : face) {
            if (takeOut(cover)) return true;
            for (const Polygon2& piece : pieces)
                if (piece.overflow) return false;  // too many corners to follow: not proven
        }
    }
    return false;
}

}  // namespace radbake
