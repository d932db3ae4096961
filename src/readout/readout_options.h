#pragma once
// The read-out's knobs: how the light at a point (vertex, texel, probe) is read from a solved
// hierarchy. None of them changes the solution, so none is in the saved solution's key
// (pipeline/solution_cache.h): changing one reuses a saved solve.
#include "radiosity/sky_light.h"
#include "radiosity/solver_options.h"

namespace radbake {

// Where the link reconstruction corrects a point on a concave edge or corner for the darkening
// of the face beside it (reconstruct.cpp, edgeTerms).
enum class EdgeCorrection {
    Off,
    // At output vertices whose faces beside have vertices at the same point (a room's edges
    // and corners): the vertex bake reads those faces there anyway, so the correction costs
    // only its weights. And at lightmap texels on a concave edge, reading the faces beside
    // once more through their links (few texels on an edge).
    Shared,
    // Also at every other output vertex and probe that touches a concave edge (a block's foot
    // on a floor), reading the faces beside once more through their links.
    On,
};

// How the bake reads the solution at its vertices and texels (probes always take the
// exhaustive gather).
enum class GatherMode {
    Links,       // LinkReconstruction
    Exhaustive,  // probeIrradiance at every point (the reference: --texel-tolerance 0)
};

struct ReadoutOptions {
    GatherMode gather = GatherMode::Links;
    double probe_opening = 0.5;        // a point opens an element when radius / distance exceeds this
    int probe_samples = 2;             // rays per side from a point to each element it gathers from (>= 2)
    double probe_visibility_ratio = 0.01;  // a partly visible element (its rays disagree) is opened, below
                                           // a leaf its polygon split, until radius / distance is below this
    double probe_visibility_coarse = 0.1;  // every element is opened (split) for rays down to this
                                           // radius / distance, so a sliver of light is not lost between rays
    // A piece's corner of highest kernel gets a ray of its own, and a piece found partly hidden
    // that no rule splits further is cast again at twice the rays a side (gather.h,
    // castVisibility): a shadow edge along a piece's border slips between its n x n rays.
    // About twice the rays of a plain gather, so on at high and reference only.
    bool probe_corner_rays = false;
    // The same corner ray (and the recast) on a piece near the point's horizon whose kernel is
    // steep toward that corner only (gather.h, kGrazingKernelRatio). Medium; high and
    // reference cast corner rays everywhere.
    bool probe_grazing_corner_rays = true;
    // A bright, partly visible source is opened for rays as the exhaustive gather's coarse rule
    // opens it (reconstruct.cpp, kCoarseShare). About a quarter of a texel's rays for a tenth of
    // a point of RMS against the exhaustive gather (docs/readout.md): high and reference only.
    bool probe_coarse_opening = false;
    // The exhaustive gather (shadow and contact vertices, probes) estimates its faintest roots
    // from a few rays among them (at most 64, each at a sampled root's centre) once their
    // unoccluded light sums to at most this share of the light it has gathered, brightest roots
    // first (gather.h, visitRoots): most of its rays went to far, small roots hidden from the
    // point. Draft 3e-2, medium 1e-2, high 1e-3; 0 at reference, the gather the others are
    // measured against.
    double probe_faint_share = 1e-2;
    // Shared at draft (a room's edges and corners, at about draft's cost), On above: Shared
    // leaves a block's feet on a floor uncorrected (docs/results.md has the figures).
    EdgeCorrection edge_correction = EdgeCorrection::On;
    // The sky's quadrature at a probe and in the exhaustive gather (radiosity/sky_light.h); vertices
    // and texels read through the links take the sky the solve found at their leaf's corners.
    // Draft (8, 2), medium (12, 3), high (16, 3), reference (24, 4); a grid of 0 leaves the sky out.
    SkyQuadrature sky{12, 3};

    static ReadoutOptions forQuality(Quality quality);  // fills every knob from a preset
};

const char* toString(EdgeCorrection mode);

}  // namespace radbake
