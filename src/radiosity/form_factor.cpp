#include "radiosity/form_factor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "geometry/polygon.h"

namespace radbake {
namespace {

// Two doubles, one SSE2 register: GCC vector extensions, lane-wise IEEE operations, so a lane
// computes exactly what the scalar code computes. (Four lanes spill on SSE2 and are slower than
// the scalar code; AVX2 adds little to two.)
using Lanes = double __attribute__((vector_size(2 * sizeof(double))));
constexpr size_t kLanes = 2;

// atan2Upper (core/math.h) on two lanes, its branches taken as selects: the same operations
// in the same order on every lane, hence the same bits.
[[gnu::always_inline]] inline Lanes atan2UpperLanes(const Lanes& y, const Lanes& x) {
    const Lanes ax = x < 0.0 ? -x : x;
    const auto steep = y > ax;
    const Lanes a = steep ? ax : y, b = steep ? y : ax;
    constexpr double kTanPi8 = 0.41421356237309504880;
    const auto reduce = a > kTanPi8 * b;
    const Lanes u = reduce ? (a - b) / (a + b) : a / b;
    Lanes angle = atanSmall(u);
    angle = reduce ? angle + 0.25 * kPi : angle;
    angle = steep ? 0.5 * kPi - angle : angle;
    return x < 0.0 ? kPi - angle : angle;
}

// The terms of the contour integral for two edges (r0 -> r1 in each lane, seen from the
// point): angle x (normal . (r0 x r1)) / |r0 x r1|, and |r0 x r1| (0: the edge adds nothing).
[[gnu::always_inline]] inline void edgeTermLanes(const Lanes& x0, const Lanes& y0, const Lanes& z0, const Lanes& x1,
                                                 const Lanes& y1, const Lanes& z1, const DVec3& normal, Lanes& term,
                                                 Lanes& c_len) {
    const Lanes cx = y0 * z1 - y1 * z0, cy = z0 * x1 - z1 * x0, cz = x0 * y1 - x1 * y0;
    c_len = cx * cx + cy * cy + cz * cz;
    for (size_t k = 0; k < kLanes; ++k) c_len[k] = std::sqrt(c_len[k]);
    const Lanes angle = atan2UpperLanes(c_len, x0 * x1 + y0 * y1 + z0 * z1);
    term = angle * (normal.x * cx + normal.y * cy + normal.z * cz) / c_len;
}

// True when pointPolygonFormFactor at the point reads `source` whole: in front of it, every
// vertex above the horizon (no clip), a polygon it takes.
bool seenWhole(const DVec3& point, const DVec3& normal, const PolygonView& source) {
    const size_t n = source.vertices.size();
    if (n < 3 || n >= kMaxClip - 1) return false;
    if (!(glm::dot(source.normal, point - source.vertices[0]) > 0.0)) return false;
    for (const DVec3& v : source.vertices)
        if (!(glm::dot(normal, v - point) >= 0.0)) return false;
    return true;
}

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

// One cell's Gauss points and weights, at most 4 x 4.
struct CellSamples {
    std::array<DVec3, 16> points;
    std::array<double, 16> weights;
    size_t count = 0;
    void add(const DVec3& p, double weight) { points[count] = p, weights[count++] = weight; }
};

// The cell's samples into the accumulator, in the order they were added.
void sample(const CellSamples& cell, const DVec3& normal, const PolygonView& source, Accumulator& acc) {
    std::array<double, 16> f;
    pointPolygonFormFactors(std::span<const DVec3>(cell.points.data(), cell.count), normal, source.vertices,
                            source.normal, f.data());
    for (size_t k = 0; k < cell.count; ++k) {
        acc.sum += cell.weights[k] * f[k];
        acc.area += cell.weights[k];
        acc.f_min = std::min(acc.f_min, f[k]);
        acc.f_max = std::max(acc.f_max, f[k]);
        ++acc.samples;
    }
}

// Tensor Gauss rule on the bilinear map of a planar quad; the weights include the Jacobian
// (linear in u and v), so they sum to the quad's area exactly.
void gaussQuad(std::span<const DVec3> q, const DVec3& normal, const PolygonView& source, int order,
               Accumulator& acc) {
    const GaussRule& rule = kGauss[std::clamp(order, 1, 4)];
    CellSamples samples;
    for (int i = 0; i < rule.count; ++i)
        for (int j = 0; j < rule.count; ++j) {
            const double u = rule.x[i], v = rule.x[j];
            const DVec3 p = (1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] + (1 - u) * v * q[3];
            const DVec3 du = (1 - v) * (q[1] - q[0]) + v * (q[2] - q[3]);
            const DVec3 dv = (1 - u) * (q[3] - q[0]) + u * (q[2] - q[1]);
            const double jacobian = glm::dot(glm::cross(du, dv), normal);
            samples.add(p, rule.w[i] * rule.w[j] * jacobian);
        }
    sample(samples, normal, source, acc);
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
        for (const auto& [u_lo, u_hi] : u_intervals) {
            CellSamples samples;
            for (int i = 0; i < rule.count; ++i)
                for (int j = 0; j < rule.count; ++j) {
                    const double u = u_lo + (u_hi - u_lo) * rule.x[i], v = v_lo + (v_hi - v_lo) * rule.x[j];
                    const DVec3 p =
                        (1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] + (1 - u) * v * q[3];
                    const DVec3 du = (1 - v) * (q[1] - q[0]) + v * (q[2] - q[3]);
                    const DVec3 dv = (1 - u) * (q[3] - q[0]) + u * (q[2] - q[1]);
                    const double jacobian = glm::dot(glm::cross(du, dv), normal);
                    samples.add(p, rule.w[i] * rule.w[j] * (u_hi - u_lo) * (v_hi - v_lo) * jacobian);
                }
            sample(samples, normal, source, acc);
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
    // A source wholly above the horizon (the common case) is its own clip.
    std::array<DVec3, kMaxClip + 1> dirs;
    bool whole = true;
    for (size_t i = 0; i < n; ++i) {
        dirs[i] = source[i] - point;
        whole = whole && glm::dot(normal, dirs[i]) >= 0.0;
    }
    size_t count = n;
    if (!whole) {
        std::array<DVec3, kMaxClip> clipped;
        count = clipAboveHorizon(point, normal, source, clipped.data());
        if (count < 3) return 0.0;
        for (size_t i = 0; i < count; ++i) dirs[i] = clipped[i] - point;
    }
    // Two edges at a time in lanes, their terms summed in edge order.
    dirs[count] = dirs[0];
    double sum = 0.0;
    for (size_t i = 0; i < count; i += 2) {
        const size_t j = i + 1 < count ? i + 1 : i;  // an odd last edge fills both lanes
        const Lanes x0 = {dirs[i].x, dirs[j].x}, y0 = {dirs[i].y, dirs[j].y}, z0 = {dirs[i].z, dirs[j].z};
        const Lanes x1 = {dirs[i + 1].x, dirs[j + 1].x}, y1 = {dirs[i + 1].y, dirs[j + 1].y},
                    z1 = {dirs[i + 1].z, dirs[j + 1].z};
        Lanes term, c_len;
        edgeTermLanes(x0, y0, z0, x1, y1, z1, normal, term, c_len);
        // A vertex at the point, or a collinear edge, sweeps no area.
        if (c_len[0] > 0.0) sum += term[0];
        if (j != i && c_len[1] > 0.0) sum += term[1];
    }
    return std::abs(sum) / (2.0 * kPi);
}

namespace {

// The contour integral of pointPolygonFormFactor at two points that see the whole (unclipped)
// source, before its abs and 1 / (2 pi), into `sum`.
void contourLanes(const Lanes& px, const Lanes& py, const Lanes& pz, const DVec3& normal,
                  std::span<const DVec3> source, Lanes& sum) {
    const size_t n = source.size();
    sum = Lanes{};
    Lanes x0 = source[0].x - px, y0 = source[0].y - py, z0 = source[0].z - pz;
    const Lanes first_x = x0, first_y = y0, first_z = z0;
    for (size_t i = 0; i < n; ++i) {
        const bool last = i + 1 == n;
        const Lanes x1 = last ? first_x : source[i + 1].x - px;
        const Lanes y1 = last ? first_y : source[i + 1].y - py;
        const Lanes z1 = last ? first_z : source[i + 1].z - pz;
        Lanes term, c_len;
        edgeTermLanes(x0, y0, z0, x1, y1, z1, normal, term, c_len);
        sum += c_len > 0.0 ? term : Lanes{};
        x0 = x1, y0 = y1, z0 = z1;
    }
}

}  // namespace

void pointPolygonFormFactors(std::span<const DVec3> points, const DVec3& normal, std::span<const DVec3> source,
                             const DVec3& source_normal, double* out) {
    const size_t n = source.size();
    if (n < 3 || n >= kMaxClip - 1) {
        std::fill(out, out + points.size(), 0.0);
        return;
    }
    for (size_t first = 0; first < points.size(); first += kLanes) {
        const size_t count = std::min(kLanes, points.size() - first);
        Lanes px{}, py{}, pz{};
        std::array<bool, kLanes> whole{};
        bool any = false;
        for (size_t k = 0; k < count; ++k) {
            const DVec3& p = points[first + k];
            // A point behind the source, or whose horizon cuts it, takes the scalar path.
            if (!seenWhole(p, normal, {source, source_normal})) {
                out[first + k] = pointPolygonFormFactor(p, normal, source, source_normal);
                continue;
            }
            whole[k] = any = true;
            px[k] = p.x, py[k] = p.y, pz[k] = p.z;
        }
        if (!any) continue;
        Lanes sum;
        contourLanes(px, py, pz, normal, source, sum);
        for (size_t k = 0; k < count; ++k)
            if (whole[k]) out[first + k] = std::abs(sum[k]) / (2.0 * kPi);
    }
}

namespace {

// The contour integrals of two sources of n vertices each, seen whole from the point, in lanes
// 0 and 1, each summed in its own edge order.
void contourOfTwo(const DVec3& point, const DVec3& normal, std::span<const DVec3> a, std::span<const DVec3> b,
                  double& sum_a, double& sum_b) {
    const size_t n = a.size();
    sum_a = 0.0, sum_b = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const size_t j = i + 1 == n ? 0 : i + 1;
        const DVec3 a0 = a[i] - point, a1 = a[j] - point, b0 = b[i] - point, b1 = b[j] - point;
        Lanes term, c_len;
        edgeTermLanes(Lanes{a0.x, b0.x}, Lanes{a0.y, b0.y}, Lanes{a0.z, b0.z}, Lanes{a1.x, b1.x},
                      Lanes{a1.y, b1.y}, Lanes{a1.z, b1.z}, normal, term, c_len);
        if (c_len[0] > 0.0) sum_a += term[0];
        if (c_len[1] > 0.0) sum_b += term[1];
    }
}

}  // namespace

void pointPolygonFormFactorsTo(const DVec3& point, const DVec3& normal, std::span<const PolygonView> sources,
                               double* out) {
    size_t k = 0;
    while (k < sources.size()) {
        const PolygonView& a = sources[k];
        if (k + 1 < sources.size()) {
            const PolygonView& b = sources[k + 1];
            if (a.vertices.size() == b.vertices.size() && seenWhole(point, normal, a) && seenWhole(point, normal, b)) {
                double sum_a, sum_b;
                contourOfTwo(point, normal, a.vertices, b.vertices, sum_a, sum_b);
                out[k] = std::abs(sum_a) / (2.0 * kPi);
                out[k + 1] = std::abs(sum_b) / (2.0 * kPi);
                k += 2;
                continue;
            }
        }
        out[k] = pointPolygonFormFactor(point, normal, a.vertices, a.normal);
        ++k;
    }
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
    std::array<DVec3, 4> points;
    std::array<double, 4> weights, f;
    size_t k = 0;
    for (const double u : {0.5 - kG, 0.5 + kG})
        for (const double v : {0.5 - kG, 0.5 + kG}) {
            points[k] = (1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] + (1 - u) * v * q[3];
            const DVec3 du = (1 - v) * (q[1] - q[0]) + v * (q[2] - q[3]);
            const DVec3 dv = (1 - u) * (q[3] - q[0]) + u * (q[2] - q[1]);
            weights[k++] = std::abs(glm::dot(glm::cross(du, dv), quad_normal));
        }
    pointPolygonFormFactors(points, quad_normal, source, source_normal, f.data());
    double sum = 0.0, weight = 0.0;
    for (k = 0; k < 4; ++k) {
        sum += weights[k] * f[k];
        weight += weights[k];
    }
    return weight > 0.0 ? sum / weight : 0.0;
}

}  // namespace radbake
