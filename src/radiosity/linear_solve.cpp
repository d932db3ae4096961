#include "radiosity/linear_solve.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <numeric>

#include "core/progress.h"
#include "radiosity/cluster.h"
#include "radiosity/elements.h"
#include "radiosity/form_factor.h"
#include "radiosity/refine.h"

namespace radbake {
namespace {

using Vector = std::vector<DVec3>;

// Restart length: at least enough for the slow modes of rho ~ 0.99 to be caught in one cycle,
// longer while the basis stays small (closed rooms at rho 0.999 restarted every 40 steps lose
// what each cycle learnt), its memory bounded by kBasisBytes.
constexpr size_t kMinRestart = 40, kMaxRestart = 120;
constexpr size_t kBasisBytes = size_t(256) << 20;
// A solve phase's progress: its set-up (row sums most of all) up to kSetUpShare, then GMRES by
// the residual's decades to the tolerance. Rough shares: the set-up dominates on large scenes.
constexpr double kSetUpShare = 0.5, kRowSumShare = 0.4;

int restartLength(size_t n) {
    return static_cast<int>(std::clamp(kBasisBytes / (sizeof(DVec3) * std::max<size_t>(n, 1)), kMinRestart, kMaxRestart));
}

struct Operator {
    Solution& s;
    ParallelRunner& runner;
    std::vector<uint32_t> leaves;
    std::vector<double> weight;       // per leaf: area / total leaf area
    std::vector<size_t> link_begin;   // per element + 1
    std::vector<DVec3> pushed;        // per element: irradiance gathered here and above
    // Per element: the part of `pushed` through links whose visibility no shaft proved whole
    // (rays sampled it, or it is partial), which a leaf below inherits from an ancestor whose
    // view it may not share.
    std::vector<DVec3> pushed_sampled;
    std::vector<double> correction;   // per leaf: exact / hierarchical row sum (see below)
    std::vector<double> inherited_scale;  // per leaf: on its inherited sampled links (limitRowSums)
    ClusterTransfer clusters;         // cluster links (cluster.h)
    std::vector<DVec3> cluster_h;     // per root: irradiance through cluster links
    std::vector<double> cluster_share;  // per leaf: its share of its root's cluster irradiance

    RowSumCache* cache = nullptr;
    Progress* progress = nullptr;  // the set-up's share of the phase, moved by the row sums

    Operator(Solution& solution, ParallelRunner& r, RowSumCache* row_cache, Progress* phase)
        : s(solution), runner(r), clusters(solution), cache(row_cache), progress(phase) {
        double total = 0.0;
        for (uint32_t i = 0; i < s.elements.size(); ++i)
            if (s.elements[i].isLeaf()) {
                leaves.push_back(i);
                total += s.elements[i].area;
            }
        for (uint32_t leaf : leaves) weight.push_back(total > 0.0 ? s.elements[leaf].area / total : 0.0);
        link_begin.assign(s.elements.size() + 1, 0);
        for (const Link& link : s.links) ++link_begin[link.receiver + 1];
        for (size_t i = 0; i < s.elements.size(); ++i) link_begin[i + 1] += link_begin[i];
        pushed.assign(s.elements.size(), DVec3(0.0));
        pushed_sampled.assign(s.elements.size(), DVec3(0.0));
        computeCorrections();
        cluster_share = clusters.leafFactors(s, runner, leaves, cache ? &cache->cluster_kernels : nullptr);
        limitRowSums();
        if (progress) progress->update(kSetUpShare);
    }

    // Pushing a link's irradiance down assumes the form factor is uniform over its receiver;
    // the oracle bounds the misplaced power, not the local error, so a small leaf near a
    // corner can inherit row sums of 1.4 (and at rho = 0.99 the system then has no physical
    // solution). Each leaf's pushed irradiance is therefore scaled by
    //   sum over inherited links of V F(leaf centroid -> source) / sum of V F(link),
    // which is exact for uniform radiosity and keeps row sums at their geometric value.
    // The point form factor to `source` averaged over the leaf: 2 x 2 Gauss points on a quad
    // (the centroid alone is biased where the leaf touches the source: that bias, ~1e-5 of
    // the row sums, read 3.7 % high in a closed room at rho = 0.999), the centroid otherwise.
    // A source farther than kFarSource x (both radii) varies so little over the leaf that the
    // centroid rule is within ~0.4 % of the Gauss average (curvature ~ (r / d)^2), at a
    // quarter of its cost; the corrections only redistribute within a root, so this moves
    // no power (it was most of a solve's set-up on the 35k-triangle classroom).
    static constexpr double kFarSource = 8.0;
    bool centroidRule(const Element& leaf, const Element& source) const {
        const DVec3 d = source.centroid - leaf.centroid;
        const double near = kFarSource * (leaf.radius + source.radius);
        return leaf.vertex_count != 4 || glm::dot(d, d) > near * near;
    }
    // V x the leaf average of every link the leaf inherits, summed in link order (the centroid
    // rule's form factors computed two sources at a time).
    double inheritedExactSum(const Element& leaf) const {
        thread_local std::vector<PolygonView> far;
        thread_local std::vector<double> far_f;
        far.clear();
        for (uint32_t a = leaf.parent; a != kNoElement; a = s.elements[a].parent)
            for (size_t l = link_begin[a]; l < link_begin[a + 1]; ++l) {
                const Element& source = s.elements[s.links[l].source];
                if (centroidRule(leaf, source)) far.push_back(polygonOf(s, source));
            }
        far_f.resize(far.size());
        pointPolygonFormFactorsTo(leaf.centroid, leaf.normal, far, far_f.data());
        const PolygonView poly = polygonOf(s, leaf);
        double exact = 0.0;
        size_t next = 0;
        for (uint32_t a = leaf.parent; a != kNoElement; a = s.elements[a].parent)
            for (size_t l = link_begin[a]; l < link_begin[a + 1]; ++l) {
                const Element& source = s.elements[s.links[l].source];
                const double f = centroidRule(leaf, source) ? far_f[next++]
                                                            : gaussAveragedFormFactor(poly.vertices, leaf.normal,
                                                                                      polygonOf(s, source).vertices,
                                                                                      source.normal);
                exact += s.links[l].visibility * f;
            }
        return exact;
    }

    void computeCorrections() {
        correction.assign(leaves.size(), 1.0);
        std::vector<double> row_hier(leaves.size(), 0.0), row_exact(leaves.size(), 0.0);
        ElementMemo* kept = cache ? &cache->row_sums : nullptr;
        if (kept) kept->cover(s.elements.size());
        std::atomic<size_t> done{0};
        const auto rowSums = [&](size_t k) {
            if (progress && ++done % 1024 == 0)
                progress->update(kRowSumShare * static_cast<double>(done) / static_cast<double>(leaves.size()));
            const Element& leaf = s.elements[leaves[k]];
            double hierarchical = 0.0, exact = 0.0;
            // Of the inherited links' sources and visibilities, in order: what the exact sum reads.
            uint64_t signature = ElementMemo::kSignatureSeed;
            for (uint32_t a = leaf.parent; a != kNoElement; a = s.elements[a].parent) {
                for (size_t l = link_begin[a]; l < link_begin[a + 1]; ++l) {
                    const Link& link = s.links[l];
                    hierarchical += link.form_factor;
                    uint32_t visibility_bits = 0;
                    std::memcpy(&visibility_bits, &link.visibility, sizeof visibility_bits);
                    signature = mixHash(signature, (uint64_t(link.source) << 32) | visibility_bits);
                }
            }
            if (!kept || !kept->find(leaves[k], signature, exact)) {
                exact = inheritedExactSum(leaf);
                if (kept) kept->keep(leaves[k], signature, exact);
            }
            double own = 0.0;
            for (size_t l = link_begin[leaves[k]]; l < link_begin[leaves[k] + 1]; ++l) own += s.links[l].form_factor;
            row_hier[k] = own + hierarchical;
            row_exact[k] = own + exact;
        };
        runner.forEachShared(
            leaves.size(), 64, rowSums, [&](Writer& w, size_t k) { w.value(row_hier[k]), w.value(row_exact[k]); },
            [&](Reader& r, size_t k) { r.value(row_hier[k]), r.value(row_exact[k]); });
        // The centroid rule is biased near adjacent sources, while the hierarchical sums are
        // exact in power over each receiver. Keep each root's power: the corrections only
        // redistribute within a root.
        std::vector<double> hier_power(s.root_count, 0.0), exact_power(s.root_count, 0.0);
        for (size_t k = 0; k < leaves.size(); ++k) {
            const Element& leaf = s.elements[leaves[k]];
            hier_power[leaf.root] += leaf.area * row_hier[k];
            exact_power[leaf.root] += leaf.area * row_exact[k];
        }
        for (size_t k = 0; k < leaves.size(); ++k) {
            const uint32_t root = s.elements[leaves[k]].root;
            if (row_hier[k] > 0.0 && exact_power[root] > 0.0)
                correction[k] = row_exact[k] / row_hier[k] * (hier_power[root] / exact_power[root]);
        }
    }

    // No surface sees more than its hemisphere: a leaf's row sum (its form factors to every
    // source, element and cluster links alike) is at most 1. Where it is more, visibility or
    // a cluster kernel was wrong: stacked layers a few millimetres apart each counted as seen
    // (the sides inside a thin closed binder), a separable kernel misread close to its
    // receiver. House.wrl had leaves at 2.7 and graz.wrl at 3.0, office.wrl at 9.8 from cluster
    // links; with rho near 1 such rows amplify light (no physical solution) and took GMRES
    // hundreds of iterations. Such a row is scaled to 1 on its uncertain part: what the leaf
    // inherits through its ancestors' links whose visibility rays sampled over more than the
    // leaf, and its cluster links. A ceiling leaf just above a lamp inherits a view past the
    // lamp, and scaling the whole row dimmed the lamp's direct light there, and with it the
    // room's bounced light. Only a leaf whose certain part alone reaches 1 is scaled whole,
    // keeping its sources' proportions. Rows
    // up to kRowLimit are left: next to a contact line the quadrature reads single leaves up to
    // 1.24 (duplex.wrl), which their neighbours make up (a root keeps its power, above), and
    // scaling those moved duplex's probes away from their Monte Carlo reference.
    static constexpr double kRowLimit = 1.25;
    void limitRowSums() {
        inherited_scale.assign(leaves.size(), 1.0);
        std::vector<DVec3> saved(leaves.size());
        for (size_t k = 0; k < leaves.size(); ++k) {
            saved[k] = s.elements[leaves[k]].radiosity;
            s.elements[leaves[k]].radiosity = DVec3(1.0);
        }
        pullRadiosity(s);
        gatherElementLinks();
        if (!clusters.empty()) clusters.gather(s, runner, cluster_h);
        size_t limited = 0;
        for (size_t k = 0; k < leaves.size(); ++k) {
            const Element& leaf = s.elements[leaves[k]];
            const double certain = correction[k] * (pushed[leaves[k]] - inheritedSampled(leaf)).x;
            double row = correction[k] * pushed[leaves[k]].x;
            if (!clusters.empty()) row += cluster_share[k] * cluster_h[leaf.root].x;
            if (!(row > kRowLimit)) continue;
            ++limited;
            if (certain < 1.0) {
                const double scale = (1.0 - certain) / (row - certain);
                inherited_scale[k] = scale;
                if (!clusters.empty()) cluster_share[k] *= scale;
            } else {
                correction[k] /= row;
                if (!clusters.empty()) cluster_share[k] /= row;
            }
        }
        s.stats.limited_row_sums = std::max(s.stats.limited_row_sums, limited);
        for (size_t k = 0; k < leaves.size(); ++k) s.elements[leaves[k]].radiosity = saved[k];
        pullRadiosity(s);
    }

    // gathered = sum over the element's own links of F B, pushed = that summed down from the roots.
    void gatherElementLinks() {
        // Shared between ranks: what crosses per application is two vectors per element.
        runner.forEachShared(
            s.elements.size(), 256,
            [&](size_t i) {
                DVec3 h(0.0), sampled(0.0);
                for (size_t l = link_begin[i]; l < link_begin[i + 1]; ++l) {
                    const Link& link = s.links[l];
                    const DVec3 light = link.form_factor * s.elements[link.source].radiosity;
                    h += light;
                    if (link.by_rays || link.visibility < 1.0f) sampled += light;
                }
                s.elements[i].gathered = h;
                pushed_sampled[i] = sampled;
            },
            [&](Writer& w, size_t i) { w.value(s.elements[i].gathered), w.value(pushed_sampled[i]); },
            [&](Reader& r, size_t i) { r.value(s.elements[i].gathered), r.value(pushed_sampled[i]); });
        // Parents precede their children in the element array.
        for (size_t i = 0; i < s.elements.size(); ++i) {
            const Element& e = s.elements[i];
            if (e.parent == kNoElement) {
                pushed[i] = e.gathered;
                continue;
            }
            pushed[i] = e.gathered + pushed[e.parent];
            pushed_sampled[i] += pushed_sampled[e.parent];
        }
    }

    // What a leaf inherits through its ancestors' links whose visibility no shaft proved whole.
    DVec3 inheritedSampled(const Element& leaf) const {
        return leaf.parent == kNoElement ? DVec3(0.0) : pushed_sampled[leaf.parent];
    }

    // y = rho K x (x, y: leaf radiosities / reflected exitance).
    void apply(const Vector& x, Vector& y) {
        for (size_t k = 0; k < leaves.size(); ++k) s.elements[leaves[k]].radiosity = x[k];
        pullRadiosity(s);
        gatherElementLinks();
        y.resize(leaves.size());
        for (size_t k = 0; k < leaves.size(); ++k) {
            const Element& leaf = s.elements[leaves[k]];
            const DVec3 h = pushed[leaves[k]] - (1.0 - inherited_scale[k]) * inheritedSampled(leaf);
            y[k] = correction[k] * (leaf.reflectance * h);
        }
        if (clusters.empty()) return;
        // Cluster links bring a uniform irradiance per root; the row-sum correction is for the
        // element links' push-down only (a cluster link's kernel has no exact counterpart
        // short of every member pair, the quadratic cost clustering avoids).
        clusters.gather(s, runner, cluster_h);
        for (size_t k = 0; k < leaves.size(); ++k) {
            const Element& leaf = s.elements[leaves[k]];
            y[k] += cluster_share[k] * (leaf.reflectance * cluster_h[leaf.root]);
        }
        for (uint32_t r = 0; r < s.root_count; ++r) s.elements[r].gathered += cluster_h[r];
    }

    double dot(const Vector& a, const Vector& b) const {
        double sum = 0.0;
        for (size_t k = 0; k < a.size(); ++k) sum += weight[k] * glm::dot(a[k], b[k]);
        return sum;
    }
    double norm(const Vector& a) const { return std::sqrt(std::max(0.0, dot(a, a))); }
};

}  // namespace

void pullRadiosity(Solution& solution) {
    auto& elements = solution.elements;
    for (size_t i = elements.size(); i-- > 0;) {
        Element& e = elements[i];
        if (e.isLeaf()) continue;
        DVec3 sum(0.0);
        double area = 0.0;
        for (uint32_t c = 0; c < e.child_count; ++c) {
            const Element& child = elements[e.first_child + c];
            sum += child.area * child.radiosity;
            area += child.area;
        }
        e.radiosity = area > 0.0 ? sum / area : DVec3(0.0);
    }
}

void groupLinksByReceiver(Solution& solution, std::vector<LinkRecord>* records) {
    std::vector<size_t> order(solution.links.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return solution.links[a].receiver < solution.links[b].receiver;
    });
    std::vector<Link> links;
    links.reserve(order.size());
    for (size_t i : order) links.push_back(solution.links[i]);
    solution.links = std::move(links);
    if (records) {
        std::vector<LinkRecord> sorted;
        sorted.reserve(order.size());
        for (size_t i : order) sorted.push_back((*records)[i]);
        *records = std::move(sorted);
    }
}

LinearSolveResult solveHierarchy(Solution& solution, ParallelRunner& runner, SolveStart start, double tolerance,
                                 int max_iterations, RowSumCache* cache, Progress* progress) {
    Operator op(solution, runner, cache, progress);
    const size_t n = op.leaves.size();
    LinearSolveResult result;
    Vector b(n), x(n), r(n), w(n), ax(n);
    for (size_t k = 0; k < n; ++k) {
        b[k] = solution.elements[op.leaves[k]].emission;
        x[k] = start == SolveStart::Emission ? b[k] : solution.elements[op.leaves[k]].radiosity;
    }
    const double b_norm = op.norm(b);
    if (!(b_norm > 0.0)) {
        std::fill(x.begin(), x.end(), DVec3(0.0));
        op.apply(x, ax);
        result.converged = true;
        return result;
    }
    const int restart = restartLength(n);
    // The phase's fraction from the residual: the decades gone of those between the first and
    // the tolerance.
    double first_residual = -1.0;
    const auto report = [&](double residual) {
        if (!progress || !(residual > 0.0)) return;
        if (first_residual < 0.0) first_residual = residual;
        const double decades = std::log(first_residual / tolerance);
        const double done = decades > 0.0 ? std::clamp(std::log(first_residual / residual) / decades, 0.0, 1.0) : 1.0;
        progress->update(kSetUpShare + (1.0 - kSetUpShare) * done);
    };
    std::vector<Vector> basis(1, Vector(n));  // grown as the cycle needs: most solves stop early
    std::vector<std::vector<double>> h(restart + 1, std::vector<double>(restart, 0.0));
    std::vector<double> cs(restart), sn(restart), g(restart + 1), y(restart);
    while (true) {
        // True residual r = b - (x - rho K x).
        op.apply(x, ax);
        ++result.iterations;
        for (size_t k = 0; k < n; ++k) r[k] = b[k] - x[k] + ax[k];
        const double beta = op.norm(r);
        result.residual = beta / b_norm;
        report(result.residual);
        if (result.residual < tolerance) {
            result.converged = true;
            break;
        }
        if (result.iterations >= max_iterations || runner.cancelled()) break;
        for (size_t k = 0; k < n; ++k) basis[0][k] = r[k] / beta;
        std::fill(g.begin(), g.end(), 0.0);
        g[0] = beta;
        int used = 0;
        for (int j = 0; j < restart && result.iterations < max_iterations; ++j) {
            op.apply(basis[j], w);
            ++result.iterations;
            for (size_t k = 0; k < n; ++k) w[k] = basis[j][k] - w[k];
            // Modified Gram-Schmidt, fixed order.
            for (int i = 0; i <= j; ++i) {
                h[i][j] = op.dot(w, basis[i]);
                for (size_t k = 0; k < n; ++k) w[k] -= h[i][j] * basis[i][k];
            }
            h[j + 1][j] = op.norm(w);
            if (basis.size() < size_t(j) + 2) basis.emplace_back(n);
            if (h[j + 1][j] > 0.0)
                for (size_t k = 0; k < n; ++k) basis[j + 1][k] = w[k] / h[j + 1][j];
            for (int i = 0; i < j; ++i) {
                const double t = cs[i] * h[i][j] + sn[i] * h[i + 1][j];
                h[i + 1][j] = -sn[i] * h[i][j] + cs[i] * h[i + 1][j];
                h[i][j] = t;
            }
            const double d = std::hypot(h[j][j], h[j + 1][j]);
            cs[j] = d > 0.0 ? h[j][j] / d : 1.0;
            sn[j] = d > 0.0 ? h[j + 1][j] / d : 0.0;
            h[j][j] = d;
            h[j + 1][j] = 0.0;
            g[j + 1] = -sn[j] * g[j];
            g[j] = cs[j] * g[j];
            used = j + 1;
            report(std::abs(g[j + 1]) / b_norm);
            if (std::abs(g[j + 1]) / b_norm < 0.5 * tolerance || d == 0.0) break;
        }
        for (int i = used - 1; i >= 0; --i) {
            double sum = g[i];
            for (int k = i + 1; k < used; ++k) sum -= h[i][k] * y[k];
            y[i] = h[i][i] != 0.0 ? sum / h[i][i] : 0.0;
        }
        for (int i = 0; i < used; ++i)
            for (size_t k = 0; k < n; ++k) x[k] += y[i] * basis[i][k];
    }
    // The last application was at the final x: leaves hold x, parents their averages and
    // `gathered` the irradiance gathered from them.
    return result;
}

}  // namespace radbake
