#pragma once
// The linear solve over a fixed hierarchy: B = E + rho K B, where K pulls leaf radiosity up
// the trees (area averages), gathers through every link and pushes the gathered irradiance
// down to the leaves. Solved with restarted GMRES in the area-weighted inner product: at
// rho = 0.99 plain Jacobi needs ~230 sweeps per decade, GMRES a few tens of steps in all.
// Deterministic: every sum runs in a fixed order whatever the thread count.
#include "core/parallel.h"
#include "core/progress.h"
#include "radiosity/cluster.h"
#include "radiosity/solution.h"

namespace radbake {

struct LinearSolveResult {
    int iterations = 0;  // operator applications
    bool converged = false;
    double residual = 0.0;  // |E + rho K B - B| / |E|, area-weighted
};

// Where the solve starts. A round's solve starts from the emission, not the last round's
// answer: in exact arithmetic the answer does not depend on the start, but GMRES stops at a
// residual relative to the whole scene, and a warm start keeps whatever the last round's links
// put where the new links bring nothing (a closed closet lit by a coarse cluster link the next
// round refined away, 2e-7 of the room's light). From the emission, a leaf no final link
// lights stays exactly zero. The re-solve after deferred links were evaluated continues from
// the round's answer: those links only add light where it was missing.
enum class SolveStart { Emission, Current };

// The operator's per-leaf set-up (the most costly part of a solve on a refined hierarchy), kept
// between the solves of one hierarchy (cluster.h, ElementMemo).
struct RowSumCache {
    // A leaf's exact row sum through its ancestors' links, signed by their sources and visibilities.
    ElementMemo row_sums;
    // Its share of its root's cluster light (ClusterTransfer::leafFactors).
    ElementMemo cluster_kernels;
};

// Leaves every element's radiosity and gathered irradiance consistent with the result.
// Links must be grouped by receiver. `cache`, when given, is read and updated (see above); the
// result is the same with or without it.
// `progress`, when given, moves with the set-up and then the residual.
LinearSolveResult solveHierarchy(Solution& solution, ParallelRunner& runner, SolveStart start, double tolerance,
                                 int max_iterations, RowSumCache* cache = nullptr, Progress* progress = nullptr);

// Sorts links by receiver (stable, so the order within a receiver stays the creation order).
void groupLinksByReceiver(Solution& solution, std::vector<struct LinkRecord>* records);

// Sets every inner element's radiosity to the area average of its children's.
void pullRadiosity(Solution& solution);

}  // namespace radbake
