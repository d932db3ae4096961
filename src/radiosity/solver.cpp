// solveRadiosity: roots, direct light, refine-solve rounds. The module boundary: nothing
// thrown below escapes (reported to Diagnostics instead).
#include <algorithm>
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
    for (int round = 0; round < rounds; ++round) {
        const std::string suffix = round == 0 ? "" : " " + std::to_string(round + 1);
        if (round == 0) progress.beginPhase("links");  // a later round's began with its reopening, below
        if (clusters && round == 0) pending = clusters->initial(progress);
        refineLinks(state, std::move(pending), progress);
        stopIfCancelled(runner);
        computeDirectLight(state);  // elements made by the refinement
        groupLinksByReceiver(s, &state.records);
        if (clusters) groupClusterLinksByReceiver(s);
        stopIfCancelled(runner);
        progress.beginPhase("solve" + suffix);
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
            std::vector<PendingLink> deferred = clusters->reopen(progress, changed, true);
            if (!changed) break;
            refineLinks(state, std::move(deferred), progress);
            computeDirectLight(state);
            groupLinksByReceiver(s, &state.records);
            groupClusterLinksByReceiver(s);
            progress.beginPhase("solve" + suffix + deferred_name);
            result = solveHierarchy(s, runner, SolveStart::Current, options.iteration_tolerance, options.max_iterations,
                                    &row_sums, &progress);
            s.stats.iterations += result.iterations;
        }
        s.stats.rounds = round + 1;
        if (round + 1 == rounds) break;
        // Reopening is the next round's linking (the clusters' part of it most of all).
        progress.beginPhase("links " + std::to_string(round + 2));
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
