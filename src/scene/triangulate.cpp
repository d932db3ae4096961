#include "scene/triangulate.h"

#include <algorithm>
#include <cmath>

namespace radbake {
namespace {

// Twice the signed area of the 2D triangle abc (positive when counter-clockwise).
double orient(const DVec2& a, const DVec2& b, const DVec2& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

void appendFan(std::span<const uint32_t> loop, std::vector<UVec3>& out) {
    for (size_t i = 1; i + 1 < loop.size(); ++i) out.emplace_back(loop[0], loop[i], loop[i + 1]);
}

// Point tests allowed per polygon before the clipper gives up and fans the rest: keeps a
// pathological (e.g. fuzzed) loop of thousands of points from taking minutes.
constexpr size_t kWorkBudget = 40'000'000;

class EarClipper {
public:
    EarClipper(std::vector<DVec2> points, std::span<const uint32_t> loop, double area_epsilon)
        : p_(std::move(points)), loop_(loop), eps_(area_epsilon), prev_(p_.size()), next_(p_.size()) {
        const size_t n = p_.size();
        for (size_t i = 0; i < n; ++i) {
            prev_[i] = static_cast<uint32_t>((i + n - 1) % n);
            next_[i] = static_cast<uint32_t>((i + 1) % n);
        }
        remaining_ = n;
    }

    size_t run(std::vector<UVec3>& out) {
        const size_t before = out.size();
        uint32_t cursor = 0;
        int mode = 0;  // 0: clean ears; 1: drop zero-area corners; 2: any convex corner; 3: fan
        while (remaining_ > 3) {
            if (work_ > kWorkBudget) mode = 3;
            if (mode == 3) {
                fanRest(cursor, out);
                return out.size() - before;
            }
            bool clipped = false;
            uint32_t v = cursor;
            for (size_t step = 0; step < remaining_; ++step, v = next_[v]) {
                const double area = orient(p_[prev_[v]], p_[v], p_[next_[v]]);
                if (mode == 1 ? std::abs(area) <= eps_ : area > eps_ && (mode == 2 || isEar(v))) {
                    if (mode != 1) emit(v, out);
                    cursor = prev_[v];
                    remove(v);
                    clipped = true;
                    break;
                }
            }
            mode = clipped ? 0 : mode + 1;
        }
        const uint32_t a = prev_[cursor], b = cursor, c = next_[cursor];
        if (std::abs(orient(p_[a], p_[b], p_[c])) > eps_) out.emplace_back(loop_[a], loop_[b], loop_[c]);
        return out.size() - before;
    }

private:
    // No other point of the ring lies inside or on triangle (prev, v, next); points that
    // coincide with a corner (self-touching loops) do not count.
    bool isEar(uint32_t v) {
        const uint32_t ia = prev_[v], ic = next_[v];
        const DVec2 &a = p_[ia], &b = p_[v], &c = p_[ic];
        for (uint32_t q = next_[ic]; q != ia; q = next_[q]) {
            ++work_;
            const DVec2& p = p_[q];
            if (p == a || p == b || p == c) continue;
            if (orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0) return false;
        }
        return true;
    }

    void emit(uint32_t v, std::vector<UVec3>& out) {
        out.emplace_back(loop_[prev_[v]], loop_[v], loop_[next_[v]]);
    }

    void remove(uint32_t v) {
        next_[prev_[v]] = next_[v];
        prev_[next_[v]] = prev_[v];
        --remaining_;
    }

    void fanRest(uint32_t start, std::vector<UVec3>& out) {
        for (uint32_t v = next_[start]; next_[v] != start; v = next_[v])
            out.emplace_back(loop_[start], loop_[v], loop_[next_[v]]);
    }

    std::vector<DVec2> p_;
    std::span<const uint32_t> loop_;
    double eps_;
    std::vector<uint32_t> prev_, next_;
    size_t remaining_ = 0;
    size_t work_ = 0;
};

}  // namespace

size_t triangulatePolygon(const std::vector<Vec3>& positions, std::span<const uint32_t> loop, bool convex,
                          std::vector<UVec3>& out) {
    const size_t n = loop.size();
    if (n < 3) return 0;
    const bool in_range =
        std::all_of(loop.begin(), loop.end(), [&](uint32_t i) { return i < positions.size(); });
    if (convex || n == 3 || !in_range) {
        appendFan(loop, out);
        return n - 2;
    }

    // Newell normal: robust for non-planar and non-convex loops.
    DVec3 normal(0.0);
    for (size_t i = 0; i < n; ++i) {
        const DVec3 a(positions[loop[i]]), b(positions[loop[(i + 1) % n]]);
        normal += DVec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    const DVec3 m = glm::abs(normal);
    const int axis = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
    if (!(m[axis] > 0.0) || !std::isfinite(m[axis])) {
        appendFan(loop, out);
        return n - 2;
    }
    // Drop the dominant axis keeping (u, v, axis) right-handed, then mirror u when the normal
    // points down that axis, so the loop runs counter-clockwise in the plane.
    const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
    const double flip = normal[axis] < 0.0 ? -1.0 : 1.0;
    std::vector<DVec2> points(n);
    DVec2 lo(INFINITY), hi(-INFINITY);
    for (size_t i = 0; i < n; ++i) {
        const Vec3& p = positions[loop[i]];
        points[i] = DVec2(flip * p[u_axis], p[v_axis]);
        lo = glm::min(lo, points[i]);
        hi = glm::max(hi, points[i]);
    }
    // Corners whose doubled area is below 1e-7 of the squared extent are treated as
    // collinear: float coordinates carry a relative error of 6e-8, so a corner authored
    // straight can be that far from straight after rounding.
    const DVec2 extent = hi - lo;
    const double area_epsilon = 1e-7 * glm::dot(extent, extent);
    return EarClipper(std::move(points), loop, area_epsilon).run(out);
}

}  // namespace radbake
