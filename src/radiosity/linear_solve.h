#pragma once
// The linear solve over a fixed hierarchy: B = E + rho K B, where K pulls leaf radiosity up
// the trees (area averages), gathers through every link and pushes the gathered irradiance
// down to the leaves. Solved with restarted GMRES in the area-weighted inner product: at
// rho = 0.99 plain Jacobi needs ~230 sweeps per decade, GMRES a few tens of steps in all.
// Deterministic: every sum runs in a fixed order whatever the thread count.
#include "core/parallel.h"
#include "radiosity/solution.h"

namespace radbake {

struct LinearSolveResult {
    int iterations = 0;  // operator applications
    bool converged = false;
    double residual = 0.0;  // |E + rho K B - B| / |E|, area-weighted
};

// Starts from the elements' current leaf radiosity; leaves every element's radiosity and
// gathered irradiance consistent with the result. Links must be grouped by receiver.
LinearSolveResult solveHierarchy(Solution& solution, ParallelRunner& runner, double tolerance, int max_iterations);

// Sorts links by receiver (stable, so the order within a receiver stays the creation order).
void groupLinksByReceiver(Solution& solution, std::vector<struct LinkRecord>* records);

// Sets every inner element's radiosity to the area average of its children's.
void pullRadiosity(Solution& solution);

}  // namespace radbake
