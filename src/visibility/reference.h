#pragma once
// Brute-force references for the shaft and occlusion tests: exact segment-vs-part tests over
// dense sample grids. Slow; for tests, benchmarks and debugging the fast tests.
#include <span>
#include <vector>

#include "geometry/types.h"

namespace radbake {

// Strict: true if the segment [a, b] passes through the part's interior (closed: strictly
// inside every face plane somewhere along it; flat: crosses the plane strictly from one side
// to the other at a point strictly inside the polygon). Touching counts as a miss.
// Non-strict (strict == false): any contact, boundary included, counts as a hit.
bool segmentHitsPart(const DVec3& a, const DVec3& b, const ConvexPart& part, bool strict);

// Points of a convex polygon: its vertices, and a barycentric grid of `subdivisions` steps
// over each triangle of its fan (edges and interior included).
std::vector<DVec3> polygonSamplePoints(std::span<const DVec3> polygon, int subdivisions);

struct SegmentCount {
    size_t segments = 0;
    size_t hits_strict = 0;  // through the interior
    size_t hits_any = 0;     // any contact
};

// Every (source sample, receiver sample) segment against the part.
SegmentCount countSegmentHits(std::span<const DVec3> source_samples,
                              std::span<const DVec3> receiver_samples, const ConvexPart& part);

}  // namespace radbake
