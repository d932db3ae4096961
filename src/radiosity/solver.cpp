// solveRadiosity: roots, direct light, refine-solve rounds. The module boundary: nothing
// thrown below escapes (reported to Diagnostics instead).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "core/memory.h"
#include "geometry/parts.h"
#include "radiosity/cluster.h"
#include "radiosity/elements.h"
#include "core/parallel.h"
#include "radiosity/refine.h"
#include "radiosity/solution.h"
#include "radiosity/solver.h"
#include "radiosity/linear_solve.h"
#include "visibility/ray_caster.h"

namespace radbake {

// The stats are saved as they lie in memory (solution_cache.cpp): their padding is zeroed
// once here (every default is 0), and the solve sets members only.
Solution::Solution() { std::memset(static_cast<void*>(&stats), 0, sizeof stats); }
Solution::~Solution() = default;
Solution::Solution(Solution&&) noexcept = default;
Solution& Solution::operator=(Solution&&) noexcept = default;

namespace {

// Deferred passes of the last round at most: light reaching new sources in the last of them
// stays where it lands (their links are dropped, solver.cpp's end).
constexpr int kLastRoundDeferredPasses = 3;

// Thrown between phases once progress is cancelled; solveRadiosity returns nullopt for it.
struct Cancelled {};

void stopIfCancelled(const ParallelRunner& runner) {
    if (runner.cancelled()) throw Cancelled{};
}

// What the solve expects its phases after the current one to take (Progress::setAhead): the
// phases done as measured, the rest from their ratios on the generated buildings
// (docs/scale.md, "The solve's progress"), as a + b x the current phase's own length x.
class SolveTimeline {
public:
    SolveTimeline(Progress& progress, int rounds, bool clusters)
        : progress_(progress), rounds_(rounds), clusters_(clusters) {}
    // Called just after the phase began; pass -1 for a round's own links and solve, else the
    // deferred pass.
    void links(int round, int pass) { begin(Kind::Links, round, pass); }
    void solve(int round, int pass) { begin(Kind::Solve, round, pass); }

private:
    enum class Kind { Links, Solve };
    struct Lin {  // a + b x
        double a = 0.0, b = 0.0;
        Lin operator+(Lin o) const { return {a + o.a, b + o.b}; }
        Lin operator*(double k) const { return {a * k, b * k}; }
    };
    static constexpr double kSolveShare = 0.07;         // a solve: of the linking before it
    static constexpr double kFirstDeferredShare = 6.0;  // the first deferred pass: of round 1's links
    static constexpr double kReopenShare = 0.18;        // a later round's links: of the linking before
    static constexpr double kLaterPassShare = 0.01;     // each phase of a later deferred pass

    void begin(Kind kind, int round, int pass) {
        const auto now = std::chrono::steady_clock::now();
        if (current_links_) {
            const double length = std::chrono::duration<double>(now - start_).count();
            linking_ += length;
            if (current_first_) first_links_ = length;
        }
        start_ = now;
        current_links_ = kind == Kind::Links;
        current_first_ = current_links_ && round == 0 && pass < 0;
        // The current phase's length is x; the linking so far includes it when it links.
        Lin linking{linking_, current_links_ ? 1.0 : 0.0};
        const Lin first = current_first_ ? Lin{0.0, 1.0} : Lin{first_links_, 0.0};
        // The phases to come, in solveRounds' order.
        Lin ahead;
        bool after = false;
        for (int r = 0; r < rounds_; ++r) {
            const int passes = !clusters_ ? 0 : r + 1 == rounds_ ? kLastRoundDeferredPasses : 1;
            for (int p = -1; p < passes; ++p)
                for (Kind k : {Kind::Links, Kind::Solve}) {
                    if (!after) {
                        after = k == kind && r == round && p == pass;
                        continue;
                    }
                    const Lin t = expected(k, r, p, linking, first);
                    ahead = ahead + t;
                    if (k == Kind::Links) linking = linking + t;
                }
        }
        progress_.setAhead(ahead.a, ahead.b);
    }
    static Lin expected(Kind k, int round, int pass, Lin linking, Lin first) {
        if (pass < 0) return linking * (k == Kind::Solve ? kSolveShare : kReopenShare);  // round 0's links never ahead
        if (round == 0 && pass == 0) return k == Kind::Solve ? linking * kSolveShare : first * kFirstDeferredShare;
        return linking * kLaterPassShare;  // few links, and a solve from the current radiosity
    }

    Progress& progress_;
    int rounds_;
    bool clusters_;
    bool current_links_ = false, current_first_ = false;
    double linking_ = 0.0, first_links_ = -1.0;
    std::chrono::steady_clock::time_point start_;
};

void solveRounds(const Scene& scene, const PartSet& parts, const SolverOptions& options, ParallelRunner& runner,
                 Progress& progress, Diagnostics& diagnostics, Solution& s) {
    RefineState state = makeRefineState(scene, parts, options, runner, s);
    progress.beginPhase("direct light");
    computeDirectLight(state);
    stopIfCancelled(runner);
    for (Element& e : s.elements) e.radiosity = e.emission;
    pullRadiosity(s);
    if (std::none_of(s.elements.begin(), s.elements.end(), [](const Element& e) { return e.emission != DVec3(0.0); })) {
        // Nothing emits and no punctual light reaches a surface: 0 everywhere, without a link.
        s.stats.converged = true;
        progress.endPhase();
        return;
    }
    // Clustering: links start at the top cluster (cluster.h); otherwise every facing pair.
    std::optional<ClusterRefiner> clusters;
    if (options.clustering && s.root_count > 1) {
        buildClusters(s);
        clusters.emplace(state);
    }
    std::vector<PendingLink> pending;
    if (!clusters) pending = initialLinks(state);
    LinearSolveResult result;
    RowSumCache row_sums;
    const int rounds = std::max(1, options.refine_rounds);
    SolveTimeline timeline(progress, rounds, clusters.has_value());
    for (int round = 0; round < rounds; ++round) {
        const std::string suffix = round == 0 ? "" : " " + std::to_string(round + 1);
        if (round == 0) {
            progress.beginPhase("links");  // a later round's began with its reopening, below
            timeline.links(0, -1);
        }
        if (clusters && round == 0) pending = clusters->initial(progress);
        refineLinks(state, std::move(pending), progress);
        stopIfCancelled(runner);
        computeDirectLight(state);  // elements made by the refinement
        groupLinksByReceiver(s, &state.records);
        if (clusters) groupClusterLinksByReceiver(s);
        stopIfCancelled(runner);
        progress.beginPhase("solve" + suffix);
        timeline.solve(round, -1);
        result = solveHierarchy(s, runner, SolveStart::Emission, options.iteration_tolerance, options.max_iterations,
                                &row_sums, &progress);
        stopIfCancelled(runner);
        s.stats.iterations += result.iterations;
        // The last round repeats the deferred pass while it lights new sources (each pass
        // carries light one more bounce: a block's shadowed side, the room past a doorway).
        const int deferred_passes = round + 1 == rounds ? kLastRoundDeferredPasses : 1;
        for (int pass = 0; pass < deferred_passes && clusters && clusters->hasDeferred(); ++pass) {
            // Cluster links deferred for want of light (the first round knows emission only)
            // are evaluated now that the solve has lit their sources, and solved once more,
            // before anything reads the solution's power or irradiance.
            // The power rule's thresholds from this solve; the local rule stays as it was in
            // this round (off in the first, as for element links).
            const bool local_active = state.local_active;
            state.updateThresholds();
            state.local_active = local_active;
            bool changed = false;
            const std::string deferred_name = pass == 0 ? " (deferred)" : " (deferred " + std::to_string(pass + 1) + ")";
            progress.beginPhase("links" + suffix + deferred_name);
            timeline.links(round, pass);
            std::vector<PendingLink> deferred = clusters->reopen(progress, changed, true);
            if (!changed) break;
            refineLinks(state, std::move(deferred), progress);
            computeDirectLight(state);
            groupLinksByReceiver(s, &state.records);
            groupClusterLinksByReceiver(s);
            progress.beginPhase("solve" + suffix + deferred_name);
            timeline.solve(round, pass);
            result = solveHierarchy(s, runner, SolveStart::Current, options.iteration_tolerance, options.max_iterations,
                                    &row_sums, &progress);
            s.stats.iterations += result.iterations;
        }
        s.stats.rounds = round + 1;
        if (round + 1 == rounds) break;
        // Reopening is the next round's linking (the clusters' part of it most of all).
        progress.beginPhase("links " + std::to_string(round + 2));
        timeline.links(round + 1, -1);
        state.updateThresholds();
        pending = reopenLinks(state);
        bool clusters_changed = false;
        if (clusters) {
            std::vector<PendingLink> more = clusters->reopen(progress, clusters_changed);
            pending.insert(pending.end(), more.begin(), more.end());
        }
        if (pending.empty() && !clusters_changed) break;
    }
    if (clusters) dropDeferredClusterLinks(s);
    progress.endPhase();
    if (s.stats.classify_fallbacks > 0)
        diagnostics.warning({scene.source_path, 0, 0},
                            std::to_string(s.stats.classify_fallbacks) +
                                " links could not be classified against their shafts (out of memory) and were kept as "
                                "partly visible: rays decided them, so the light is right but the solve was slower");
    s.stats.converged = result.converged;
    s.stats.residual = result.residual;
    if (!result.converged)
        diagnostics.warning({}, "radiosity did not converge in " + std::to_string(options.max_iterations) +
                                    " iterations (relative residual " + std::to_string(result.residual) +
                                    "); raise --max-iterations or the iteration tolerance");
}

}  // namespace

std::optional<Solution> solveRadiosity(const Scene& scene, const PartSet& parts, const SolverOptions& options,
                                       ParallelRunner& runner, Progress& progress, Diagnostics& diagnostics) {
    try {
        Solution s;
        s.scene = &scene;
        s.options = options;
        progress.beginPhase("elements");
        buildRootElements(scene, s);
        if (s.root_count == 0) {
            diagnostics.warning({scene.source_path, 0, 0}, "the scene has no surface to light");
            progress.endPhase();
            s.stats.converged = true;
            return s;
        }
        s.rays = RayCaster::build(scene, diagnostics, runner.threads());
        if (!s.rays) return std::nullopt;
        solveRounds(scene, parts, options, runner, progress, diagnostics, s);
        s.rays->reportLateErrors(diagnostics);
        s.stats.elements = s.elements.size();
        s.stats.roots = s.root_count;
        s.stats.element_links = s.links.size();
        s.stats.cluster_links = s.cluster_links.size();
        s.stats.clusters = s.clusters.size();
        s.stats.links = s.links.size() + s.cluster_links.size();
        if (!s.elements.empty())
            s.stats.bytes_per_element =
                static_cast<double>(s.elements.size() * sizeof(Element) + s.vertices.size() * sizeof(DVec3)) /
                static_cast<double>(s.elements.size());
        if (s.stats.links > 0)
            s.stats.bytes_per_link = static_cast<double>(s.links.size() * sizeof(Link) +
                                                         s.cluster_links.size() * sizeof(ClusterLink) +
                                                         s.cluster_kernel.size() * sizeof(float)) /
                                     static_cast<double>(s.stats.links);
        s.stats.memory_budget_mb = memoryBudgetMegabytes(options.max_memory_mb);
        s.stats.leaves = 0;
        for (const Element& e : s.elements) s.stats.leaves += e.isLeaf() ? 1 : 0;
        // Counted here once, over the final links (refinement reopens and drops links).
        for (const Link& l : s.links) s.stats.partial_links += l.visibility < 1.0f ? 1 : 0;
        return s;
    } catch (const Cancelled&) {
        progress.endPhase();
    } catch (const MemoryBudgetExceeded& e) {
        char message[256];
        std::snprintf(message, sizeof message,
                      "the solve stopped while %s: it holds %.0f MiB, above its memory budget of %.0f MiB "
                      "(--max-memory; default 3/4 of this machine's memory); lower --quality or raise "
                      "--error-threshold, or give --max-memory",
                      e.during.c_str(), e.used_mb, e.budget_mb);
        diagnostics.error({scene.source_path, 0, 0}, message);
    } catch (const std::bad_alloc&) {
        diagnostics.error({scene.source_path, 0, 0}, outOfMemoryMessage("solving the radiosity"));
    } catch (const std::exception& e) {
        diagnostics.error({scene.source_path, 0, 0}, std::string("radiosity solve failed: ") + e.what());
    } catch (...) {
        diagnostics.error({scene.source_path, 0, 0}, "radiosity solve failed (unknown error)");
    }
    return std::nullopt;
}

}  // namespace radbake
