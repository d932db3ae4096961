#include "geometry/cone_cover.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/polygon.h"

namespace radbake {
namespace {

using Polygon2 = std::vector<DVec2>;

double area(const Polygon2& p) {
    double twice = 0.0;
    for (size_t i = 0; i < p.size(); ++i) {
        const DVec2& a = p[i];
        const DVec2& b = p[(i + 1) % p.size()];
        twice += a.x * b.y - a.y * b.x;
    }
    return 0.5 * twice;
}

// The part of convex `p` where n . x + c >= 0 (inside) or <= 0 (!inside).
Polygon2 clipHalfPlane(const Polygon2& p, const DVec2& n, double c, bool inside) {
    Polygon2 out;
    const double sign = inside ? 1.0 : -1.0;
    for (size_t i = 0; i < p.size(); ++i) {
        const DVec2& a = p[i];
        const DVec2& b = p[(i + 1) % p.size()];
        const double da = sign * (glm::dot(n, a) + c), db = sign * (glm::dot(n, b) + c);
        if (da >= 0.0) out.push_back(a);
        if ((da >= 0.0) != (db >= 0.0)) out.push_back(a + (b - a) * (da / (da - db)));
    }
    return out;
}

// Appends to `out` the pieces of convex `piece` outside convex counter-clockwise `cover`.
void subtract(const Polygon2& piece, const Polygon2& cover, double min_area, std::vector<Polygon2>& out) {
    Polygon2 rest = piece;
    for (size_t i = 0; i < cover.size() && rest.size() >= 3; ++i) {
        const DVec2& a = cover[i];
        const DVec2& b = cover[(i + 1) % cover.size()];
        const DVec2 n(a.y - b.y, b.x - a.x);  // inward for counter-clockwise
        const double c = -glm::dot(n, a);
        Polygon2 outside = clipHalfPlane(rest, n, c, false);
        if (outside.size() >= 3 && std::abs(area(outside)) > min_area) out.push_back(std::move(outside));
        rest = clipHalfPlane(rest, n, c, true);
    }
}

}  // namespace

bool patchCovered(const DVec3& apex, std::span<const DVec3> boundary, std::span<const std::array<DVec3, 3>> triangles) {
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
    std::vector<Polygon2> pieces{{lo, {hi.x, lo.y}, hi, {lo.x, hi.y}}};

    for (const std::array<DVec3, 3>& triangle : triangles) {
        // The triangle relative to the apex, cut to the half-space in front of it, projected.
        double scale = 0.0;
        std::array<DVec3, 3> q;
        for (int i = 0; i < 3; ++i) q[i] = triangle[i] - apex, scale = std::max(scale, glm::length(q[i]));
        const double front = 1e-9 * scale;
        Polygon2 projected;
        for (int i = 0; i < 3; ++i) {
            const DVec3& a = q[i];
            const DVec3& b = q[(i + 1) % 3];
            const double da = glm::dot(a, axis) - front, db = glm::dot(b, axis) - front;
            auto project = [&](const DVec3& x) {
                const double along = glm::dot(x, axis);
                return DVec2(glm::dot(x, e1) / along, glm::dot(x, e2) / along);
            };
            if (da >= 0.0) projected.push_back(project(a));
            if ((da >= 0.0) != (db >= 0.0)) projected.push_back(project(a + (b - a) * (da / (da - db))));
        }
        if (projected.size() < 3) continue;
        const double signed_area = area(projected);
        if (std::abs(signed_area) <= min_area) continue;  // seen edge on
        if (signed_area < 0.0) std::reverse(projected.begin(), projected.end());
        std::vector<Polygon2> left;
        for (const Polygon2& piece : pieces) subtract(piece, projected, min_area, left);
        pieces.swap(left);
        if (pieces.empty()) return true;
    }
    return false;
}

}  // namespace radbake
