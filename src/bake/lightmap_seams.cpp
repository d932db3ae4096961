// Chart edges and seams: sampling the chart boundaries, pairing seam edges, and the
// least-squares fit of the texels under their bilinear lookups (conjugate gradient).
#include "bake/lightmap_seams.h"

#include <span>

#include <functional>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>

#include "bake/chart_texels.h"

namespace radbake {
namespace {

// A clipped chart point whose barycentric weight for a corner is below this lies on the
// opposite source edge: clipping puts points on cell lines exactly and interpolates along
// edges with ~1e-15 relative rounding; the slack covers skinny triangles.
constexpr double kOnEdge = 1e-7;
// Faces closer than this (1 - cos) are coplanar: the charts' own coplanarity test.
constexpr double kCoplanar = 1e-4;
// Edge points per texel of edge length: a bilinear lookup along an edge is piecewise linear
// between texel-centre crossings, so two points per texel pin every piece.
constexpr double kSamplesPerTexel = 2.0;
// Widest EdgeSample::span: with a tolerance, light that agrees at both ends of 8 samples (4
// texels of edge) is taken as linear between them, as the texels' adaptive evaluation does.
constexpr size_t kMaxEdgeSpan = 4;
// Least-squares weights. A covered texel's own point (where it was evaluated) keeps its value
// with weight 1000 per unit of the texel its chart covers: the lookup there is the texel
// itself when its centre lies on the chart, else a row (addOwnPointRows). On a chart narrower
// than a texel the lookups along both edges and at its texels' points read the same texels,
// and the points inside win: light read along a line where the chart meets another surface
// says little about the area beside it. Padding texels are nearly free (a small pull keeps
// the system definite and the change minimal);
// an edge lookup is pulled to the light there with weight 1 and a seam's two lookups to
// each other with weight 100, so where both cannot hold exactly (per-face light changes
// across a smooth edge; diagonal seams through partly covered texels) the seam wins. Where
// the padding alone can satisfy the lookups (straight chart edges, cuts), the residual is
// about kFree / weight of the padding's change: 1e-4 relative. (A seam weight of 1000 was no
// better on the Cornell box and needed twice the CG steps.)
constexpr double kCoveredPrior = 1000.0;
constexpr double kFree = 1e-4;
// A covered texel whose centre lies outside its chart's geometry (an edge crosses it between
// its centre and the chart) mostly serves lookups at that edge: it bends more easily, as long
// as the lookup at its own point keeps its value.
constexpr double kPartialPrior = 1e-2;
constexpr double kEdgeWeight = 1.0;
constexpr double kSeamWeight = 100.0;
// Conjugate gradient: stop when the residual falls below this fraction of the right-hand side.
constexpr double kSolveTolerance = 1e-9;
constexpr int kMaxIterations = 2000;
// A padding texel's range (fitBounds) widens by this many times the light's local range over
// the largest weight a lookup it serves gives it, that weight taken at least kLeastReach.
constexpr double kPaddingReach = 2.0;
constexpr double kLeastReach = 0.5;
// Rounds of the bounded fit (solveBounded); it stops sooner once a round lowers the fit's
// error by less than this fraction.
constexpr int kBoundRounds = 16;
constexpr double kBoundProgress = 1e-6;
// Edge light below this fraction of the brightest is compared against it, not itself (the
// texels' kDarkFloor, lightmap_adaptive.h).
constexpr double kDarkEdge = 1e-2;

struct BoundaryEdge {
    uint32_t chart = 0;
    uint32_t face = 0;
    DVec2 p{0.0}, q{0.0};  // plane ends
    DVec3 p_world{0.0}, q_world{0.0};
    std::vector<std::pair<double, double>> seamed;  // parameter intervals that lie on a seam
};

DVec3 barycentricInPlane(const ChartFace& face, const DVec2& p) {
    const DVec2 e1 = face.corner_plane[1] - face.corner_plane[0], e2 = face.corner_plane[2] - face.corner_plane[0];
    const DVec2 d = p - face.corner_plane[0];
    const double det = e1.x * e2.y - e1.y * e2.x;
    if (det == 0.0) return DVec3(1.0, 0.0, 0.0);
    const double b1 = (d.x * e2.y - d.y * e2.x) / det, b2 = (e1.x * d.y - e1.y * d.x) / det;
    return DVec3(1.0 - b1 - b2, b1, b2);
}

int sampleCount(double length_texels) {
    return std::max(2, static_cast<int>(std::ceil(kSamplesPerTexel * length_texels)) + 1);
}

EdgeSample edgeSample(const LightmapChart& chart, const BoundaryEdge& edge, double t) {
    EdgeSample s;
    s.chart = edge.chart;
    s.texel = chart.atlasTexel(edge.p + (edge.q - edge.p) * t);
    s.p_world = edge.p_world + (edge.q_world - edge.p_world) * t;
    s.normal_world = chart.faces[edge.face].normal_world;
    s.mesh = chart.mesh;
    s.triangle = chart.faces[edge.face].triangle;
    return s;
}

// Boundary edges of one chart: face polygon edges that no other face of the chart runs
// back along (faces of one chart share bit-identical plane points).
void chartBoundary(const LightmapChart& chart, uint32_t c, std::vector<BoundaryEdge>& out) {
    std::set<std::array<double, 4>> directed;
    for (const ChartFace& face : chart.faces)
        for (size_t k = 0; k < face.p_plane.size(); ++k) {
            const DVec2& a = face.p_plane[k];
            const DVec2& b = face.p_plane[(k + 1) % face.p_plane.size()];
            directed.insert({a.x, a.y, b.x, b.y});
        }
    for (uint32_t f = 0; f < chart.faces.size(); ++f) {
        const ChartFace& face = chart.faces[f];
        for (size_t k = 0; k < face.p_plane.size(); ++k) {
            const DVec2& a = face.p_plane[k];
            const DVec2& b = face.p_plane[(k + 1) % face.p_plane.size()];
            if (a == b || directed.count({b.x, b.y, a.x, a.y})) continue;
            out.push_back(BoundaryEdge{c, f, a, b, face.worldPoint(a), face.worldPoint(b), {}});
        }
    }
}

// Which line an edge lies on, for pairing: a source edge (welded ends) or a cut through one triangle.
using EdgeKey = std::tuple<uint32_t, uint32_t, uint32_t, uint32_t>;  // mesh, kind, a, b

EdgeKey edgeKey(const LightmapChart& chart, const BoundaryEdge& edge, const Scene& scene,
                const std::vector<std::vector<uint32_t>>& welded) {
    const ChartFace& face = chart.faces[edge.face];
    const DVec3 bp = barycentricInPlane(face, edge.p), bq = barycentricInPlane(face, edge.q);
    for (int k = 0; k < 3; ++k) {
        if (std::fabs(bp[k]) > kOnEdge || std::fabs(bq[k]) > kOnEdge) continue;
        const UVec3& tri = scene.meshes[chart.mesh].triangles[face.triangle];
        uint32_t a = welded[chart.mesh][tri[(k + 1) % 3]], b = welded[chart.mesh][tri[(k + 2) % 3]];
        if (a > b) std::swap(a, b);
        return {chart.mesh, 0u, a, b};
    }
    return {chart.mesh, 1u, face.triangle, 0u};
}

bool sameSurface(const Scene& scene, const LightmapChart& a, const ChartFace& fa, const ChartFace& fb) {
    if (fa.triangle == fb.triangle) return true;
    const double cos_crease = std::cos(static_cast<double>(scene.meshes[a.mesh].crease_angle));
    return glm::dot(fa.normal_world, fb.normal_world) >= std::min(cos_crease, 1.0 - kCoplanar);
}

// Pairs two boundary edges of different charts lying on one line; appends seam samples over
// their overlap and records the overlap on both edges.
void pairEdges(const LightmapLayout& layout, BoundaryEdge& e1, BoundaryEdge& e2, double tolerance,
               std::vector<SeamSample>& seams) {
    const LightmapChart& c1 = layout.charts[e1.chart];
    const LightmapChart& c2 = layout.charts[e2.chart];
    const DVec3 d = e1.q_world - e1.p_world;
    const double length = glm::length(d);
    if (!(length > tolerance)) return;
    const DVec3 u = d / length;
    const double s_p = glm::dot(e2.p_world - e1.p_world, u), s_q = glm::dot(e2.q_world - e1.p_world, u);
    if (glm::length(e2.p_world - e1.p_world - s_p * u) > tolerance) return;
    if (glm::length(e2.q_world - e1.p_world - s_q * u) > tolerance) return;
    const double lo = std::max(0.0, std::min(s_p, s_q)), hi = std::min(length, std::max(s_p, s_q));
    if (!(hi - lo > tolerance) || !(std::fabs(s_q - s_p) > tolerance)) return;
    const int n = sampleCount((hi - lo) * std::max(c1.texels_per_metre, c2.texels_per_metre));
    for (int k = 0; k < n; ++k) {
        const double s = lo + (hi - lo) * k / (n - 1);
        SeamSample seam;
        seam.a = edgeSample(c1, e1, s / length);
        seam.b = edgeSample(c2, e2, (s - s_p) / (s_q - s_p));
        seam.b.p_world = seam.a.p_world;  // one point, seen from both faces
        seams.push_back(seam);
    }
    e1.seamed.emplace_back(lo / length, hi / length);
    const double t_lo = (lo - s_p) / (s_q - s_p), t_hi = (hi - s_p) / (s_q - s_p);
    e2.seamed.emplace_back(std::min(t_lo, t_hi), std::max(t_lo, t_hi));
}

struct Tap {
    uint32_t unknown = 0;
    double weight = 0.0;
};

struct Row {
    std::array<Tap, 8> taps{};
    int count = 0;
    double weight = 0.0;
    DVec3 target{0.0};
    bool anchored = false;  // pulls a lookup to the light at a point (else a seam's two lookups together)
};

struct Unknowns {
    std::unordered_map<uint64_t, uint32_t> ids;
    std::vector<std::pair<int, size_t>> texels;  // atlas, pixel
    std::vector<uint32_t> charts;                // the chart whose lookup first read it

    uint32_t id(int atlas, size_t pixel, uint32_t chart) {
        const uint64_t key = (static_cast<uint64_t>(atlas) << 40) | pixel;
        const auto [it, added] = ids.emplace(key, static_cast<uint32_t>(texels.size()));
        if (added) {
            texels.emplace_back(atlas, pixel);
            charts.push_back(chart);
        }
        return it->second;
    }
};

bool centreOnGeometry(const LightmapChart& chart, const LightmapImage& image, size_t pixel) {
    DVec2 centre;
    return faceAtTexel(chart, static_cast<int>(pixel % image.width), static_cast<int>(pixel / image.width), centre) != nullptr;
}

// The four bilinear taps of a lookup, clamped to the image like bilinearLookup.
void addStencil(const LightmapImage& image, int atlas, uint32_t chart, const DVec2& texel, double sign, Unknowns& unknowns,
                Row& row) {
    const double x = texel.x - 0.5, y = texel.y - 0.5;
    const double fx0 = std::floor(x), fy0 = std::floor(y);
    const double fx = x - fx0, fy = y - fy0;
    const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const int xi = std::clamp(x0 + dx, 0, image.width - 1), yi = std::clamp(y0 + dy, 0, image.height - 1);
            const double w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy);
            row.taps[row.count++] = Tap{unknowns.id(atlas, static_cast<size_t>(yi) * image.width + xi, chart), sign * w};
        }
}

double relativeGap(const DVec3& a, const DVec3& b, double floor) {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::fabs(a[c] - b[c]) / std::max({std::fabs(a[c]), std::fabs(b[c]), floor}));
    return worst;
}

// Rows pulling the lookup at each covered unknown texel's own point to its value, for those
// whose centre lies off their chart, weighted by the part of the texel the chart covers.
void addOwnPointRows(const LightmapLayout& layout, const std::vector<LightmapImage>& images, Unknowns& unknowns,
                     std::vector<Row>& rows) {
    const size_t tapped = unknowns.texels.size();  // the rows add padding unknowns: those are not covered
    for (size_t i = 0; i < tapped; ++i) {
        const auto [atlas, pixel] = unknowns.texels[i];
        const LightmapImage& image = images[atlas];
        const LightmapChart& chart = layout.charts[unknowns.charts[i]];
        if (image.state[pixel] != TexelState::Covered || centreOnGeometry(chart, image, pixel)) continue;
        const int x = static_cast<int>(pixel % image.width) - chart.x, y = static_cast<int>(pixel / image.width) - chart.y;
        DVec2 p_plane;
        size_t face = 0;
        const double coverage = texelCoverage(chart, x, y, p_plane, face);
        if (!(coverage > 0.0)) continue;
        Row row;
        row.weight = kCoveredPrior * std::min(coverage, 1.0);
        row.target = DVec3(image.rgb[3 * pixel], image.rgb[3 * pixel + 1], image.rgb[3 * pixel + 2]);
        row.anchored = true;
        addStencil(image, atlas, unknowns.charts[i], chart.atlasTexel(p_plane), 1.0, unknowns, row);
        rows.push_back(row);
    }
}

// Unknowns coupled through rows (a connected component of the fit), with their rows; in
// order of their smallest unknown, each listing its own in increasing order.
struct Coupled {
    std::vector<uint32_t> unknowns;
    std::vector<uint32_t> rows;
};

std::vector<Coupled> coupledGroups(const std::vector<Row>& rows, size_t n) {
    std::vector<uint32_t> parent(n);
    for (size_t i = 0; i < n; ++i) parent[i] = static_cast<uint32_t>(i);
    const auto find = [&](uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (const Row& row : rows)
        for (int k = 1; k < row.count; ++k) {
            const uint32_t a = find(row.taps[0].unknown), b = find(row.taps[k].unknown);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    std::vector<uint32_t> group_of(n, UINT32_MAX);
    std::vector<Coupled> groups;
    for (size_t i = 0; i < n; ++i) {
        const uint32_t root = find(static_cast<uint32_t>(i));
        if (group_of[root] == UINT32_MAX) {
            group_of[root] = static_cast<uint32_t>(groups.size());
            groups.emplace_back();
        }
        groups[group_of[root]].unknowns.push_back(static_cast<uint32_t>(i));
    }
    for (size_t r = 0; r < rows.size(); ++r)
        if (rows[r].count > 0) groups[group_of[find(rows[r].taps[0].unknown)]].rows.push_back(static_cast<uint32_t>(r));
    return groups;
}

// EdgeSample::span over samples [run, end) of one edge, consecutive along it: sample i of the
// run lies between i - d and i + d for d its lowest set bit, if both are in the run.
void setEdgeSpans(std::vector<EdgeSample>& edges, size_t run) {
    const size_t count = edges.size() - run;
    for (size_t i = 1; i + 1 < count; ++i) {
        const size_t d = i & (~i + 1);
        if (d <= kMaxEdgeSpan && i + d < count) edges[run + i].span = static_cast<uint32_t>(d);
    }
}

// Preconditioned (Jacobi) conjugate gradient on (P + sum w c c^T) delta = rhs, matrix-free,
// for the unknowns not `held` (their delta stays 0).
int solveChannel(const std::vector<Row>& rows, const std::vector<double>& prior, const std::vector<uint8_t>& held,
                 const std::vector<double>& rhs, std::vector<double>& delta) {
    const size_t n = prior.size();
    std::vector<double> diagonal = prior;
    for (const Row& row : rows)
        for (int k = 0; k < row.count; ++k) diagonal[row.taps[k].unknown] += row.weight * row.taps[k].weight * row.taps[k].weight;
    const auto apply = [&](const std::vector<double>& x, std::vector<double>& y) {
        for (size_t i = 0; i < n; ++i) y[i] = prior[i] * x[i];
        for (const Row& row : rows) {
            double dot = 0.0;
            for (int k = 0; k < row.count; ++k) dot += row.taps[k].weight * x[row.taps[k].unknown];
            dot *= row.weight;
            for (int k = 0; k < row.count; ++k) y[row.taps[k].unknown] += row.taps[k].weight * dot;
        }
        for (size_t i = 0; i < n; ++i)
            if (held[i]) y[i] = 0.0;
    };
    const auto dot = [n](const std::vector<double>& a, const std::vector<double>& b) {
        double s = 0.0;
        for (size_t i = 0; i < n; ++i) s += a[i] * b[i];
        return s;
    };
    delta.assign(n, 0.0);
    std::vector<double> r = rhs, z(n), p(n), ap(n);
    for (size_t i = 0; i < n; ++i)
        if (held[i]) r[i] = 0.0;
    const double stop = kSolveTolerance * kSolveTolerance * dot(r, r);
    for (size_t i = 0; i < n; ++i) z[i] = r[i] / diagonal[i];
    p = z;
    double rz = dot(r, z);
    int iteration = 0;
    while (iteration < kMaxIterations && dot(r, r) > stop) {
        ++iteration;
        apply(p, ap);
        const double pap = dot(p, ap);
        if (!(pap > 0.0)) break;
        const double alpha = rz / pap;
        for (size_t i = 0; i < n; ++i) {
            delta[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
        }
        for (size_t i = 0; i < n; ++i) z[i] = r[i] / diagonal[i];
        const double rz_next = dot(r, z);
        const double beta = rz_next / rz;
        rz = rz_next;
        for (size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    }
    return iteration;
}

// Where a texel may go in the fit, per channel. A covered texel stays between its own value
// and the light at the points whose lookups read it: on a chart narrower than a texel, two
// edges a fraction of a texel apart ask for any gradient, and an unbounded fit runs their
// texels far past every read-out (and the padding below 0). A padding texel extrapolates the
// light past the chart's edge, so its range (its own value, the light it serves, the texels it
// is read with) widens on each side by kPaddingReach widths over the largest weight w it has
// in those lookups: a lookup reading it with weight w needs it (1 - w) / w widths past that
// range, more where padding texels share a corner. Light is never negative.
struct Bounds {
    std::vector<double> lo, hi;
};

Bounds fitBounds(const std::vector<Row>& rows, const std::vector<double>& x0, const std::vector<uint8_t>& covered,
                 int channel) {
    Bounds b{x0, x0};
    std::vector<double> reach(x0.size(), 0.0);
    for (const Row& row : rows) {
        if (!row.anchored) continue;
        const double target = row.target[channel];
        double lo = target, hi = target;
        for (int k = 0; k < row.count; ++k) {
            lo = std::min(lo, x0[row.taps[k].unknown]);
            hi = std::max(hi, x0[row.taps[k].unknown]);
        }
        for (int k = 0; k < row.count; ++k) {
            const uint32_t i = row.taps[k].unknown;
            if (!(row.taps[k].weight > 0.0)) continue;
            b.lo[i] = std::min(b.lo[i], covered[i] ? target : lo);
            b.hi[i] = std::max(b.hi[i], covered[i] ? target : hi);
            reach[i] = std::max(reach[i], row.taps[k].weight);
        }
    }
    for (size_t i = 0; i < x0.size(); ++i) {
        const double widen = covered[i] ? 0.0 : kPaddingReach * (b.hi[i] - b.lo[i]) / std::max(reach[i], kLeastReach);
        b.lo[i] = std::max(b.lo[i] - widen, 0.0);
        b.hi[i] = std::max(b.hi[i] + widen, b.lo[i]);
    }
    return b;
}

// The fit's error at x (what solveChannel minimises from there) and minus its gradient: where
// the fit pulls each unknown.
double fitError(const std::vector<Row>& rows, const std::vector<double>& prior, const std::vector<double>& x0,
                const std::vector<double>& x, int channel) {
    double error = 0.0;
    for (size_t i = 0; i < x.size(); ++i) error += prior[i] * (x[i] - x0[i]) * (x[i] - x0[i]);
    for (const Row& row : rows) {
        double residual = row.target[channel];
        for (int k = 0; k < row.count; ++k) residual -= row.taps[k].weight * x[row.taps[k].unknown];
        error += row.weight * residual * residual;
    }
    return 0.5 * error;
}

std::vector<double> fitPull(const std::vector<Row>& rows, const std::vector<double>& prior, const std::vector<double>& x0,
                            const std::vector<double>& x, int channel) {
    std::vector<double> pull(x.size());
    for (size_t i = 0; i < x.size(); ++i) pull[i] = prior[i] * (x0[i] - x[i]);
    for (const Row& row : rows) {
        double residual = row.target[channel];
        for (int k = 0; k < row.count; ++k) residual -= row.taps[k].weight * x[row.taps[k].unknown];
        for (int k = 0; k < row.count; ++k) pull[row.taps[k].unknown] += row.weight * row.taps[k].weight * residual;
    }
    return pull;
}

// Unknowns at a bound that the fit pulls past it.
std::vector<uint8_t> heldAtBounds(const std::vector<double>& x, const std::vector<double>& pull, const Bounds& bounds) {
    std::vector<uint8_t> held(x.size());
    for (size_t i = 0; i < x.size(); ++i)
        held[i] = (x[i] >= bounds.hi[i] && pull[i] > 0.0) || (x[i] <= bounds.lo[i] && pull[i] < 0.0);
    return held;
}

// From x towards x + delta within the bounds: the step clamped to them, halved while that does
// not lower the fit's error, else as far as every unknown stays in range (the error falls
// along delta). Sets `clamped` when the step taken was clamped or shortened.
std::vector<double> boundedStep(const std::vector<Row>& rows, const std::vector<double>& prior, const std::vector<double>& x0,
                                const std::vector<double>& x, const std::vector<double>& delta, const Bounds& bounds,
                                int channel, bool& clamped) {
    const size_t n = x.size();
    const double before = fitError(rows, prior, x0, x, channel);
    std::vector<double> trial(n);
    for (double step = 1.0; step > 0.1; step *= 0.5) {
        clamped = step < 1.0;
        for (size_t i = 0; i < n; ++i) {
            trial[i] = std::clamp(x[i] + step * delta[i], bounds.lo[i], bounds.hi[i]);
            clamped = clamped || trial[i] != x[i] + step * delta[i];
        }
        if (fitError(rows, prior, x0, trial, channel) <= before) return trial;
    }
    double step = 1.0;
    for (size_t i = 0; i < n; ++i) {
        if (delta[i] > 0.0) step = std::min(step, (bounds.hi[i] - x[i]) / delta[i]);
        if (delta[i] < 0.0) step = std::min(step, (bounds.lo[i] - x[i]) / delta[i]);
    }
    clamped = true;
    for (size_t i = 0; i < n; ++i) trial[i] = std::clamp(x[i] + std::max(step, 0.0) * delta[i], bounds.lo[i], bounds.hi[i]);
    return trial;
}

// The least-squares fit of one channel within its bounds, from x0 (in range): gradient
// projection with the conjugate gradient on the unknowns not held (Moré and Toraldo 1991).
// Each round holds the unknowns at a bound that the fit pulls past it, solves for the rest and
// steps within the bounds; it stops when a whole step holds the same unknowns, when a round
// gains under kBoundProgress, or after kBoundRounds, always in range. Returns the CG steps.
int solveBounded(const std::vector<Row>& rows, const std::vector<double>& prior, const std::vector<double>& x0,
                 const Bounds& bounds, int channel, std::vector<double>& x) {
    x = x0;
    int iterations = 0;
    for (int round = 0; round < kBoundRounds; ++round) {
        const std::vector<double> pull = fitPull(rows, prior, x0, x, channel);
        const std::vector<uint8_t> held = heldAtBounds(x, pull, bounds);
        std::vector<double> delta;
        iterations += solveChannel(rows, prior, held, pull, delta);
        const double before = fitError(rows, prior, x0, x, channel);
        bool clamped = false;
        x = boundedStep(rows, prior, x0, x, delta, bounds, channel, clamped);
        if (!(before - fitError(rows, prior, x0, x, channel) > kBoundProgress * before)) break;
        if (!clamped && heldAtBounds(x, fitPull(rows, prior, x0, x, channel), bounds) == held) break;
    }
    return iterations;
}

}  // namespace

DVec3 bilinearLookup(const LightmapImage& image, const DVec2& texel) {
    const double x = texel.x - 0.5, y = texel.y - 0.5;
    const double fx0 = std::floor(x), fy0 = std::floor(y);
    const double fx = x - fx0, fy = y - fy0;
    const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
    DVec3 sum(0.0);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const int xi = std::clamp(x0 + dx, 0, image.width - 1), yi = std::clamp(y0 + dy, 0, image.height - 1);
            const size_t at = 3 * (static_cast<size_t>(yi) * image.width + xi);
            const double w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy);
            sum += w * DVec3(image.rgb[at], image.rgb[at + 1], image.rgb[at + 2]);
        }
    return sum;
}

ChartEdges findChartEdges(const Scene& scene, const LightmapLayout& layout) {
    ChartEdges result;
    const double tolerance = kLightmapWeld * lightmapExtent(scene);
    std::vector<std::vector<uint32_t>> welded(scene.meshes.size());
    for (size_t m = 0; m < scene.meshes.size(); ++m) welded[m] = weldLightmapVertices(scene.meshes[m], tolerance);

    std::vector<BoundaryEdge> edges;
    for (uint32_t c = 0; c < layout.charts.size(); ++c)
        if (layout.charts[c].atlas >= 0 && layout.charts[c].mesh < scene.meshes.size())
            chartBoundary(layout.charts[c], c, edges);

    std::map<EdgeKey, std::vector<size_t>> groups;  // ordered: deterministic pairing
    for (size_t e = 0; e < edges.size(); ++e)
        groups[edgeKey(layout.charts[edges[e].chart], edges[e], scene, welded)].push_back(e);
    for (const auto& [key, members] : groups)
        for (size_t i = 0; i < members.size(); ++i)
            for (size_t j = i + 1; j < members.size(); ++j) {
                BoundaryEdge& e1 = edges[members[i]];
                BoundaryEdge& e2 = edges[members[j]];
                if (e1.chart == e2.chart) continue;
                const LightmapChart& c1 = layout.charts[e1.chart];
                if (!sameSurface(scene, c1, c1.faces[e1.face], layout.charts[e2.chart].faces[e2.face])) continue;
                pairEdges(layout, e1, e2, tolerance, result.seams);
            }

    // Seam ends by chart and position, so a chart corner on a seam takes the seam's light.
    using PointKey = std::tuple<uint32_t, int64_t, int64_t, int64_t>;
    const auto pointKey = [cell = 16.0 * tolerance](uint32_t chart, const DVec3& p) {
        return PointKey{chart, std::llround(p.x / cell), std::llround(p.y / cell), std::llround(p.z / cell)};
    };
    std::map<PointKey, int64_t> seam_ends;
    for (size_t k = 0; k < result.seams.size(); ++k) {
        seam_ends.emplace(pointKey(result.seams[k].a.chart, result.seams[k].a.p_world), static_cast<int64_t>(k));
        seam_ends.emplace(pointKey(result.seams[k].b.chart, result.seams[k].b.p_world), static_cast<int64_t>(k));
    }
    for (const BoundaryEdge& edge : edges) {
        const LightmapChart& chart = layout.charts[edge.chart];
        const int n = sampleCount(glm::length(edge.q - edge.p) * chart.texels_per_metre);
        size_t run = result.edges.size();  // the first of the consecutive samples kept so far
        for (int k = 0; k < n; ++k) {
            const double t = static_cast<double>(k) / (n - 1);
            const bool on_seam = std::any_of(edge.seamed.begin(), edge.seamed.end(), [t](const auto& interval) {
                return t >= interval.first - 1e-9 && t <= interval.second + 1e-9;
            });
            if (on_seam) {
                setEdgeSpans(result.edges, run);
                run = result.edges.size();
                continue;
            }
            EdgeSample sample = edgeSample(chart, edge, t);
            if (k == 0 || k == n - 1) {
                const auto it = seam_ends.find(pointKey(edge.chart, sample.p_world));
                if (it != seam_ends.end()) sample.seam = it->second;
            }
            result.edges.push_back(sample);
        }
        setEdgeSpans(result.edges, run);
    }
    return result;
}

EdgeLight readChartEdges(const ChartEdges& found, const IrradianceFunction& irradiance, ParallelRunner& runner,
                         double tolerance, double dark_light, std::span<const uint8_t> wanted,
                         const std::function<void(bool)>& shared) {
    // Every query: the edges, then each seam's two sides; each belongs to its sample's chart.
    std::vector<const EdgeSample*> queries;
    for (const EdgeSample& e : found.edges) queries.push_back(&e);
    for (const SeamSample& s : found.seams) {
        queries.push_back(&s.a);
        queries.push_back(&s.b);
    }
    const auto isWanted = [&](size_t q) {
        const uint32_t chart = queries[q]->chart;
        return wanted.empty() || (chart < wanted.size() && wanted[chart]);
    };
    EdgeLight out;
    out.light.assign(queries.size(), DVec3(0.0));
    out.read.assign(queries.size(), 0);
    // A point seen with one normal is evaluated once: both sides of a cut through a flat
    // region, and the shared ends of consecutive boundary edges, ask for the same light. It is
    // read as its first query (its triangle), which owns it. With a tolerance, samples between
    // two others wait for them (later passes, widest spans first).
    const auto deferred = [&](size_t q) { return tolerance > 0.0 && q < found.edges.size() && found.edges[q].span > 0; };
    std::map<std::array<double, 6>, size_t> distinct_ids;  // ordered: first-seen order is deterministic
    std::vector<size_t> distinct_of(queries.size(), SIZE_MAX);
    std::vector<size_t> first_query;  // per distinct point
    for (size_t q = 0; q < queries.size(); ++q) {
        if (deferred(q)) continue;
        const DVec3& p = queries[q]->p_world;
        const DVec3& n = queries[q]->normal_world;
        const auto [it, added] = distinct_ids.emplace(std::array<double, 6>{p.x, p.y, p.z, n.x, n.y, n.z}, first_query.size());
        if (added) first_query.push_back(q);
        distinct_of[q] = it->second;
    }
    const auto evaluate = [&](const std::vector<size_t>& points, std::vector<DVec3>& light) {
        light.resize(points.size());
        runner.forRanges(points.size(), 16, [&](size_t begin, size_t end) {
            for (size_t k = begin; k < end; ++k) {
                const EdgeSample& e = *queries[points[k]];
                light[k] = irradiance({e.p_world, e.normal_world, e.mesh, e.triangle}) / kPi;
            }
        });
    };
    // The distinct points the wanted queries need, those their charts own read apart from the
    // rest (which another shard owns and counts).
    std::vector<uint8_t> needed(first_query.size(), 0);
    for (size_t q = 0; q < queries.size(); ++q)
        if (!deferred(q) && isWanted(q)) needed[distinct_of[q]] = 1;
    std::vector<size_t> owned, others;
    for (size_t d = 0; d < first_query.size(); ++d)
        if (needed[d]) (isWanted(first_query[d]) ? owned : others).push_back(first_query[d]);
    std::vector<DVec3> distinct_light(first_query.size()), owned_light, other_light;
    if (!others.empty()) {
        if (shared) shared(true);
        evaluate(others, other_light);
        if (shared) shared(false);
    }
    evaluate(owned, owned_light);
    for (size_t k = 0; k < owned.size(); ++k) distinct_light[distinct_of[owned[k]]] = owned_light[k];
    for (size_t k = 0; k < others.size(); ++k) distinct_light[distinct_of[others[k]]] = other_light[k];
    out.evaluations = owned.size();
    for (size_t q = 0; q < queries.size(); ++q)
        if (!deferred(q) && isWanted(q)) {
            out.light[q] = distinct_light[distinct_of[q]];
            out.read[q] = 1;
        }
    if (tolerance > 0.0) {
        double brightest_edge = 0.0;
        for (const DVec3& l : distinct_light) brightest_edge = std::max({brightest_edge, l.x, l.y, l.z});
        const double dark = dark_light >= 0.0 ? dark_light : kDarkEdge * brightest_edge;
        std::vector<DVec3>& light = out.light;
        for (size_t span = kMaxEdgeSpan; span > 0; span /= 2) {
            std::vector<size_t> rest;
            for (size_t q = 0; q < found.edges.size(); ++q) {
                if (found.edges[q].span != span || !isWanted(q)) continue;
                const DVec3 &before = light[q - span], &after = light[q + span];
                bool agree = true;
                for (int c = 0; c < 3; ++c)
                    agree = agree && std::fabs(before[c] - after[c]) <=
                                         tolerance * std::max(0.5 * std::fabs(before[c] + after[c]), dark);
                if (agree) light[q] = 0.5 * (before + after);
                else rest.push_back(q);
                out.read[q] = 1;
            }
            std::vector<DVec3> rest_light;
            evaluate(rest, rest_light);
            for (size_t k = 0; k < rest.size(); ++k) light[rest[k]] = rest_light[k];
            out.evaluations += rest.size();
        }
    }
    return out;
}

StitchStats stitchLightmaps(const Scene& scene, Lightmaps& lightmaps, const IrradianceFunction& irradiance, int padding,
                            ParallelRunner& runner, double tolerance, double dark_light) {
    if (padding < 1 || lightmaps.images.empty()) {
        lightmaps.stitch = StitchStats{};
        return lightmaps.stitch;
    }
    const ChartEdges found = findChartEdges(scene, lightmaps.layout);
    const EdgeLight light = readChartEdges(found, irradiance, runner, tolerance, dark_light);
    return fitChartEdges(lightmaps, found, light, runner);
}

StitchStats fitChartEdges(Lightmaps& lightmaps, const ChartEdges& found, const EdgeLight& edge_light,
                          ParallelRunner& runner) {
    StitchStats stats;
    const LightmapLayout& layout = lightmaps.layout;
    stats.edge_samples = found.edges.size();
    stats.seam_samples = found.seams.size();
    stats.evaluations = edge_light.evaluations;
    const std::vector<DVec3>& light = edge_light.light;
    double brightest = 0.0;
    for (const DVec3& l : light) brightest = std::max({brightest, l.x, l.y, l.z});
    const double floor = std::max(1e-6 * brightest, 1e-30);  // relative gaps in the dark are measured against this

    const auto atlasOf = [&](const EdgeSample& e) { return layout.charts[e.chart].atlas; };
    const auto imageOf = [&](const EdgeSample& e) -> const LightmapImage& { return lightmaps.images[atlasOf(e)]; };
    for (const SeamSample& s : found.seams)
        stats.max_seam_before = std::max(stats.max_seam_before, relativeGap(bilinearLookup(imageOf(s.a), s.a.texel),
                                                                            bilinearLookup(imageOf(s.b), s.b.texel), floor));

    Unknowns unknowns;
    std::vector<Row> rows;
    const auto anchor = [&](const EdgeSample& e, const DVec3& target) {
        Row row;
        row.weight = kEdgeWeight;
        row.target = target;
        row.anchored = true;
        addStencil(imageOf(e), atlasOf(e), e.chart, e.texel, 1.0, unknowns, row);
        rows.push_back(row);
    };
    // A seam point aims at the mean of the light on its two faces (the vertex bake's average
    // over face normals), from both sides.
    const auto seamTarget = [&](size_t k) {
        return 0.5 * (light[found.edges.size() + 2 * k] + light[found.edges.size() + 2 * k + 1]);
    };
    for (size_t k = 0; k < found.edges.size(); ++k)
        anchor(found.edges[k], found.edges[k].seam >= 0 ? seamTarget(static_cast<size_t>(found.edges[k].seam)) : light[k]);
    for (size_t k = 0; k < found.seams.size(); ++k) {
        const SeamSample& s = found.seams[k];
        const DVec3 target = seamTarget(k);
        anchor(s.a, target);
        anchor(s.b, target);
        Row row;
        row.weight = kSeamWeight;
        addStencil(imageOf(s.a), atlasOf(s.a), s.a.chart, s.a.texel, 1.0, unknowns, row);
        addStencil(imageOf(s.b), atlasOf(s.b), s.b.chart, s.b.texel, -1.0, unknowns, row);
        rows.push_back(row);
    }
    addOwnPointRows(layout, lightmaps.images, unknowns, rows);
    const size_t n = unknowns.texels.size();
    stats.texels = n;
    std::vector<double> prior(n);
    for (size_t i = 0; i < n; ++i) {
        const auto [atlas, pixel] = unknowns.texels[i];
        const LightmapImage& image = lightmaps.images[atlas];
        if (image.state[pixel] != TexelState::Covered) prior[i] = kFree;
        else prior[i] = centreOnGeometry(layout.charts[unknowns.charts[i]], image, pixel) ? kCoveredPrior : kPartialPrior;
    }
    // The system falls apart into groups of charts joined by seams: each is solved on its
    // own, in parallel, writing only its own texels (so the result does not depend on the
    // thread count), and none waits for the slowest one's iterations. As one system, graz.wrl's
    // 122k texels spent 15 s in the conjugate gradient, a third of its bake.
    const std::vector<Coupled> groups = coupledGroups(rows, n);
    std::vector<uint32_t> local_of(n);
    for (const Coupled& group : groups)
        for (size_t i = 0; i < group.unknowns.size(); ++i) local_of[group.unknowns[i]] = static_cast<uint32_t>(i);
    std::vector<std::array<double, 3>> solved(n);
    std::vector<int> group_iterations(groups.size(), 0);
    runner.forEach(groups.size(), 1, [&](size_t g) {
        const Coupled& group = groups[g];
        const size_t m = group.unknowns.size();
        std::vector<Row> local_rows;
        local_rows.reserve(group.rows.size());
        for (const uint32_t r : group.rows) {
            Row row = rows[r];
            for (int k = 0; k < row.count; ++k) row.taps[k].unknown = local_of[row.taps[k].unknown];
            local_rows.push_back(row);
        }
        std::vector<double> local_prior(m);
        std::vector<uint8_t> covered(m);
        for (size_t i = 0; i < m; ++i) {
            const auto [atlas, pixel] = unknowns.texels[group.unknowns[i]];
            local_prior[i] = prior[group.unknowns[i]];
            covered[i] = lightmaps.images[atlas].state[pixel] == TexelState::Covered;
        }
        for (int c = 0; c < 3; ++c) {
            std::vector<double> x0(m), x;
            for (size_t i = 0; i < m; ++i) {
                const auto [atlas, pixel] = unknowns.texels[group.unknowns[i]];
                x0[i] = lightmaps.images[atlas].rgb[3 * pixel + c];
            }
            group_iterations[g] += solveBounded(local_rows, local_prior, x0, fitBounds(local_rows, x0, covered, c), c, x);
            for (size_t i = 0; i < m; ++i) solved[group.unknowns[i]][c] = x[i];
        }
    });
    for (const int i : group_iterations) stats.iterations += i;
    for (size_t i = 0; i < n; ++i) {
        const auto [atlas, pixel] = unknowns.texels[i];
        LightmapImage& image = lightmaps.images[atlas];
        for (int c = 0; c < 3; ++c) image.rgb[3 * pixel + c] = static_cast<float>(solved[i][c]);
        if (image.state[pixel] == TexelState::Empty) image.state[pixel] = TexelState::Dilated;
    }

    for (const SeamSample& s : found.seams)
        stats.max_seam_after = std::max(stats.max_seam_after, relativeGap(bilinearLookup(imageOf(s.a), s.a.texel),
                                                                          bilinearLookup(imageOf(s.b), s.b.texel), floor));
    for (size_t k = 0; k < found.edges.size(); ++k)
        if (found.edges[k].seam < 0)
            stats.max_edge_after = std::max(
                stats.max_edge_after, relativeGap(bilinearLookup(imageOf(found.edges[k]), found.edges[k].texel), light[k], floor));
    lightmaps.stitch = stats;
    return stats;
}

}  // namespace radbake
