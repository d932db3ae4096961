#include "radiosity/form_factor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "geometry/polygon.h"

namespace radbake {
namespace {

// Gauss-Legendre rules on [0, 1] (abscissae, weights), orders 1 to 4.
struct GaussRule {
    int count;
    double x[4];
    double w[4];
};
constexpr GaussRule kGauss[5] = {
    {0, {}, {}},
    {1, {0.5}, {1.0}},
    {2, {0.5 - 0.28867513459481288225, 0.5 + 0.28867513459481288225}, {0.5, 0.5}},
    {3, {0.5 - 0.38729833462074168852, 0.5, 0.5 + 0.38729833462074168852},
     {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0}},
    {4,
     {0.5 - 0.43056815579702628811, 0.5 - 0.16999052179242813331, 0.5 + 0.16999052179242813331,
      0.5 + 0.43056815579702628811},
     {0.17392742256872692869, 0.32607257743127307131, 0.32607257743127307131, 0.17392742256872692869}},
};

double segmentDistance(const DVec3& p, const DVec3& a, const DVec3& b) {
    const DVec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

struct Accumulator {
    double sum = 0.0;
    double area = 0.0;
    double f_min = std::numeric_limits<double>::max();
    double f_max = 0.0;
    int samples = 0;
};

void sample(const DVec3& p, double weight, const DVec3& normal, const PolygonView& source,
            Accumulator& acc) {
    const double f = pointPolygonFormFactor(p, normal, source.vertices, source.normal);
    acc.sum += weight * f;
    acc.area += weight;
    acc.f_min = std::min(acc.f_min, f);
    acc.f_max = std::max(acc.f_max, f);
    ++acc.samples;
}

// Tensor Gauss rule on the bilinear map of a planar quad; the weights include the Jacobian
// (linear in u and v), so they sum to the quad's area exactly.
void gaussQuad(std::span<const DVec3> q, const DVec3& normal, const PolygonView& source, int order,
               Accumulator& acc) {
    const GaussRule& rule = kGauss[std::clamp(order, 1, 4)];
    for (int i = 0; i < rule.count; ++i)
        for (int j = 0; j < rule.count; ++j) {
            const double u = rule.x[i], v = rule.x[j];
            const DVec3 p = (1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] + (1 - u) * v * q[3];
            const DVec3 du = (1 - v) * (q[1] - q[0]) + v * (q[2] - q[3]);
            const DVec3 dv = (1 - u) * (q[3] - q[0]) + u * (q[2] - q[1]);
            const double jacobian = glm::dot(glm::cross(du, dv), normal);
            sample(p, rule.w[i] * rule.w[j] * jacobian, normal, source, acc);
        }
}

// A receiver cell whose edge lies on the source (a shared edge of adjacent elements, or a
// wall standing on a floor) sees a point form factor with a v log v singularity across that
// edge. Splitting towards it isotropically converges slowly (every level halves the error of
// a strip yet doubles its cells: 2e-5 relative at depth 9 on unit squares) and the error is the
// same fraction of every touching link at every level of the hierarchy, so in a closed room it
// becomes a row-sum deficit that 1 / (1 - rho) amplifies (3.7 % at rho = 0.999). A geometric
// grading across the edge (intervals [2^-k-1, 2^-k] in v, and in u towards a corner where the
// source ends) integrates unit squares to 2.5e-6 relative at order 3 with 369 points; the
// error no longer depends on kGradedLevels beyond 6 (the coarse intervals dominate).
constexpr int kGradedLevels = 6;
// A cell that touches a smaller source along part of an edge may split this many levels past
// max_depth (source and receiver sizes within 2^4 of each other in a hierarchy).
constexpr int kTouchingExtraDepth = 4;

// Index i of the cell edge (cell[i], cell[i + 1]) lying on the source, or -1. "On": both ends
// within a float rounding of the cell's size (shared vertices may come from different transforms).
int touchingEdge(std::span<const DVec3> cell, double radius, const PolygonView& source) {
    const double tolerance = 1e-7 * radius;
    std::array<bool, 4> on{};
    for (size_t i = 0; i < 4; ++i) on[i] = pointPolygonDistance(cell[i], source) <= tolerance;
    for (int i = 0; i < 4; ++i)
        if (on[i] && on[(i + 1) % 4]) return i;
    return -1;
}

// Intervals of [0, 1] graded geometrically down to `width` towards 0 (to_lo) and/or 1 (to_hi).
void gradedIntervals(double width, bool to_lo, bool to_hi, std::vector<std::pair<double, double>>& out) {
    out.clear();
    if (!to_lo && !to_hi) {
        out.push_back({0.0, 1.0});
        return;
    }
    if (to_lo && to_hi) out.push_back({0.25, 0.75});
    else out.push_back(to_lo ? std::pair{0.5, 1.0} : std::pair{0.0, 0.5});
    for (double w = to_lo && to_hi ? 0.25 : 0.5;; w *= 0.5) {
        const bool last = w <= width;
        if (to_lo) out.push_back({last ? 0.0 : 0.5 * w, w});
        if (to_hi) out.push_back({1.0 - w, last ? 1.0 : 1.0 - 0.5 * w});
        if (last) break;
    }
}

// True when the source continues past the cell corner `corner` along the edge direction
// `along` (from the other end towards it): no corner singularity there.
bool sourceContinues(const DVec3& corner, const DVec3& along, double radius, const PolygonView& source) {
    const DVec3 beyond = corner + (1e-4 * radius / std::max(glm::length(along), 1e-300)) * along;
    return pointPolygonDistance(beyond, source) <= 1e-7 * radius;
}

// Tensor Gauss rule on the quad (q0 q1 q2 q3, rotated so that edge 0-1 touches the source)
// with v graded geometrically towards that edge and, where the source ends at a corner of
// that edge (F falls from 1/2 to 1/4 within a distance v of it), u graded towards that corner
// down to the v interval's width.
void gradedQuad(std::span<const DVec3> cell, int edge, double radius, const DVec3& normal, const PolygonView& source,
                int order, Accumulator& acc) {
    std::array<DVec3, 4> q;
    for (int i = 0; i < 4; ++i) q[i] = cell[(edge + i) % 4];
    const bool corner_lo = !sourceContinues(q[0], q[0] - q[1], radius, source);
    const bool corner_hi = !sourceContinues(q[1], q[1] - q[0], radius, source);
    const GaussRule& rule = kGauss[std::clamp(order, 1, 4)];
    std::vector<std::pair<double, double>> u_intervals;
    for (int level = 0; level <= kGradedLevels; ++level) {
        const double v_hi = std::ldexp(1.0, -level);
        const double v_lo = level == kGradedLevels ? 0.0 : 0.5 * v_hi;
        gradedIntervals(v_hi, corner_lo, corner_hi, u_intervals);
        for (const auto& [u_lo, u_hi] : u_intervals)
            for (int i = 0; i < rule.count; ++i)
                for (int j = 0; j < rule.count; ++j) {
                    const double u = u_lo + (u_hi - u_lo) * rule.x[i], v = v_lo + (v_hi - v_lo) * rule.x[j];
                    const DVec3 p =
                        (1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] + (1 - u) * v * q[3];
                    const DVec3 du = (1 - v) * (q[1] - q[0]) + v * (q[2] - q[3]);
                    const DVec3 dv = (1 - u) * (q[3] - q[0]) + u * (q[2] - q[1]);
                    const double jacobian = glm::dot(glm::cross(du, dv), normal);
                    sample(p, rule.w[i] * rule.w[j] * (u_hi - u_lo) * (v_hi - v_lo) * jacobian, normal, source,
                           acc);
                }
    }
}

void integrate(std::span<const DVec3> cell, const DVec3& normal, const PolygonView& source,
               const QuadratureOptions& options, int depth, Accumulator& acc) {
    DVec3 centre(0.0);
    for (const DVec3& p : cell) centre += p;
    centre /= static_cast<double>(cell.size());
    double radius = 0.0;
    for (const DVec3& p : cell) radius = std::max(radius, glm::length(p - centre));
    const bool far = pointPolygonDistance(centre, source) - radius > options.near_ratio * radius;
    bool touches = false;
    if (cell.size() == 4 && !far) {
        const int edge = touchingEdge(cell, radius, source);
        if (edge >= 0) {
            gradedQuad(cell, edge, radius, normal, source, options.order, acc);
            return;
        }
        // A vertex on the source (part of an edge on a smaller source, or a corner): split on,
        // until a cell's edge lies on it or the corner's share is small.
        for (const DVec3& p : cell) touches = touches || pointPolygonDistance(p, source) <= 1e-7 * radius;
    }
    const int max_depth = touches ? options.max_depth + kTouchingExtraDepth : options.max_depth;
    if (cell.size() == 4 && (far || depth >= max_depth)) {
        gaussQuad(cell, normal, source, options.order, acc);
        return;
    }
    for (const auto& child : splitPolygon(cell)) integrate(child, normal, source, options, depth + 1, acc);
}

}  // namespace

double pointPolygonFormFactor(const DVec3& point, const DVec3& normal, std::span<const DVec3> source,
                              const DVec3& source_normal) {
    const size_t n = source.size();
    if (n < 3 || n >= kMaxClip - 1) return 0.0;
    // The receiver point must be strictly in front of the source (light leaves the front).
    if (!(glm::dot(source_normal, point - source[0]) > 0.0)) return 0.0;
    std::array<DVec3, kMaxClip> clipped;
    const size_t count = clipAboveHorizon(point, normal, source, clipped.data());
    if (count < 3) return 0.0;
    double sum = 0.0;
    std::array<DVec3, kMaxClip> dirs;
    for (size_t i = 0; i < count; ++i) dirs[i] = clipped[i] - point;
    for (size_t i = 0; i < count; ++i) {
        const DVec3& r0 = dirs[i];
        const DVec3& r1 = dirs[i + 1 == count ? 0 : i + 1];  // no division: this is the hottest loop
        const DVec3 c = glm::cross(r0, r1);
        const double c_len = glm::length(c);
        if (!(c_len > 0.0)) continue;  // a vertex at the point, or collinear: no area swept
        const double angle = atan2Upper(c_len, glm::dot(r0, r1));
        sum += angle * glm::dot(normal, c) / c_len;
    }
    return std::abs(sum) / (2.0 * kPi);
}

size_t clipAboveHorizon(const DVec3& point, const DVec3& normal, std::span<const DVec3> loop, DVec3* out) {
    const size_t n = loop.size();
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        const DVec3& a = loop[i];
        const DVec3& b = loop[i + 1 == n ? 0 : i + 1];
        const double da = glm::dot(normal, a - point);
        const double db = glm::dot(normal, b - point);
        if (da >= 0.0) out[count++] = a;
        if ((da > 0.0 && db < 0.0) || (da < 0.0 && db > 0.0)) out[count++] = a + (da / (da - db)) * (b - a);
    }
    return count;
}

double pointPolygonDistance(const DVec3& point, const PolygonView& polygon) {
    const auto& v = polygon.vertices;
    const double height = glm::dot(point - v[0], polygon.normal);
    const DVec3 projected = point - height * polygon.normal;
    bool inside = true;
    for (size_t i = 0; i < v.size() && inside; ++i) {
        const DVec3 edge = v[(i + 1) % v.size()] - v[i];
        inside = glm::dot(glm::cross(edge, projected - v[i]), polygon.normal) >= 0.0;
    }
    if (inside) return std::abs(height);
    double best = std::numeric_limits<double>::max();
    for (size_t i = 0; i < v.size(); ++i) best = std::min(best, segmentDistance(point, v[i], v[(i + 1) % v.size()]));
    return best;
}

bool facing(const PolygonView& receiver, const PolygonView& source) {
    // Tolerance: 1e-9 of the pair's size, so coplanar neighbours (rounding only) never face.
    const double tolerance = 1e-9 * (receiver.radius + source.radius + glm::length(receiver.centroid - source.centroid));
    bool source_ahead = false, receiver_ahead = false;
    for (const DVec3& p : source.vertices)
        source_ahead = source_ahead || glm::dot(receiver.normal, p - receiver.vertices[0]) > tolerance;
    for (const DVec3& p : receiver.vertices)
        receiver_ahead = receiver_ahead || glm::dot(source.normal, p - source.vertices[0]) > tolerance;
    return source_ahead && receiver_ahead;
}

FormFactorEstimate polygonFormFactor(const PolygonView& receiver, const PolygonView& source,
                                     const QuadratureOptions& options) {
    FormFactorEstimate estimate;
    if (!facing(receiver, source)) return estimate;
    Accumulator acc;
    integrate(receiver.vertices, receiver.normal, source, options, 0, acc);
    if (acc.area > 0.0) estimate.form_factor = acc.sum / acc.area;
    estimate.f_min = acc.samples > 0 ? acc.f_min : 0.0;
    estimate.f_max = acc.f_max;
    estimate.samples = acc.samples;
    return estimate;
}

double gaussAveragedFormFactor(std::span<const DVec3> q, const DVec3& quad_normal, std::span<const DVec3> source,
                               const DVec3& source_normal) {
    constexpr double kG = 0.28867513459481288225;  // 1 / (2 sqrt 3): Gauss points at 0.5 -+ kG
    double sum = 0.0, weight = 0.0;
    for (const double u : {0.5 - kG, 0.5 + kG})
        for (const double v : {0.5 - kG, 0.5 + kG}) {
            const DVec3 p = (1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] + (1 - u) * v * q[3];
            const DVec3 du = (1 - v) * (q[1] - q[0]) + v * (q[2] - q[3]);
            const DVec3 dv = (1 - u) * (q[3] - q[0]) + u * (q[2] - q[1]);
            const double w = std::abs(glm::dot(glm::cross(du, dv), quad_normal));
            sum += w * pointPolygonFormFactor(p, quad_normal, source, source_normal);
            weight += w;
        }
    return weight > 0.0 ? sum / weight : 0.0;
}

}  // namespace radbake
