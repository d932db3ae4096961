#pragma once
// Chart edges and seams (issue 5). A bilinear lookup at a chart's edge reads the edge texels
// and the first ring of padding; dilation fills that ring with averages, so the lookup on a
// chart edge is off by about half a texel of gradient, and the two charts meeting at a seam
// (pieces of a region cut by the cap, charts of a smooth surface meeting below the crease
// angle) disagree. stitchLightmaps fits the texels under those lookups, by least squares, so
// that the lookup at every sampled edge point gives the light there (the vertex bake's value
// at a vertex) and both sides of a seam give the same light, while covered texels stay close
// to their evaluated values and only the padding moves freely. No texel leaves the light around
// it: a covered one stays between its value and the light at the points whose lookups read it,
// the padding within a few times that range (a chart narrower than a texel puts two edges with
// different light a fraction of a texel apart, and an unbounded fit runs its texels to any value).
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "bake/lightmap_bake.h"
#include "bake/lightmap_charts.h"
#include "core/math.h"
#include "scene/scene.h"

namespace radbake {

// A point on a chart's boundary edge.
struct EdgeSample {
    uint32_t chart = 0;
    DVec2 texel{0.0};         // continuous atlas texel coordinates (texel centres at +0.5)
    DVec3 p_world{0.0};       // on the chart face's own triangle
    DVec3 normal_world{0.0};  // that face's normal
    uint32_t mesh = 0, triangle = 0;  // that face's source triangle (Scene::meshes[mesh].triangles)
    // For a boundary point at the end of a seam (a chart corner on the seam): the seam sample
    // there, whose light (the mean over the faces meeting) it takes; -1 otherwise.
    int64_t seam = -1;
    // Midway along one straight boundary edge between the samples `span` before and after it
    // in ChartEdges::edges (0: none): where their light agrees, it takes their mean. Spans
    // nest (1 between samples with span 2 or 0, 2 between those with 4 or 0, ...), so an edge
    // where the light is smooth is read at every 2 x kMaxEdgeSpan-th sample.
    uint32_t span = 0;
};

// A point where two charts of one surface meet, seen from both.
struct SeamSample {
    EdgeSample a, b;
};

struct ChartEdges {
    std::vector<EdgeSample> edges;  // boundary points that are not on a seam
    std::vector<SeamSample> seams;
};

// Samples the boundary of every placed chart (about two points per texel of edge, ends
// included) and pairs the boundary edges of different charts that lie on one surface: the
// two sides of a cut through a triangle, or of a source edge whose faces' dihedral angle is
// within the mesh's crease angle (or coplanar). Deterministic order: chart by chart.
ChartEdges findChartEdges(const Scene& scene, const LightmapLayout& layout);

// Bilinear lookup at continuous texel coordinates (texel centres at +0.5), clamped to the image.
DVec3 bilinearLookup(const LightmapImage& image, const DVec2& texel);

// Fits the texels under the edge and seam lookups (see the top of this file); values are
// H / pi from `irradiance`, evaluated once per distinct (point, normal). tolerance > 0: an
// edge sample between two (EdgeSample::span) whose light agrees within that relative
// tolerance (or `dark`, as the texels' evaluateTexelsAdaptive takes it; negative: 1 % of the
// brightest edge light) takes their mean instead of an evaluation (about one evaluation per
// four texels of edge where the light is smooth). Groups of charts
// joined by seams are solved in parallel, each on its own: the result does not depend on the
// runner's thread count. Needs padding >= 1 (a lookup on an edge reads one
// padding ring); does nothing otherwise. Fills and returns lightmaps.stitch.
// The light (H / pi) at every query of a ChartEdges (its edges, then each seam's a and b), as
// stitchLightmaps reads it, and what was read.
struct EdgeLight {
    std::vector<DVec3> light;   // per query
    std::vector<uint8_t> read;  // per query: 1 when read (its chart was wanted)
    size_t evaluations = 0;     // irradiance evaluations of the points the wanted charts own
};
// `wanted` (per chart; empty: every chart): only the queries of those charts are read, each
// (with `dark` given) the same as when every chart is. A point asked for by several queries is
// read once, as its first query, whose chart owns it; points the wanted charts need but do not
// own are read between shared(true) and shared(false) (when given), so a shard can leave their
// work to the shard that owns them.
EdgeLight readChartEdges(const ChartEdges& found, const IrradianceFunction& irradiance, ParallelRunner& runner,
                         double tolerance, double dark = -1.0, std::span<const uint8_t> wanted = {},
                         const std::function<void(bool)>& shared = {});
// The fit of the texels under the edge and seam lookups, from the light at every query.
StitchStats fitChartEdges(Lightmaps& lightmaps, const ChartEdges& found, const EdgeLight& light, ParallelRunner& runner);

StitchStats stitchLightmaps(const Scene& scene, Lightmaps& lightmaps, const IrradianceFunction& irradiance, int padding,
                            ParallelRunner& runner, double tolerance = 0.0, double dark = -1.0);

}  // namespace radbake
