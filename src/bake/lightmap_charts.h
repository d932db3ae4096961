#pragma once
// Lightmap charts and their packing into atlases (issue 5). A chart is a connected set of
// coplanar triangles of one mesh (so one material), grown further across the mesh's smooth
// edges (dihedral angle below Mesh::crease_angle) while every face stays within a cone of the
// chart's normal and no two projected faces overlap; it is projected onto the seed face's
// plane (each face keeps its own triangle: ChartFace::worldPoint) and measured in texels at a
// fixed texel density; charts larger than the cap are cut into pieces along
// a grid in their plane, so one huge floor cannot eat an atlas.
//
// Texel frame: a chart's texel (i, j) covers plane coordinates
//   [min_plane.x + i / d, min_plane.x + (i + 1) / d] x [min_plane.y + j / d, ...]
// with d = texels_per_metre; in its atlas that texel is at column x + i, row y + j (row 0 is
// the image's top row, as glTF's TEXCOORD and the EXR file have it).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "scene/scene.h"

namespace radbake {

struct LightmapOptions {
    double texels_per_metre = 16.0;  // the scene is in metres (--texel-density is per scene unit)
    int max_chart_texels = 256;   // the cap: no chart side exceeds this; larger regions are split
    int min_chart_texels = 2;     // no chart side is smaller, however small its region
    int atlas_size = 1024;        // --atlas-size: atlases are at most this many texels a side
    int padding = 2;              // texels around every chart that belong to it alone (dilation fills them)
    // Fit the padding ring so that bilinear lookups along every chart edge give the light
    // there and both sides of a seam agree (lightmap_seams.h). Off: dilation only.
    bool stitch_seams = true;
    // --texel-tolerance: a block of texels is interpolated from its corners when the texels
    // evaluated inside it match that interpolation within this relative tolerance (or of 1%
    // of the brightest light), and the odd edge samples of the seam fit take their
    // neighbours' mean when those agree within it (lightmap_adaptive.h, lightmap_seams.h).
    // 0 evaluates every texel and edge sample: the exhaustive bake.
    double texel_tolerance = 0.02;
    // Per mesh (by index), a factor on texels_per_metre: per-object lightmap density
    // (--lightmap-scales). Empty, or shorter than the mesh list: 1.
    std::vector<double> mesh_texel_scale;
};

// The part of one source triangle that lies in a chart: the whole triangle (3 points) or,
// in a chart cut by the cap, the triangle clipped to the chart's cell (up to 7 points).
struct ChartFace {
    uint32_t triangle = 0;           // index into Mesh::triangles
    std::vector<DVec2> p_plane;      // counter-clockwise, metres in the chart's plane frame
    // The whole source triangle, projected (corner_plane) and in the world (corner_world):
    // a chart across smooth edges is not flat, so a plane point is lifted back onto its own
    // face's triangle and evaluated with that face's normal.
    std::array<DVec2, 3> corner_plane{};
    std::array<DVec3, 3> corner_world{};
    DVec3 normal_world{0.0, 0.0, 1.0};

    // The point of this face's triangle that projects to p_plane (barycentric lift).
    DVec3 worldPoint(const DVec2& p_plane) const {
        const DVec2 e1 = corner_plane[1] - corner_plane[0], e2 = corner_plane[2] - corner_plane[0];
        const DVec2 d = p_plane - corner_plane[0];
        const double det = e1.x * e2.y - e1.y * e2.x;
        if (det == 0.0) return corner_world[0];
        const double b1 = (d.x * e2.y - d.y * e2.x) / det, b2 = (e1.x * d.y - e1.y * d.x) / det;
        return corner_world[0] + b1 * (corner_world[1] - corner_world[0]) + b2 * (corner_world[2] - corner_world[0]);
    }
};

struct LightmapChart {
    uint32_t mesh = 0;
    uint32_t material = 0;
    // Plane frame: p_world = origin_world + p_plane.x * u_world + p_plane.y * v_world.
    DVec3 origin_world{0.0};
    DVec3 u_world{1.0, 0.0, 0.0}, v_world{0.0, 1.0, 0.0}, normal_world{0.0, 0.0, 1.0};
    DVec2 min_plane{0.0};  // plane coordinates of the corner of texel (0, 0)
    double texels_per_metre = 1.0;
    int width = 0, height = 0;  // texels, padding excluded
    std::vector<ChartFace> faces;
    double area = 0.0;  // m^2 of geometry in the chart
    // Placement, filled by packLightmapCharts: texel (0, 0) of the chart is at column x, row y.
    int atlas = -1;
    int x = 0, y = 0;

    // Continuous atlas texel coordinates of a plane point (texel centres at +0.5).
    DVec2 atlasTexel(const DVec2& p_plane) const {
        return DVec2(x, y) + (p_plane - min_plane) * texels_per_metre;
    }
    // The point of the chart's projection plane (on the geometry only for a flat chart; use
    // ChartFace::worldPoint for the surface point).
    DVec3 worldPoint(const DVec2& p_plane) const { return origin_world + p_plane.x * u_world + p_plane.y * v_world; }
};

struct LightmapAtlas {
    int width = 0, height = 0;
    std::vector<uint32_t> charts;  // indices into LightmapLayout::charts
};

struct LightmapLayout {
    std::vector<LightmapChart> charts;
    std::vector<LightmapAtlas> atlases;
    double occupancy = 0.0;         // chart texels (padding excluded) / atlas texels
    double padded_occupancy = 0.0;  // the same with each chart's padding counted
};

// Every non-degenerate triangle of every mesh lands in exactly one chart (or, when split,
// its pieces in several); charts come out mesh by mesh, in triangle order. Emitters get
// charts too (their texels hold what they receive). Unplaced (atlas == -1).
std::vector<LightmapChart> buildLightmapCharts(const Scene& scene, const LightmapOptions& options);

// An upper bound on the chart texels buildLightmapCharts would make at options.texels_per_metre
// (exact when no region exceeds the cap), found from the regions alone: its time and memory
// do not depend on the density, so the texel budget can reject a density a million times
// too high without building its charts.
double estimateLightmapTexels(const Scene& scene, const LightmapOptions& options);

// The scene's bounding-box diagonal (1 for an empty scene): the length every chart and seam
// tolerance is scaled by.
double lightmapExtent(const Scene& scene);

// Relative weld distance (times the extent): float positions carry ~1e-7 relative rounding,
// transforms a little more.
inline constexpr double kLightmapWeld = 1e-6;

// Welded vertex ids of a mesh: positions within about `weld` of each other (one quantisation
// cell) share an id, so edges of faces with duplicated vertices still connect.
std::vector<uint32_t> weldLightmapVertices(const Mesh& mesh, double weld);

// The part of a convex polygon inside the rectangle [lo, hi] (empty when fewer than 3 points remain).
std::vector<DVec2> clipToRectangle(std::vector<DVec2> polygon, const DVec2& lo, const DVec2& hi);

// Signed area of a polygon in the plane (positive when counter-clockwise).
double polygonArea(const std::vector<DVec2>& polygon);

}  // namespace radbake
