#pragma once
// Form factors between convex polygons, without visibility.
//
// Point to polygon: the exact Lambert contour integral, after clipping the polygon to the
// receiver's upper half-space (the formula is only right for the part above the tangent
// plane). Element to element: that exact inner integral over the source, integrated over the
// receiver with Gauss points on an adaptive subdivision that refines towards the source, so
// adjacent and nearby elements (where point estimates fail) stay accurate.
#include <span>

#include "radiosity/elements.h"

namespace radbake {

// Fraction of the energy leaving a differential area at `point` (unit `normal`) that reaches
// the convex polygon `source` (counter-clockwise around its unit `source_normal`), i.e. the
// differential-to-finite form factor. Zero when the point is not strictly in front of the
// source's plane. Polygons of at most 62 vertices.
double pointPolygonFormFactor(const DVec3& point, const DVec3& normal, std::span<const DVec3> source,
                              const DVec3& source_normal);

// pointPolygonFormFactor at each of `points` (one receiver normal), written to `out`: the same
// values to the bit, two points at a time where the whole source is above a point's horizon.
void pointPolygonFormFactors(std::span<const DVec3> points, const DVec3& normal, std::span<const DVec3> source,
                             const DVec3& source_normal, double* out);

// pointPolygonFormFactor at one point (and normal) to each of `sources`, written to `out`: the
// same values to the bit, two sources at a time where two in a row have as many vertices and
// lie wholly above the point's horizon.
void pointPolygonFormFactorsTo(const DVec3& point, const DVec3& normal, std::span<const PolygonView> sources,
                               double* out);

// The largest polygon pointPolygonFormFactor takes, plus room for the vertex its clip adds.
inline constexpr size_t kMaxClip = 64;

// `loop` (at most kMaxClip - 2 vertices) clipped to the half-space {y : normal . (y - point)
// >= 0} above a point's tangent plane, written to `out` (room for kMaxClip); returns its
// vertex count (< 3: nothing of it is above). pointPolygonFormFactor integrates this part,
// and the point gather aims its visibility rays at it.
size_t clipAboveHorizon(const DVec3& point, const DVec3& normal, std::span<const DVec3> loop, DVec3* out);

// pointPolygonFormFactor averaged over a quad receiver (its bilinear patch) with 2 x 2 Gauss
// points, weighted by the patch's area element: where the receiver touches the source the
// centroid alone is biased (solve.cpp's leaf row sums, cluster.cpp's kernels).
double gaussAveragedFormFactor(std::span<const DVec3> quad, const DVec3& quad_normal, std::span<const DVec3> source,
                               const DVec3& source_normal);

struct QuadratureOptions {
    // A receiver cell is integrated with its order x order Gauss rule once its distance to the source
    // exceeds `near_ratio` times its radius; otherwise it is split (up to max_depth levels).
    double near_ratio = 1.5;
    int max_depth = 5;
    int order = 3;  // Gauss points per side of a cell (1..4)
};

struct FormFactorEstimate {
    double form_factor = 0.0;  // receiver-area average of the point form factor
    double f_min = 0.0;        // min and max of the point form factor over the sample points
    double f_max = 0.0;
    int samples = 0;
};

// F(receiver -> source): the fraction of energy leaving the receiver that arrives at the
// source, unoccluded.
FormFactorEstimate polygonFormFactor(const PolygonView& receiver, const PolygonView& source,
                                     const QuadratureOptions& options);

// Distance from `point` to the convex polygon (0 when the point is on it).
double pointPolygonDistance(const DVec3& point, const PolygonView& polygon);

// True when some part of each polygon lies strictly in front of the other's plane (else no
// light can pass between them).
bool facing(const PolygonView& receiver, const PolygonView& source);

}  // namespace radbake
