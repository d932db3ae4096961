#pragma once
// The solver's entry point: hierarchical radiosity (Hanrahan-Salzman-Aupperle) with the
// shaft/occlusion refinement oracle of Dupuy, Paulin and Caubet, clustered above the
// polygons (radiosity/cluster.h). Knobs in solver_options.h; the result in solution.h; the
// linear solve over a fixed hierarchy in linear_solve.h.
#include <optional>

#include "core/diagnostics.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "radiosity/solution.h"
#include "radiosity/solver_options.h"
#include "scene/scene.h"

namespace radbake {

struct PartSet;

// Solves the scene's light on the runner's threads. Returns nullopt after reporting an
// error to diagnostics, or soon after the runner's cancel flag is set (no error then: the
// caller knows it cancelled). Never throws. Deterministic: the same result bytes for any
// thread count.
std::optional<Solution> solveRadiosity(const Scene& scene, const PartSet& parts, const SolverOptions& options,
                                       ParallelRunner& runner, Progress& progress, Diagnostics& diagnostics);

}  // namespace radbake
