#include "geometry/polygon.h"

#include <algorithm>
#include <cmath>

namespace radbake {

DVec3 newellNormal(std::span<const DVec3> loop) {
    DVec3 n(0.0);
    const size_t count = loop.size();
    for (size_t i = 0; i < count; ++i) {
        const DVec3& a = loop[i];
        const DVec3& b = loop[(i + 1) % count];
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    return n;
}

Plane planeFromPoints(const DVec3& a, const DVec3& b, const DVec3& c) {
    Plane plane;
    const DVec3 n = glm::cross(b - a, c - a);
    const double length = glm::length(n);
    plane.normal = length > 0.0 ? n / length : DVec3(0.0);
    plane.offset = -glm::dot(plane.normal, a);
    return plane;
}

Plane planeFromPolygon(std::span<const DVec3> loop) {
    Plane plane;
    const DVec3 n = newellNormal(loop);
    const double length = glm::length(n);
    plane.normal = length > 0.0 ? n / length : DVec3(0.0);
    plane.offset = -glm::dot(plane.normal, polygonCentroid(loop));
    return plane;
}

double polygonArea(std::span<const DVec3> loop) { return 0.5 * glm::length(newellNormal(loop)); }

DVec3 polygonCentroid(std::span<const DVec3> loop) {
    if (loop.empty()) return DVec3(0.0);
    DVec3 mean(0.0);
    for (const DVec3& p : loop) mean += p;
    mean /= double(loop.size());
    // Fan from the vertex mean: triangle centroids weighted by signed area along the normal.
    const DVec3 n = newellNormal(loop);
    const double n2 = glm::dot(n, n);
    if (n2 == 0.0) return mean;
    DVec3 sum(0.0);
    double weight = 0.0;
    for (size_t i = 0; i < loop.size(); ++i) {
        const DVec3& a = loop[i];
        const DVec3& b = loop[(i + 1) % loop.size()];
        const double w = glm::dot(glm::cross(a - mean, b - mean), n);
        sum += w * (mean + a + b) / 3.0;
        weight += w;
    }
    return weight != 0.0 ? sum / weight : mean;
}

bool pointInConvexPolygon(std::span<const DVec3> loop, const DVec3& normal, const DVec3& p,
                          double tolerance) {
    const size_t count = loop.size();
    if (count == 0) return false;
    for (size_t i = 0; i < count; ++i) {
        const DVec3& a = loop[i];
        const DVec3& b = loop[(i + 1) % count];
        const DVec3 edge = b - a;
        const double length = glm::length(edge);
        if (length == 0.0) continue;
        // Signed distance of p to the edge's line, positive on the inner (left) side.
        const double distance = glm::dot(glm::cross(edge, p - a), normal) / length;
        if (distance < -tolerance) return false;
    }
    return true;
}

namespace {

// Turn at b (from a->b to b->c) around n: > 0 left, scaled as a distance (of c from the
// line a-b) so it compares with a length tolerance.
double turnDistance(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& n) {
    const DVec3 e1 = b - a;
    const double length = glm::length(e1);
    if (length == 0.0) return 0.0;
    return glm::dot(glm::cross(e1, c - b), n) / length;
}

}  // namespace

bool isConvexPolygon(std::span<const DVec3> loop, const DVec3& normal, double tolerance) {
    const size_t count = loop.size();
    if (count < 3) return false;
    double winding = 0.0;  // sum of turning angles: one full turn for a simple convex loop
    for (size_t i = 0; i < count; ++i) {
        const DVec3& a = loop[(i + count - 1) % count];
        const DVec3& b = loop[i];
        const DVec3& c = loop[(i + 1) % count];
        const double turn = turnDistance(a, b, c, normal);
        if (turn < -tolerance) return false;
        const DVec3 e1 = b - a, e2 = c - b;
        // A straight-back reversal has no turn but is not convex.
        if (std::abs(turn) <= tolerance && glm::dot(e1, e2) < 0.0) return false;
        winding += std::atan2(glm::dot(glm::cross(e1, e2), normal), glm::dot(e1, e2));
    }
    return std::abs(winding - 2.0 * kPi) < 0.5;
}

std::vector<DVec3> removeCollinear(std::span<const DVec3> loop, double tolerance) {
    std::vector<DVec3> out(loop.begin(), loop.end());
    // Drop repeats first, then vertices within tolerance of their neighbours' segment; repeat
    // until stable since removing one can expose another.
    bool changed = true;
    while (changed && out.size() > 3) {
        changed = false;
        for (size_t i = 0; i < out.size() && out.size() > 3; ++i) {
            const DVec3& a = out[(i + out.size() - 1) % out.size()];
            const DVec3& b = out[i];
            const DVec3& c = out[(i + 1) % out.size()];
            const DVec3 ac = c - a;
            const double length = glm::length(ac);
            bool drop = glm::length(b - a) <= tolerance;
            if (!drop && length > 0.0) {
                const double t = glm::dot(b - a, ac) / (length * length);
                const double off = glm::length(glm::cross(ac, b - a)) / length;
                drop = off <= tolerance && t > 0.0 && t < 1.0;
            }
            if (drop) {
                out.erase(out.begin() + long(i));
                changed = true;
                --i;
            }
        }
    }
    return out;
}

void tangentFrame(const DVec3& n, DVec3& u, DVec3& v) {
    // Pick the world axis least aligned with n so the cross product is well conditioned.
    const DVec3 a = std::abs(n.x) < 0.57 ? DVec3(1, 0, 0) : (std::abs(n.y) < 0.57 ? DVec3(0, 1, 0) : DVec3(0, 0, 1));
    u = glm::normalize(glm::cross(a, n));
    v = glm::cross(n, u);
}

double pointExtent(std::span<const DVec3> points) {
    if (points.empty()) return 0.0;
    DVec3 lo = points[0], hi = points[0];
    for (const DVec3& p : points) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const DVec3 e = hi - lo;
    return std::max(e.x, std::max(e.y, e.z));
}

}  // namespace radbake
