// Brute-force segment tests (reference for the property tests and benchmarks).
#include "visibility/reference.h"

#include <algorithm>
#include <cmath>

namespace radbake {
namespace {

// Clip the parameter range [t0, t1] of a + t (b - a) to {plane(x) < 0} (strict) or <= 0.
bool clipToPlane(double da, double db, bool strict, double& t0, double& t1) {
    const bool a_in = strict ? da < 0.0 : da <= 0.0;
    const bool b_in = strict ? db < 0.0 : db <= 0.0;
    if (a_in && b_in) return true;
    if (!a_in && !b_in) return false;
    const double t = da / (da - db);  // where the plane is crossed
    if (a_in) {
        t1 = std::min(t1, t);
    } else {
        t0 = std::max(t0, t);
    }
    return strict ? t0 < t1 : t0 <= t1;
}

bool closedHit(const DVec3& a, const DVec3& b, const ConvexPart& part, bool strict) {
    double t0 = 0.0, t1 = 1.0;
    for (const Plane& plane : part.planes) {
        if (!clipToPlane(plane.eval(a), plane.eval(b), strict, t0, t1)) return false;
    }
    return strict ? t0 < t1 : t0 <= t1;
}

// Outward edge planes of a flat part's polygon (perpendicular to it), from its centroid.
Plane edgePlane(const ConvexPart& part, size_t k, const DVec3& centroid) {
    const size_t n = part.vertices.size();
    const DVec3& v0 = part.vertices[k];
    const DVec3& v1 = part.vertices[(k + 1) % n];
    DVec3 g = glm::cross(v1 - v0, part.planes[0].normal);
    if (glm::dot(g, centroid - v0) > 0.0) g = -g;
    return Plane{g, -glm::dot(g, v0)};
}

bool flatHit(const DVec3& a, const DVec3& b, const ConvexPart& part, bool strict) {
    if (part.planes.empty() || part.vertices.size() < 3) return false;
    const Plane& plane = part.planes[0];
    const double da = plane.eval(a), db = plane.eval(b);
    DVec3 centroid(0.0);
    for (const DVec3& v : part.vertices) centroid += v;
    centroid /= static_cast<double>(part.vertices.size());
    const size_t n = part.vertices.size();
    if (da == 0.0 && db == 0.0) {
        // Lying in the plate's plane: never through it (strict); contact when the segment
        // meets the polygon (non-strict): clip it against the edge planes.
        if (strict) return false;
        double t0 = 0.0, t1 = 1.0;
        for (size_t k = 0; k < n; ++k) {
            const Plane edge = edgePlane(part, k, centroid);
            if (!clipToPlane(edge.eval(a), edge.eval(b), false, t0, t1)) return false;
        }
        return t0 <= t1;
    }
    if (strict) {
        if (!((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0))) return false;
    } else if ((da > 0.0 && db > 0.0) || (da < 0.0 && db < 0.0)) {
        return false;
    }
    const DVec3 p = a + (da / (da - db)) * (b - a);
    for (size_t k = 0; k < n; ++k) {
        const double side = edgePlane(part, k, centroid).eval(p);
        if (strict ? side >= 0.0 : side > 0.0) return false;
    }
    return true;
}

}  // namespace

bool segmentHitsPart(const DVec3& a, const DVec3& b, const ConvexPart& part, bool strict) {
    return part.closed ? closedHit(a, b, part, strict) : flatHit(a, b, part, strict);
}

std::vector<DVec3> polygonSamplePoints(std::span<const DVec3> polygon, int subdivisions) {
    std::vector<DVec3> points(polygon.begin(), polygon.end());
    const int g = std::max(subdivisions, 1);
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
        const DVec3& p0 = polygon[0];
        const DVec3& p1 = polygon[k];
        const DVec3& p2 = polygon[k + 1];
        for (int i = 0; i <= g; ++i) {
            for (int j = 0; i + j <= g; ++j) {
                const int l = g - i - j;
                if (i == g || j == g || l == g) continue;  // the corners are already in
                points.push_back((static_cast<double>(i) * p1 + static_cast<double>(j) * p2 +
                                  static_cast<double>(l) * p0) /
                                 static_cast<double>(g));
            }
        }
    }
    return points;
}

SegmentCount countSegmentHits(std::span<const DVec3> source_samples,
                              std::span<const DVec3> receiver_samples, const ConvexPart& part) {
    SegmentCount count;
    for (const DVec3& a : source_samples) {
        for (const DVec3& b : receiver_samples) {
            ++count.segments;
            if (segmentHitsPart(a, b, part, true)) ++count.hits_strict;
            if (segmentHitsPart(a, b, part, false)) ++count.hits_any;
        }
    }
    return count;
}

}  // namespace radbake
