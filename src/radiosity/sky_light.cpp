#include "radiosity/sky_light.h"

#include <algorithm>
#include <array>
#include <limits>
#include <optional>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/cone_cover.h"
#include "geometry/polygon.h"
#include "radiosity/punctual_lights.h"
#include "radiosity/solution.h"
#include "scene/daylight.h"
#include "visibility/ray_caster.h"

namespace radbake {
namespace {

// What a sample sees: the sky, the sky through a transmitting surface, something in the way, or
// nothing (at or below the horizon).
enum class Seen : uint8_t { Sky, Through, Blocked, Nothing, Unknown };

struct Sample {
    DVec3 weighted{0.0};  // L V cos theta
    Seen seen = Seen::Unknown;
    RayBlocker blocker;  // Blocked: the opaque triangle met first (when searching)
};

// A cell's four samples, at its quarter centres: [i][j], i along u, j along v.
using Quad = std::array<std::array<Sample, 2>, 2>;
// What a sample across a cell's edge saw, and what blocked it (null if nothing did). The sample
// outlives the cells that look at it (a parent's children, the top samples).
struct Neighbour {
    Seen seen = Seen::Unknown;
    const RayBlocker* blocker = nullptr;
};
Neighbour neighbourOf(const Sample& sample) {
    return {sample.seen, sample.blocker.found ? &sample.blocker : nullptr};
}
// What lies across each edge of a cell next to each of its two samples on that edge: [edge][k]
// for edges u-min, u-max, v-min, v-max, k the sample's index along the edge.
using Across = std::array<std::array<Neighbour, 2>, 4>;

class SkyGather {
public:
    SkyGather(const Sky& sky, const RayCaster* caster, const DVec3& p, const DVec3& n, const SkyQuadrature& quadrature)
        : sky_(sky), caster_(caster), p_(p), n_(n), depth_(quadrature.depth), search_(quadrature.search) {
        // The up axis's projection along b: the horizon of a vertical surface then runs along
        // v = 1/2, a cell edge for an even grid.
        const DVec3 up(sky.up);
        const DVec3 along = up - glm::dot(up, n) * n;
        if (glm::length(along) > 1e-6) {
            b_ = glm::normalize(along);
            t_ = glm::cross(b_, n);
        } else {
            tangentFrame(n, t_, b_);
        }
    }

    // The samples at (u[k], v[k]), their rays cast together: the square onto the unit disc by
    // the concentric map (equal areas, the normal at the centre), then onto the
    // hemisphere by the equal-area azimuthal projection (1 - cos theta = r^2), so d omega is
    // 2 pi du dv: as many samples near the horizon, where a window seen at a grazing angle lies, as
    // anywhere else.
    // `side`: the side of the square cell each sample stands for.
    void sample(std::span<const double> u, std::span<const double> v, double side, std::span<Sample> out) {
        std::array<DVec3, kBatch> far;
        std::array<size_t, kBatch> which;
        std::array<float, kBatch> through;
        size_t cast = 0;
        for (size_t k = 0; k < out.size(); ++k) {
            const DVec3 d = direction(u[k], v[k]);
            // The sample stands for 2 pi side^2 steradians: a map's detail within them is averaged.
            const DVec3 radiance = skyRadianceOver(sky_, d, 2.0 * kPi * side * side);
            if (radiance == DVec3(0.0)) {
                out[k] = {DVec3(0.0), Seen::Nothing};
                continue;
            }
            out[k] = {radiance * meanCosine(u[k], v[k], side), Seen::Sky};
            if (!caster_) continue;
            far[cast] = pointAtInfinity(*caster_, p_, d);
            which[cast++] = k;
            if (cast == kBatch) flush(far, which, through, cast, out);
        }
        if (cast > 0) flush(far, which, through, cast, out);
    }

    Quad quad(double u0, double v0, double size) {
        const double a = u0 + 0.25 * size, b = u0 + 0.75 * size, c = v0 + 0.25 * size, d = v0 + 0.75 * size;
        const std::array<double, 4> u{a, a, b, b}, v{c, d, c, d};
        std::array<Sample, 4> samples;
        sample(u, v, 0.5 * size, samples);
        return {{{samples[0], samples[1]}, {samples[2], samples[3]}}};
    }

    // The integral of L V cos theta du dv over the cell [u0, u0 + size] x [v0, v0 + size] at
    // `level` below the top cells, whose samples are `q`: the midpoint rule on its quarters where
    // they and the samples across its edges agree (and, when all are blocked, the blockers they
    // met are proven to cover the cell), else the sum over its quarters, each read at its own
    // quarter centres. Cells whose samples disagree split down to `limit`; a dark cell not proven
    // dark splits down to search_ levels, and a branch that finds sky that way may split depth_
    // levels below where it looked.
    DVec3 cell(double u0, double v0, double size, const Quad& q, const Across& across, int level, int limit) {
        const double half = 0.5 * size;
        const bool agree = uniform(q, across);
        const bool search = agree && q[0][0].seen == Seen::Blocked && level < search_ && caster_ &&
                            !provenDark(u0, v0, size, q, across);
        if (!search && (agree || level >= limit))
            return (q[0][0].weighted + q[0][1].weighted + q[1][0].weighted + q[1][1].weighted) * (half * half);
        const int child_limit = search ? std::max(limit, level + 1 + depth_) : limit;
        // The children's samples first: each child's neighbours inside the cell are its siblings'.
        Quad child[2][2];
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) child[i][j] = quad(u0 + i * half, v0 + j * half, half);
        // The samples of the 4 x 4 grid the children make, and what lies beyond it (the cell's own
        // neighbours, one per half edge).
        auto at = [&](int a, int b) -> Neighbour {
            if (a < 0) return across[0][b / 2];
            if (a > 3) return across[1][b / 2];
            if (b < 0) return across[2][a / 2];
            if (b > 3) return across[3][a / 2];
            return neighbourOf(child[a / 2][b / 2][a % 2][b % 2]);
        };
        DVec3 sum(0.0);
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) {
                Across beyond;
                for (int k = 0; k < 2; ++k) {
                    beyond[0][k] = at(2 * i - 1, 2 * j + k);
                    beyond[1][k] = at(2 * i + 2, 2 * j + k);
                    beyond[2][k] = at(2 * i + k, 2 * j - 1);
                    beyond[3][k] = at(2 * i + k, 2 * j + 2);
                }
                sum += cell(u0 + i * half, v0 + j * half, half, child[i][j], beyond, level + 1, child_limit);
            }
        return sum;
    }

    size_t rays = 0;

private:
    static constexpr size_t kBatch = 16;
    // A face of more triangles than this proves with the triangle met only.
    static constexpr size_t kFaceTriangles = 16;

    // The unit direction of parameter point (u, v): the square onto the unit disc by the concentric
    // map (equal areas, the normal at the centre), then onto the hemisphere by the equal-area
    // azimuthal projection (1 - cos theta = r^2).
    DVec3 direction(double u, double v) const {
        const DVec2 disc = concentricDisc(2.0 * u - 1.0, 2.0 * v - 1.0);
        const double r2 = glm::dot(disc, disc), cos_t = 1.0 - r2, lift = std::sqrt(std::max(0.0, 2.0 - r2));
        return glm::normalize(t_ * (disc.x * lift) + b_ * (disc.y * lift) + n_ * cos_t);
    }

    // Whether the opaque triangles the cell's four samples met cover every direction of the cell
    // (geometry/cone_cover.h): its outline, two points an edge, against their union.
    bool provenDark(double u0, double v0, double size, const Quad& q, const Across& across) const {
        bool one_surface = true;
        for (const auto& column : q)
            for (const Sample& sample : column)
                one_surface = one_surface && sample.blocker.found && sample.blocker.mesh == q[0][0].blocker.mesh;
        for (const auto& edge : across)
            for (const Neighbour& n : edge)
                one_surface = one_surface && (n.seen == Seen::Unknown || (n.blocker && n.blocker->mesh == q[0][0].blocker.mesh));
        // All four, and the samples around the cell, on one mesh: a gap worth looking for lies
        // between surfaces (two panels, a wall and its frame), not among a mesh's own triangles,
        // which are often finer than the cell.
        if (one_surface) return true;
        // The faces the samples and their neighbours met, whole (a quad's two triangles cover
        // what one does not; the cell reaches a quarter of its side beyond its samples).
        std::vector<std::array<DVec3, 3>> opaque;
        std::vector<size_t> face_ends;
        std::array<std::pair<uint32_t, uint32_t>, 12> faces;
        size_t face_count = 0;
        auto addFace = [&](const RayBlocker& blocker) {
            const std::pair<uint32_t, uint32_t> face{blocker.mesh, blocker.polygon};
            if (std::find(faces.begin(), faces.begin() + face_count, face) != faces.begin() + face_count) return;
            faces[face_count++] = face;
            const size_t before = opaque.size();
            caster_->appendPolygonTriangles(face.first, face.second, kFaceTriangles, opaque);
            if (opaque.size() == before) opaque.push_back(blocker.corners);
            face_ends.push_back(opaque.size());
        };
        for (const auto& column : q)
            for (const Sample& sample : column)
                if (sample.blocker.found) addFace(sample.blocker);
        for (const auto& edge : across)
            for (const Neighbour& n : edge)
                if (n.blocker) addFace(*n.blocker);
        if (opaque.empty()) return false;
        constexpr int kPerEdge = 2;
        std::array<DVec3, 4 * kPerEdge> outline;
        for (int k = 0; k < kPerEdge; ++k) {
            const double f = double(k) / kPerEdge;
            outline[k] = direction(u0 + f * size, v0);
            outline[kPerEdge + k] = direction(u0 + size, v0 + f * size);
            outline[2 * kPerEdge + k] = direction(u0 + (1.0 - f) * size, v0 + size);
            outline[3 * kPerEdge + k] = direction(u0, v0 + (1.0 - f) * size);
        }
        return patchCovered(p_, outline, opaque, face_ends);
    }

    // The mean of cos theta = 1 - max(|a|, |b|)^2 over the square cell of side `side` about (u, v)
    // (a = 2u - 1, b = 2v - 1): 2 x 2 Gauss points, exact for the quadratic on either side of the
    // diagonals, so an open uniform sky integrates to pi L but for cells astride a diagonal.
    static double meanCosine(double u, double v, double side) {
        constexpr double kGauss = 0.2886751345948129;  // 1 / (2 sqrt 3)
        double sum = 0.0;
        for (const double du : {-kGauss, kGauss})
            for (const double dv : {-kGauss, kGauss}) {
                const double a = 2.0 * (u + du * side) - 1.0, b = 2.0 * (v + dv * side) - 1.0;
                const double r = std::max(std::abs(a), std::abs(b));
                sum += 1.0 - r * r;
            }
        return 0.25 * sum;
    }

    void flush(const std::array<DVec3, kBatch>& far, const std::array<size_t, kBatch>& which,
               std::array<float, kBatch>& through, size_t& cast, std::span<Sample> out) {
        const std::span<const DVec3> to(far.data(), cast);
        const std::span<float> passed(through.data(), cast);
        std::array<RayBlocker, kBatch> blockers;
        // The blockers are what a search proves a dark cell with.
        if (search_ > 0) caster_->transmittanceAndBlockersFrom(p_, to, passed, std::span(blockers.data(), cast));
        else caster_->transmittanceFrom(p_, to, passed);
        for (size_t k = 0; k < cast; ++k) {
            Sample& sample = out[which[k]];
            if (through[k] == 0.0f) {
                sample = {DVec3(0.0), Seen::Blocked, blockers[k]};
            } else if (through[k] < 1.0f) {
                sample.weighted *= double(through[k]);
                sample.seen = Seen::Through;
            }
        }
        rays += cast;
        cast = 0;
    }

    static bool uniform(const Quad& q, const Across& across) {
        const Seen first = q[0][0].seen;
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j)
                if (q[i][j].seen != first) return false;
        for (const auto& edge : across)
            for (const Neighbour& n : edge)
                if (n.seen != Seen::Unknown && n.seen != first) return false;
        return true;
    }

    const Sky& sky_;
    const RayCaster* caster_;
    DVec3 p_, n_, t_, b_;
    int depth_ = 0, search_ = 0;
};

// The bilinear interpolation of the corner values h over the convex quad v (in order) at p's
// projection onto its plane (inverse bilinear map, clamped to the quad); nullopt when degenerate.
std::optional<DVec3> bilinearInQuad(const DVec3* v, const DVec3* h, const DVec3& normal, const DVec3& p) {
    const DVec3 x_axis = v[1] - v[0];
    const double length = glm::length(x_axis);
    if (!(length > 0.0)) return std::nullopt;
    const DVec3 ex = x_axis / length, ey = glm::cross(normal, ex);
    auto flat = [&](const DVec3& q) { return DVec2(glm::dot(q - v[0], ex), glm::dot(q - v[0], ey)); };
    auto cross2 = [](const DVec2& a, const DVec2& b) { return a.x * b.y - a.y * b.x; };
    const DVec2 b = flat(v[1]), c = flat(v[2]), d = flat(v[3]), q = flat(p);
    const DVec2 e = b, f = d, g = c - b - d;  // p = e s + f t + g s t, corner 0 at the origin
    const double k2 = cross2(g, f), k1 = cross2(e, f) + cross2(q, g), k0 = cross2(q, e);
    const double scale = std::abs(cross2(e, f));
    if (!(scale > 0.0)) return std::nullopt;
    double s = 0.0, t = 0.0;
    auto sAt = [&](double tt) {
        const DVec2 den = e + g * tt;
        return std::abs(den.x) > std::abs(den.y) ? (q.x - f.x * tt) / den.x : (q.y - f.y * tt) / den.y;
    };
    if (std::abs(k2) <= 1e-9 * scale) {
        t = -k0 / k1;
        s = sAt(t);
    } else {
        const double w = k1 * k1 - 4.0 * k0 * k2;
        if (w < 0.0) return std::nullopt;
        const double root = std::sqrt(w);
        t = (-k1 - root) / (2.0 * k2);
        s = sAt(t);
        if (!(s >= -1e-9 && s <= 1.0 + 1e-9 && t >= -1e-9 && t <= 1.0 + 1e-9)) {
            const double t2 = (-k1 + root) / (2.0 * k2), s2 = sAt(t2);
            if (std::abs(std::clamp(t2, 0.0, 1.0) - t2) + std::abs(std::clamp(s2, 0.0, 1.0) - s2) <
                std::abs(std::clamp(t, 0.0, 1.0) - t) + std::abs(std::clamp(s, 0.0, 1.0) - s))
                s = s2, t = t2;
        }
    }
    if (!std::isfinite(s) || !std::isfinite(t)) return std::nullopt;
    s = std::clamp(s, 0.0, 1.0), t = std::clamp(t, 0.0, 1.0);
    return h[0] * ((1 - s) * (1 - t)) + h[1] * (s * (1 - t)) + h[2] * (s * t) + h[3] * ((1 - s) * t);
}

}  // namespace

DVec3 skyIrradiance(const Sky& sky, const RayCaster* caster, const DVec3& p_world, const DVec3& n_world,
                    const SkyQuadrature& quadrature, size_t* rays_cast) {
    if (!sky.shines()) return DVec3(0.0);
    SkyGather gather(sky, caster, p_world, n_world, quadrature);
    const int grid = std::max(1, quadrature.grid), samples = 2 * grid;
    const double size = 1.0 / grid;
    // Every top cell's samples first, so that a cell whose neighbour's samples differ from its
    // own is split too (the outline of an opening can run just inside a cell's edge).
    std::vector<Sample> top(static_cast<size_t>(samples) * samples);
    std::vector<double> u(top.size()), v(top.size());
    for (int a = 0; a < samples; ++a)
        for (int b = 0; b < samples; ++b) {
            u[a * samples + b] = (a + 0.5) / samples;
            v[a * samples + b] = (b + 0.5) / samples;
        }
    gather.sample(u, v, 1.0 / samples, top);
    // Nothing beyond the square's edges (the horizon).
    auto seen = [&](int a, int b) {
        if (a < 0 || a >= samples || b < 0 || b >= samples) return Neighbour{};
        return neighbourOf(top[a * samples + b]);
    };
    DVec3 sum(0.0);
    for (int i = 0; i < grid; ++i)
        for (int j = 0; j < grid; ++j) {
            Quad q;
            Across across;
            for (int k = 0; k < 2; ++k) {
                q[k][0] = top[(2 * i + k) * samples + 2 * j];
                q[k][1] = top[(2 * i + k) * samples + 2 * j + 1];
                across[0][k] = seen(2 * i - 1, 2 * j + k);
                across[1][k] = seen(2 * i + 2, 2 * j + k);
                across[2][k] = seen(2 * i + k, 2 * j - 1);
                across[3][k] = seen(2 * i + k, 2 * j + 2);
            }
            sum += gather.cell(i * size, j * size, size, q, across, 0, quadrature.depth);
        }
    if (rays_cast) *rays_cast += gather.rays;
    return 2.0 * kPi * sum;  // d omega = 2 pi du dv
}

DVec3 skyInElement(const Solution& solution, uint32_t element, const DVec3& p) {
    if (solution.vertex_sky.size() != solution.vertices.size() || element >= solution.elements.size())
        return DVec3(0.0);
    const Element& e = solution.elements[element];
    const DVec3* v = solution.vertices.data() + e.first_vertex;
    const DVec3* h = solution.vertex_sky.data() + e.first_vertex;
    if (e.vertex_count == 4)
        if (const std::optional<DVec3> value = bilinearInQuad(v, h, e.normal, p)) return *value;
    // The fan triangle (0, k, k + 1) that holds p's projection best (its least barycentric
    // coordinate the largest), weights clamped to it: a texel's sample point may lie a little
    // outside its leaf.
    double best = -std::numeric_limits<double>::infinity();
    DVec3 value = h[0];
    for (uint32_t k = 1; k + 1 < e.vertex_count; ++k) {
        const DVec3 a = v[k] - v[0], b = v[k + 1] - v[0], q = p - v[0];
        const DVec3 cross = glm::cross(a, b);
        const double area2 = glm::dot(cross, cross);
        if (!(area2 > 0.0)) continue;
        const double wb = glm::dot(glm::cross(a, q), cross) / area2;  // weight of corner k + 1
        const double wa = glm::dot(glm::cross(q, b), cross) / area2;  // weight of corner k
        const double w0 = 1.0 - wa - wb;
        const double least = std::min(w0, std::min(wa, wb));
        if (least <= best) continue;
        best = least;
        const double ca = std::clamp(wa, 0.0, 1.0), cb = std::clamp(wb, 0.0, 1.0), c0 = std::clamp(w0, 0.0, 1.0);
        value = (h[0] * c0 + h[k] * ca + h[k + 1] * cb) / (c0 + ca + cb);
    }
    return value;
}

}  // namespace radbake
