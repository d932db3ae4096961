#include "radiosity/form_factor.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "geometry/polygon.h"

namespace radbake {
namespace {

constexpr size_t kMaxClip = 64;

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

void integrate(std::span<const DVec3> cell, const DVec3& normal, const PolygonView& source,
               const QuadratureOptions& options, int depth, Accumulator& acc) {
    DVec3 centre(0.0);
    for (const DVec3& p : cell) centre += p;
    centre /= static_cast<double>(cell.size());
    double radius = 0.0;
    for (const DVec3& p : cell) radius = std::max(radius, glm::length(p - centre));
    const bool far = pointPolygonDistance(centre, source) - radius > options.near_ratio * radius;
    if (cell.size() == 4 && (far || depth >= options.max_depth)) {
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
    // Clip the source to the receiver's upper half-space {y : normal.(y - point) >= 0}.
    std::array<DVec3, kMaxClip> clipped;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        const DVec3& a = source[i];
        const DVec3& b = source[(i + 1) % n];
        const double da = glm::dot(normal, a - point);
        const double db = glm::dot(normal, b - point);
        if (da >= 0.0) clipped[count++] = a;
        if ((da > 0.0 && db < 0.0) || (da < 0.0 && db > 0.0)) clipped[count++] = a + (da / (da - db)) * (b - a);
    }
    if (count < 3) return 0.0;
    double sum = 0.0;
    std::array<DVec3, kMaxClip> dirs;
    for (size_t i = 0; i < count; ++i) dirs[i] = clipped[i] - point;
    for (size_t i = 0; i < count; ++i) {
        const DVec3& r0 = dirs[i];
        const DVec3& r1 = dirs[(i + 1) % count];
        const DVec3 c = glm::cross(r0, r1);
        const double c_len = glm::length(c);
        if (!(c_len > 0.0)) continue;  // a vertex at the point, or collinear: no area swept
        const double angle = std::atan2(c_len, glm::dot(r0, r1));
        sum += angle * glm::dot(normal, c) / c_len;
    }
    return std::abs(sum) / (2.0 * kPi);
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

}  // namespace radbake
