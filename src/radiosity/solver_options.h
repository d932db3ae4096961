#pragma once
// The solver's knobs (SolverOptions, with the presets of each Quality) and what a solve
// reports (SolveStats). The entry point is in radiosity/solver.h, the solved hierarchy in
// radiosity/solution.h. CONTRACT between the solver and its users (bake, export, cli):
// fields may be added; names below stay.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/progress.h"
#include "scene/scene.h"

namespace radbake {

struct PartSet;

// How the solver finds a link's visibility (--visibility): the solver's policy. Rays: no
// shafts, rays on every candidate link. Aabb, Obb, Exact: a shaft per link, whose crossing
// parts are tested with the visibility layer's OcclusionTest (visibility/occlusion.h) None,
// Obb (the paper's test, which can claim occlusions that are not there) or Exact
// (conservative); rays only for the links that stay partly hidden.
enum class LinkVisibility { Rays, Aabb, Obb, Exact };
enum class Quality { Draft, Medium, High, Reference };
// Every threshold is relative to the scene, so a scene scaled by any factor (1e-4, 1e6)
// refines the same way:
//   - a link (receiver R, source S) is refined while
//       rho_R * (F_max - F_min) * B_S * A_R  >  error_threshold * P,
//     the power it may misplace (W; max channel). P is the emitted power, sum over roots of
//     A * (pi L_e + rho H_direct), in the first round; in later rounds the power leaving the
//     surfaces (sum of A * B) of the receiver's light-exchange group (roots joined by links
//     that carry light: two closed rooms are two groups, each refined as if alone). F_min is
//     0 when the link has potential occluders; F_max/F_min are the point form factor's
//     extremes over the receiver's sample points.
//     (area_exponent < 1 replaces A_R by A_total (A_R / A_total)^area_exponent.)
//   - from the second round on, a link whose receiver is at the min-area floor (below) has
//     its source split while
//       (F_max - F_min) * B_S  >  local_error_threshold * H_R   (rho_R > 0),
//     H_R the receiver's mean irradiance from the last solve (an element made since reads its
//     nearest ancestor's): the power rule scales with the receiver's area, so a sliver
//     standing on a lit floor would otherwise gather the floor's mean, not what is near it;
//   - an element is split only while its area exceeds min_element_area * total scene area;
//   - direct light of punctual lights refines an element while
//       rho * (H_max - H_min) * A > error_threshold * P.
// The solve scales each leaf's inherited irradiance so its row sum matches the point form
// factors averaged over it (2 x 2 Gauss points, solve.cpp): the oracle bounds power, not local error, and without
// this closed scenes at rho = 0.99 drift by tens of percent.
// The sky's quadrature at a point (radiosity/sky_light.h): grid x grid top cells of four samples
// each, split into quarters where they disagree, down to `depth` levels; a cell whose samples are
// all blocked is split down to `search` levels unless what blocks them provably covers it, so an
// opening between samples is looked for down to 1 / (2^(search + 1) grid) of the hemisphere's
// parameter square.
struct SkyQuadrature {
    int grid = 12;  // even: a vertical surface's horizon then lies on cell edges
    int depth = 3;
    // Levels below the top cells down to which a cell whose samples all meet something is split
    // unless the triangles they meet are proven to cover it: a slit between two panels lies between
    // samples. 0: trust the samples.
    int search = 4;
};

struct SolverOptions {
    LinkVisibility visibility = LinkVisibility::Aabb;  // the fastest conservative mode on real scenes (docs/scale.md)
    Quality quality = Quality::Medium;
    double error_threshold = 2e-4;     // fraction of the emitted power a link may misplace (above)
    double min_element_area = 1e-4;    // relative to the scene's total area
    // Stop when |E + rho K B - B| / |E| (area-weighted) is below this. Relative to the whole
    // scene's light: a room lit through a slit by 1e-4 of what its sunlit outside gets needs
    // 1e-5 for its own bounce.
    double iteration_tolerance = 1e-5;
    int max_iterations = 200;          // operator applications (GMRES steps) per solve, then a warning
    double max_memory_mb = 0.0;        // --max-memory: the solve stops with an error above this
                                       // resident memory (MiB); 0: 3/4 of the machine's memory

    // Finer knobs, set by forQuality.
    int refine_rounds = 2;             // refine-solve rounds (the first with emitted light only)
    int quadrature_order = 3;          // Gauss points per side of a receiver cell
    double quadrature_near_ratio = 0.5;  // cells closer to the source than this x their radius split
    int quadrature_max_depth = 2;      // towards a touching source (the singularity is mild:
                                       // 1e-6 relative on unit squares sharing an edge)
    int visibility_samples = 3;        // rays per side for a partial link (n x n segments)
    // The sky at every element corner (draft 8, medium 12, high 16, reference 24 top cells a side).
    SkyQuadrature sky{12, 3};
    double area_exponent = 1.0;        // A_R in the oracle becomes A_total (A_R / A_total)^area_exponent
    // Links start between clusters of roots (cluster.h) instead of between every pair of
    // roots: linking in O(n log n) instead of O(n^2). Off: every facing pair of roots.
    bool clustering = true;
    double local_error_threshold = 0.1;   // fraction of its own irradiance a link may vary over a
                                          // receiver (above; 0: off; needs refine_rounds >= 2)
    // Cluster links found blocked by every one of their sample rays carry nothing and are not
    // kept (counted in occluded_links); true keeps them with visibility 0, for tests of the
    // link hierarchy's coverage. The light is the same either way.
    bool keep_blocked_links = false;

    static SolverOptions forQuality(Quality quality);  // fills every knob from a preset
};

const char* toString(LinkVisibility mode);
const char* toString(Quality quality);
// The preset toString names ("draft", "medium", "high", "reference"); `fallback` for any other.
Quality qualityNamed(const std::string& name, Quality fallback = Quality::Medium);

struct SolveStats {
    size_t elements = 0;
    size_t links = 0;                 // element links + cluster links
    size_t shafts = 0;
    size_t occluded_links = 0;
    size_t rays = 0;
    size_t cluster_rays = 0;          // of `rays`, those cast for cluster links
    int iterations = 0;               // operator applications over all rounds
    bool converged = false;           // the last solve reached iteration_tolerance
    size_t leaves = 0;
    size_t roots = 0;
    size_t contact_cuts = 0;          // root polygons cut where another touches or crosses them (contact_cuts.h)
    // Every evaluation of the oracle (candidate_links) ends one way, so that
    //   candidate_links = links + reopened_links + occluded_links + dropped_links + split_links:
    // kept (a final link, unless a later round reopens it: reopened_links), occluded (a shaft
    // blocker or every ray blocked), dropped (nothing to carry: facing away, zero form factor)
    // or split into sub-links (which are candidates of their own).
    size_t candidate_links = 0;       // evaluations of the oracle, element and cluster links
    size_t split_links = 0;
    size_t dropped_links = 0;
    size_t reopened_links = 0;
    size_t partial_links = 0;         // final links found partly hidden (visibility < 1)
    size_t limited_row_sums = 0;      // leaves whose form factors summed to more than 1, scaled to 1 (largest over the solves)
    size_t classify_fallbacks = 0;    // links whose shaft classification failed (out of memory): kept partial
    int rounds = 0;
    double residual = 0.0;            // final relative residual
    size_t element_links = 0;         // Solution::links (between elements)
    size_t cluster_links = 0;         // Solution::cluster_links (a cluster at one end at least)
    size_t clusters = 0;
    // What the solution holds, per item: an element with its polygon's share of the vertex
    // loops; a link (element or cluster) with its share of the cluster kernels.
    double bytes_per_element = 0.0;
    double bytes_per_link = 0.0;
    double memory_budget_mb = 0.0;    // the budget the solve ran under (SolverOptions::max_memory_mb)
};

struct Solution;  // defined in radiosity/solution.h

}  // namespace radbake
