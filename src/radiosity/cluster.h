#pragma once
// Clustering: a box hierarchy above the root elements, links that start at its top and
// refine down to root-root links, and the light those cluster links carry in the solve.
// The method and why: cluster.cpp.
#include <cstdint>
#include <functional>
#include <vector>

#include "core/parallel.h"
#include "radiosity/refine.h"
#include "radiosity/solution.h"

namespace radbake {

// Leaves hold at most this many roots.
inline constexpr uint32_t kClusterLeafSize = 8;
// A cluster link whose ends hold at most this many member pairs keeps a kernel per pair
// (with its own ray-cast visibility); a larger one must be wholly visible or is split.
inline constexpr uint32_t kPairwiseLimit = 64;

// Builds Solution::clusters, cluster_members, member_position and root_leaf_cluster: a
// deterministic top-down median split of the roots' centroids along the widest axis of
// their bounds, down to leaves of at most kClusterLeafSize roots.
void buildClusters(Solution& solution);

// A cluster link waiting for the oracle (nodes as in ClusterLink).
struct PendingClusterLink {
    uint32_t receiver = 0;
    uint32_t source = 0;
    uint32_t candidates = kNoList;
};

// The oracle's per-node data for one refinement round.
class ClusterRefiner {
public:
    explicit ClusterRefiner(RefineState& state);

    // The top cluster linked to itself, refined: final cluster links are appended to
    // Solution::cluster_links; returns the root-root links for refineLinks.
    std::vector<PendingLink> initial(Progress& progress);

    // After a solve (and RefineState::updateThresholds): the cluster links whose bound now
    // exceeds the threshold are removed and refined again. Returns the root-root links they
    // give; `changed` tells whether any cluster link was reopened. A link from a source that
    // had no light when it was evaluated is deferred (it carries nothing); reopen evaluates
    // those whose source now has light (all that `deferred_only` reopens).
    std::vector<PendingLink> reopen(Progress& progress, bool& changed, bool deferred_only = false);
    // Whether some link is deferred: the solver then refines and solves once more after its
    // last round, so light reflected by the first solve is carried.
    bool hasDeferred() const;

    // The bound on the power a link may misplace (W, max channel), for tests: rho_R A_R
    // Phi_S / (pi d_min^2), infinite when the nodes' boxes touch or overlap, 0 when the source
    // has no light.
    double bound(uint32_t receiver, uint32_t source) const;
    // Upper bound on the irradiance any point of the receiver node can get from the source
    // node (W/m^2, max channel): Phi_S / (pi d_min^2).
    double irradianceBound(uint32_t receiver, uint32_t source) const;
    // A lower bound on the distance between any point of the two nodes: the larger of the
    // boxes' distance and, for a flat end (a root, or a cluster in one plane), the other
    // box's distance from that plane (a big wall's box overlaps everything near it, its
    // plane does not). 0 when they may touch.
    double minDistance(uint32_t a, uint32_t b) const;

    // The links the last refinement's progress estimate refined ahead (0: none, as when no
    // one watches the progress); for tests.
    size_t sampledLinks() const { return sampled_links_; }

    // Per-node power and thresholds for the oracle, from the roots' radiosity (before the
    // first solve: their emission). initial and reopen call it; exposed for tests.
    void prepareRound();

private:
    std::vector<PendingLink> refine(std::vector<PendingClusterLink> pending, Progress& progress);

    RefineState& state_;
    std::vector<Aabb> root_box_;          // per root
    std::vector<DVec3> root_points_;      // per root: its ray sample points (kPointsPerMember each)
    std::vector<double> cluster_rho_;     // per cluster: max oracleReflectance (refine.h) of its members
    std::vector<double> cluster_radius_;  // per cluster: largest member radius
    std::vector<uint8_t> cluster_flat_;   // per cluster: every member in one plane (cluster_plane_)
    std::vector<Plane> cluster_plane_;
    std::vector<double> node_power_;      // per root, then per cluster: sum A B (max channel)
    std::vector<double> node_threshold_;  // per root, then per cluster: the least threshold of its members
    size_t sampled_links_ = 0;
};

// Calls join(a, b) on pairs of roots that exchange light through a cluster link (enough
// pairs to join every member that sends or receives light through it to one group), for
// the light-exchange groups of RefineState::updateThresholds.
void forEachClusterExchange(const Solution& solution, const std::function<void(uint32_t, uint32_t)>& join);

// Removes the links still deferred when the solve ends (counted as dropped): their sources
// never got light, so they carry nothing (a scene without light keeps no link at all).
void dropDeferredClusterLinks(Solution& solution);

// Sorts Solution::cluster_links by receiver node (roots first, then clusters; stable).
void groupClusterLinksByReceiver(Solution& solution);

// A value per element kept between the solves of one bake, with a signature (mixHash, from
// kSignatureSeed) of what it was computed from: used again only for the same signature. Elements
// keep their indices as the hierarchy grows, so entries stay valid across rounds.
struct ElementMemo {
    static constexpr uint64_t kSignatureSeed = 0x2545f4914f6cdd1dull;
    std::vector<uint64_t> signature;
    std::vector<double> value;
    std::vector<uint8_t> known;

    void cover(size_t elements) {
        signature.resize(elements, 0);
        value.resize(elements, 0.0);
        known.resize(elements, 0);
    }
    // Call cover() first; find and keep touch only their own element's slot (thread-safe per element).
    bool find(uint32_t e, uint64_t sig, double& out) const {
        if (!known[e] || signature[e] != sig) return false;
        out = value[e];
        return true;
    }
    void keep(uint32_t e, uint64_t sig, double v) {
        signature[e] = sig;
        value[e] = v;
        known[e] = 1;
    }
};

// The irradiance the cluster links bring, for the solve: per root, from the roots' current
// radiosity (Element::radiosity, inner averages pulled up). Links must be grouped.
class ClusterTransfer {
public:
    explicit ClusterTransfer(const Solution& solution);
    bool empty() const { return empty_; }
    // per_root[r] = irradiance (W/m^2, uniform over root r) through every cluster link whose
    // receiver holds r. Deterministic whatever the thread count.
    void gather(const Solution& solution, ParallelRunner& runner, std::vector<DVec3>& per_root);

    // Per leaf of `leaves` (element indices): how the cluster irradiance of its root is
    // shared among the root's leaves, exact for uniform radiosity like solve.cpp's row-sum
    // correction of element links: the cluster links' geometric kernel at the leaf's
    // centroid over its area average on the root (1 for a root that is its own leaf).
    // Without it a subdivided root near a room edge reads its cluster light uniform
    // (4 % errors in a tessellated furnace).
    // `kept`, when given, keeps each leaf's kernel between solves, signed by the cluster links
    // and lit member pairs it read (same result).
    std::vector<double> leafFactors(const Solution& solution, ParallelRunner& runner,
                                    const std::vector<uint32_t>& leaves, ElementMemo* kept = nullptr) const;

private:
    // Calls f(link index) for every cluster link whose receiver holds root r, in a fixed order.
    template <class F>
    void forLinksOf(const Solution& solution, uint32_t root, F&& f) const;

    bool empty_ = true;
    std::vector<size_t> link_begin_;  // per receiver key (roots, then clusters) + 1
    std::vector<DVec3> flux_;         // per separable link: sum_i s_i B_i
    std::vector<DVec3> member_radiosity_;  // per Solution::cluster_members entry
};

}  // namespace radbake
