#pragma once
// Link refinement: the oracle of Hanrahan-Salzman-Aupperle with the shaft/occlusion tests of
// Dupuy-Paulin-Caubet. Candidate links are evaluated in parallel (pure: form factor bounds,
// shaft, occlusion); decisions and element splits then run sequentially in link order, so
// element numbering and link order never depend on the thread count.
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "core/parallel.h"
#include "radiosity/solution.h"

namespace radbake {

inline constexpr uint32_t kNoList = 0xffffffffu;

struct PendingLink {
    uint32_t receiver = 0;
    uint32_t source = 0;
    uint32_t candidates = 0;  // index into RefineState::candidate_pool, kNoList: none
};

// Per final link (parallel to Solution::links): what the oracle needs to reopen it.
struct LinkRecord {
    double spread = 0.0;           // F_max - F_min, with F_min = 0 for a partial link
    uint32_t candidates = kNoList; // its potential occluders (partial links)
};

// An element corner where the sky was read: its point and its element's normal, bit for bit.
struct SkyCornerKey {
    DVec3 point, normal;
    bool operator==(const SkyCornerKey&) const = default;
};
struct SkyCornerHash {
    size_t operator()(const SkyCornerKey& k) const;
};
// Lifts (ray caster epsilons) a corner is read from inside its element and off its plane.
inline constexpr double kSkyCornerLifts = 4.0;

struct RefineState {
    const Scene& scene;
    const PartSet& parts;
    const SolverOptions& options;
    ParallelRunner& runner;
    Solution& solution;
    std::vector<std::vector<uint32_t>> candidate_pool{};  // [0] = every part
    std::vector<std::vector<uint32_t>> root_excluded{};   // parts holding each root's polygon
    std::vector<LinkRecord> records{};
    std::vector<uint8_t> direct_done{};                   // per element
    std::vector<DVec3> direct{};                          // per element: mean punctual irradiance (W/m^2)
    std::vector<DVec3> direct_spread{};                   // per element: its max - min over the element
    // The sky read at element corners (skyAtCorners): index into sky_values per distinct corner.
    std::unordered_map<SkyCornerKey, uint32_t, SkyCornerHash> sky_corners{};
    std::vector<DVec3> sky_values{};
    double threshold = 0.0;  // W: a link may misplace at most this much power
    // Per root, once a solve has linked the roots: the power rule's threshold relative to
    // the power of the root's light-exchange group (below), never above `threshold`.
    std::vector<double> root_threshold{};
    double min_area = 0.0;   // m^2: elements at or below it are not split
    // The local rule (SolverOptions::local_error_threshold), active once a solve has given
    // every element an irradiance: per element (elements made since then read their
    // nearest ancestor's), the mean irradiance H (max channel, W/m^2) from the last solve.
    std::vector<double> irradiance{};
    bool local_active = false;
    double memory_budget_mb = 0.0;  // memoryBudgetMegabytes(options.max_memory_mb)
    // The share of a linking phase the cluster links took (set at their end), where the
    // element links' progress starts; 0 once refineLinks has run.
    double progress_base = 0.0;
    // After a solve: the power rule relative to the power leaving the surfaces of each
    // light-exchange group, and the local rule's irradiances from the solved hierarchy.
    void updateThresholds();
    double thresholdFor(uint32_t root) const {
        return root < root_threshold.size() ? root_threshold[root] : threshold;
    }
};

RefineState makeRefineState(const Scene& scene, const PartSet& parts, const SolverOptions& options,
                            ParallelRunner& runner, Solution& solution);

// Direct light of punctual lights on every element that lacks it, then splits elements
// (to the minimum area) where it varies more than the threshold allows. Sets emission.
void computeDirectLight(RefineState& state);

// Every ordered pair of facing roots, with every part as potential occluder.
std::vector<PendingLink> initialLinks(const RefineState& state);

// Evaluates and refines the pending links into final links (appended to solution.links).
void refineLinks(RefineState& state, std::vector<PendingLink> pending, Progress& progress);

// Removes the final links whose oracle, re-run with the current radiosity, asks for a split,
// and returns them as pending links.
std::vector<PendingLink> reopenLinks(RefineState& state);

// Pending links evaluated at once (bounds the memory their candidate lists hold).
inline constexpr size_t kEvaluationBatch = 8192;

// A refinement's progress fraction after `levels` levels (fractional within a level): the
// number of levels is not known in advance, so each level covers 30 % of what is left.
inline double refinementFraction(double levels) { return 1.0 - std::pow(0.7, levels); }

// Helper: the largest channel.
inline double maxChannel(const DVec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

// The spread of an element's children's radiosity (largest channel), B_max - B_min; 0 for a leaf.
inline double childRadiositySpread(const Solution& solution, const Element& e) {
    if (e.child_count == 0) return 0.0;
    double lo = std::numeric_limits<double>::max(), hi = 0.0;
    for (uint32_t c = 0; c < e.child_count; ++c) {
        const double b = maxChannel(solution.elements[e.first_child + c].radiosity);
        lo = std::min(lo, b);
        hi = std::max(hi, b);
    }
    return hi - lo;
}

// The reflectance the refinement oracles weigh a receiver's error by. A black receiver (an
// emitter with no diffuse colour, a black material) reflects nothing, but what it receives
// is still an output: its vertices and texels are read from its links (reconstruct.h), so
// it is linked and refined as if it reflected everything (it still reflects nothing in the
// solve). Without links, each of its points fell back to the exhaustive gather: 3.6k such
// corners were 63 of graz.wrl's 65 s of vertices.
inline double oracleReflectance(const DVec3& reflectance) {
    const double rho = maxChannel(reflectance);
    return rho > 0.0 ? rho : 1.0;
}

}  // namespace radbake
