#pragma once
// Small polygon and plane utilities, all in double.
#include <span>
#include <vector>

#include "geometry/types.h"

namespace radbake {

// Newell's normal of a closed loop: length = 2 * area, direction by the right-hand rule.
// Robust for non-planar and nearly degenerate loops.
DVec3 newellNormal(std::span<const DVec3> loop);

// Unit-normal plane through three points, counter-clockwise seen from the outside (the
// side the normal points to). The normal is zero if the points are collinear.
Plane planeFromPoints(const DVec3& a, const DVec3& b, const DVec3& c);

// Plane of a loop: Newell normal (normalised) through the loop's centroid.
Plane planeFromPolygon(std::span<const DVec3> loop);

double polygonArea(std::span<const DVec3> loop);
DVec3 polygonCentroid(std::span<const DVec3> loop);  // area-weighted; vertex mean if degenerate

// True if p (assumed on the polygon's plane) lies inside or within `tolerance` of a convex
// loop ordered counter-clockwise around `normal`.
bool pointInConvexPolygon(std::span<const DVec3> loop, const DVec3& normal, const DVec3& p,
                          double tolerance);

// True if the loop turns the same way (left around `normal`) at every vertex; collinear
// vertices (turn within tolerance) are allowed.
bool isConvexPolygon(std::span<const DVec3> loop, const DVec3& normal, double tolerance);

// Drops vertices that repeat or sit on the segment between their neighbours (within
// tolerance): a convex loop keeps only its corners.
std::vector<DVec3> removeCollinear(std::span<const DVec3> loop, double tolerance);

// Orthonormal u, v with u x v = n (n unit).
void tangentFrame(const DVec3& n, DVec3& u, DVec3& v);

// Largest coordinate extent of a point set (for scaling tolerances); 0 when empty.
double pointExtent(std::span<const DVec3> points);

}  // namespace radbake
