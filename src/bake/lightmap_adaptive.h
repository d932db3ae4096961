#pragma once
// Adaptive texel evaluation (issue 5): most of a lightmap is smooth light, where evaluating
// every texel with probeIrradiance is wasted work. Each chart is evaluated on a coarse
// lattice first (every kCoarsestStep-th texel); a block between four evaluated lattice
// texels that holds no partly covered texel (no chart edge crosses it) is tested at its
// centre and edge midpoints: when every texel evaluated inside it lies within the tolerance
// of the bilinear interpolation of its corners (and the corners differ by less than half their light),
// its other texels are interpolated at their own sample points; otherwise it is split in
// four, its test points being the new corners, down to every texel. Partly covered texels
// and their 8 neighbours (the texels bilinear lookups on chart edges read, which the seam
// fit adjusts) are always evaluated. A smooth edge inside a chart (faces with different
// normals see different light) is a step like a shadow edge: the test points find it.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "bake/lightmap_bake.h"
#include "core/parallel.h"
#include "core/progress.h"

namespace radbake {

// The coarsest lattice step in texels (blocks of 8 x 8 texels at most).
inline constexpr int kCoarsestStep = 8;
// Below this fraction of the brightest light evaluated on the coarse lattice, the tolerance
// is measured against this level instead of the local light: errors that small are not
// visible next to the bright parts, and relative agreement in near-black would force every
// dark texel to be evaluated.
inline constexpr double kDarkFloor = 1e-2;

// How much of a texel's square its chart's faces cover.
enum class TexelCover : uint8_t { Empty = 0, Partial = 1, Full = 2 };

// One texel of a chart as the evaluation sees it. An edge texel is partly covered, or beside
// (8-neighbour, or past the chart's border) a texel that is not fully covered: bilinear lookups
// along chart edges read it and the seam fit adjusts it, so it is evaluated whatever the tolerance.
struct TexelSite {
    DVec2 p_plane{0.0};    // where it is evaluated (texelCoverage)
    uint32_t face = 0;     // index into LightmapChart::faces
    TexelCover cover = TexelCover::Empty;  // Empty too when hidden
    bool hidden = false;   // covered, but its sample point is inside geometry (dilated instead)
    bool edge = false;     // covered and on the chart's edge, as above
};

// Every texel of a chart, row by row (width x height), sample points found on the runner's
// threads; `hidden` (when given) empties texels inside geometry, which makes their neighbours
// edge texels. The one definition of coverage and edges that evaluateTexelsAdaptive uses, for
// tools that need to know which texels a bake evaluated and why.
std::vector<TexelSite> chartTexelSites(const LightmapChart& chart, ParallelRunner& runner,
                                       const HiddenTest& hidden = {});

struct AdaptiveCounts {
    size_t covered = 0;       // texels with geometry (all filled, evaluated or interpolated)
    size_t evaluated = 0;     // irradiance evaluations at texel sample points
    size_t interpolated = 0;  // covered texels filled by bilinear interpolation
    size_t required = 0;      // texels evaluated whatever the light: partly covered or beside one
    size_t hidden = 0;        // texels with geometry whose sample point `hidden` found inside geometry
};

// Fills the covered texels of every placed chart (state Covered, value H / pi) and leaves
// the rest Empty; texels whose sample point `hidden` (when given) finds inside geometry are
// left Empty too, and count as not covered for the blocks around them. tolerance <= 0: every
// covered texel is evaluated, exactly as evaluateLightmaps always did. Decisions depend only on evaluated values and run level by
// level; each evaluation writes its own slot: the result does not depend on the runner's
// thread count. A cancelled runner leaves texels unevaluated (the caller discards them).
// `progress`, when given, moves from 0 to kTexelShare as texels are evaluated.
inline constexpr double kTexelShare = 0.9;
// `dark` (H / pi): below it the tolerance is taken against it, not the light itself. A bake
// passes kDarkFloor of the light level its solution gives (brightestLight), known before any
// texel is read, so each chart's decisions are its own (a shard of the read-out takes them as
// the whole bake does); negative: kDarkFloor of the brightest texel of the first level.
// `wanted` (per chart; empty: every chart): the charts to fill, the others left Empty and
// uncounted. With `dark` given, a chart's texels are the same whichever others are wanted.
AdaptiveCounts evaluateTexelsAdaptive(const LightmapLayout& layout, std::vector<LightmapImage>& images,
                                      const IrradianceFunction& irradiance, double tolerance, ParallelRunner& runner,
                                      Progress* progress = nullptr, const HiddenTest& hidden = {}, double dark = -1.0,
                                      std::span<const uint8_t> wanted = {});

}  // namespace radbake
