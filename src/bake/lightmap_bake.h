#pragma once
// Lightmap texels: each chart texel is evaluated at the part of the chart's geometry it
// covers, then the texels around charts are filled by dilation so bilinear filtering never
// pulls in black. Values are H / pi like the vertex bake (DESIGN.md section 2).
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "bake/lightmap_charts.h"
#include "bake/lightmap_pack.h"
#include "core/diagnostics.h"
#include "core/math.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "readout/evaluate_probe.h"
#include "readout/readout_options.h"

namespace radbake {

struct Solution;
class RayCaster;

enum class TexelState : uint8_t { Empty = 0, Dilated = 1, Covered = 2 };

struct LightmapImage {
    int width = 0, height = 0;
    std::vector<float> rgb;          // width * height * 3, row 0 at the top
    std::vector<TexelState> state;   // width * height
};

// What fitting the chart edges and seams did (stitchLightmaps; zero when not run).
struct StitchStats {
    size_t edge_samples = 0;     // points on chart boundaries whose bilinear lookup was fitted to the light there
    size_t seam_samples = 0;     // points where two charts of one surface meet
    size_t texels = 0;           // texels the fit could change
    size_t evaluations = 0;      // irradiance evaluations: distinct (point, normal) pairs among the samples
    int iterations = 0;          // conjugate-gradient steps, summed over channels
    double max_seam_before = 0;  // worst |lookup A - lookup B| / max(|A|, |B|) over seam samples and channels
    double max_seam_after = 0;
    double max_edge_after = 0;   // worst |lookup - light| / |light| over edge samples after the fit
};

struct Lightmaps {
    LightmapLayout layout;
    std::vector<LightmapImage> images;  // one per atlas
    size_t covered_texels = 0;       // texels with geometry, each evaluated or interpolated
    size_t hidden_texels = 0;        // texels with geometry whose point is inside geometry: dilated instead
    size_t evaluated_texels = 0;     // irradiance evaluations at texel sample points
    size_t interpolated_texels = 0;  // covered texels interpolated (LightmapOptions::texel_tolerance)
    size_t required_texels = 0;      // texels evaluated whatever the light (chart edges; 0 at tolerance 0)
    StitchStats stitch;
    ReadoutWork work;   // of the link read-out, seam fit included (none with the exhaustive gather)
};

// A point on one of the scene's triangles, seen from the side its normal faces.
struct SurfacePoint {
    DVec3 p_world{0.0};
    DVec3 normal_world{0.0, 0.0, 1.0};  // unit, the triangle's
    uint32_t mesh = 0, triangle = 0;    // Scene::meshes[mesh].triangles[triangle]
};

// Irradiance H (W/m^2) at a surface point; in a bake, LinkReconstruction (probeIrradiance
// for the exhaustive reference).
using IrradianceFunction = std::function<DVec3(const SurfacePoint& at)>;

// True where a texel's sample point is hidden inside geometry (under a block standing on the
// floor): its light is never seen, and bilinear lookups beside the contact would mix its
// darkness into the lit texels beside it, so it is left to dilation from its valid neighbours.
using HiddenTest = std::function<bool(const SurfacePoint& at)>;

// Inside closed geometry: every one of kHiddenRays fixed hemisphere rays (the normal's first)
// meets the back of a one-sided surface. Every ray, not most: the ceiling just above a
// one-sided lamp sees the lamp's back along most rays but the room past its edge, and is lit
// through that gap. The normal ray alone decides for most points: about one ray a texel.
inline constexpr int kHiddenRays = 16;
bool insideGeometry(const Scene& scene, const RayCaster& rays, const DVec3& p, const DVec3& normal);

// Where a texel is evaluated: the centroid of the largest piece of the chart's faces inside
// the texel square (a convex piece of one triangle, so the point lies on the surface, never
// in a gap of the chart or beyond its edge). False when the texel covers no geometry.
bool texelSamplePoint(const LightmapChart& chart, int i, int j, DVec2& p_plane);
// The same, also naming the face (index into chart.faces) the point lies on.
bool texelSamplePoint(const LightmapChart& chart, int i, int j, DVec2& p_plane, size_t& face);
// The same point and face, returning the fraction of the texel square the chart's faces
// cover (0 when none; 1 up to rounding inside the chart).
double texelCoverage(const LightmapChart& chart, int i, int j, DVec2& p_plane, size_t& face);

// Fills every covered texel (value = H / pi) and dilates, on the runner's threads. Texels
// `hidden` (when given) finds inside geometry are filled by the dilation instead.
// texel_tolerance <= 0 evaluates every covered texel; above 0, smooth blocks of texels are
// interpolated from evaluated ones within that relative tolerance (lightmap_adaptive.h).
// Each texel writes its own slot, so the images do not depend on the thread count.
// `dark`: as evaluateTexelsAdaptive takes it.
Lightmaps evaluateLightmaps(LightmapLayout layout, const IrradianceFunction& irradiance, int padding,
                            ParallelRunner& runner, double texel_tolerance = 0.0, Progress* progress = nullptr,
                            const HiddenTest& hidden = {}, double dark = -1.0);

// The light level a solution gives (H / pi): the brightest any leaf receives, through its own
// and its ancestors' links and from the punctual lights and the sky (their share of its
// emission over its reflectance). What the lightmaps' relative tolerances fall back on in the
// dark, known before any texel is read.
double brightestLight(const Solution& solution);

// Fills Empty texels (padding, and texels hidden inside geometry) inside each chart's padded
// rectangle from their filled 8-neighbours (the average of those filled in the previous pass),
// pass after pass until the rectangle is full; texels of one chart never take light from another chart.
void dilateLightmaps(Lightmaps& lightmaps, int padding);

// A scene's charts at one density, built once (unplaced): the texel budget builds them
// before the solve (lightmap_budget.h) and bakeLightmaps places and fills the same ones.
struct LightmapCharts {
    LightmapOptions options;           // options.texels_per_metre is the density they were built at
    std::vector<LightmapChart> charts;
    size_t texels = 0;                 // chart texels, padding excluded (what the budget counts)
};
LightmapCharts chartLightmaps(const Scene& scene, const LightmapOptions& options);

// The whole lightmap stage: packing, texels, dilation, then (options.stitch_seams) the
// padding ring fitted to the chart edges and seams (lightmap_seams.h). Texels are read as
// `readout` says (readout.gather: through the links, or the exhaustive gather). False after reporting,
// or with nothing reported when the runner was cancelled.
// `progress`, when given, moves through the phase (texels, then the seams).
bool bakeLightmaps(const Scene& scene, const Solution& solution, const ReadoutOptions& readout, LightmapCharts charts,
                   ParallelRunner& runner, Lightmaps& lightmaps, Diagnostics& diagnostics,
                   Progress* progress = nullptr);

// bakeLightmaps in pieces, for a read-out split into shards: the reads of some charts (their
// texels before dilation, the light at their chart-edge queries, the work), then the lightmaps
// assembled from parts that cover every placed chart once: dilation and the seam fit run there.
// Reading the charts in any parts and assembling them gives bakeLightmaps' images bit for bit.
struct LightmapPart {
    std::vector<uint32_t> charts;       // chart indices read, increasing
    std::vector<float> rgb;             // their texels, chart after chart, row after row: 3 each
    std::vector<TexelState> state;      // the same texels' states
    std::vector<uint64_t> edge_queries; // the chart-edge queries read (lightmap_seams.h: EdgeLight)
    std::vector<DVec3> edge_light;      // and their light
    uint64_t covered = 0, hidden = 0, evaluated = 0, interpolated = 0, required = 0, edge_evaluations = 0;
    ReadoutWork work;                   // of the link read-out, without the points other parts own
};
// The charts `wanted` selects (per chart of the placed `layout`; empty: every chart).
LightmapPart readLightmapPart(const Scene& scene, const Solution& solution, const ReadoutOptions& readout,
                              const LightmapLayout& layout, const LightmapOptions& options,
                              std::span<const uint8_t> wanted, ParallelRunner& runner, Progress* progress = nullptr);
// False when the parts do not cover every placed chart and chart-edge query once.
bool assembleLightmaps(const Scene& scene, LightmapLayout layout, const LightmapOptions& options,
                       std::span<const LightmapPart> parts, ParallelRunner& runner, Lightmaps& lightmaps);

}  // namespace radbake
