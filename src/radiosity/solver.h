#pragma once
// Hierarchical radiosity (Hanrahan-Salzman-Aupperle) with the shaft/occlusion refinement
// oracle of Dupuy, Paulin and Caubet. CONTRACT between the solver and its users (bake,
// export, cli): fields may be added; names below stay.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/progress.h"
#include "scene/scene.h"

namespace radbake {

struct PartSet;

enum class VisibilityMode { Rays, Aabb, Obb, Exact };
enum class Quality { Draft, Medium, High, Reference };

struct SolverOptions {
    VisibilityMode visibility = VisibilityMode::Exact;
    Quality quality = Quality::Medium;
    double error_threshold = 0.0;      // refine while (F_max - F_min) * B_source exceeds this (relative; see solver.cpp)
    double min_element_area = 0.0;     // relative to the scene's total area
    double iteration_tolerance = 0.0;  // stop when the relative change in radiosity is below this
    int max_iterations = 0;
    int threads = 0;                   // 0: all cores

    static SolverOptions forQuality(Quality quality);  // fills every knob from a preset
};

struct SolveStats {
    size_t elements = 0;
    size_t links = 0;
    size_t shafts = 0;
    size_t occluded_links = 0;
    size_t rays = 0;
    int iterations = 0;
    bool converged = false;
};

struct Solution;  // defined in radiosity/solution.h

}  // namespace radbake
