#pragma once
// Box utilities: corners, containment, volumes, and fitting a tight OBB to points.
#include <array>
#include <span>

#include "geometry/hull.h"
#include "geometry/types.h"

namespace radbake {

// Corner i has bit 0/1/2 choosing min/max (or -/+ half extent) along x/y/z (axes 0/1/2).
std::array<DVec3, 8> boxCorners(const Aabb& box);
std::array<DVec3, 8> boxCorners(const Obb& box);

Aabb aabbOf(std::span<const DVec3> points);
Aabb aabbOf(const Obb& box);  // the AABB of an OBB

double obbVolume(const Obb& box);
// Area of the largest face (the rectangle of a flat box).
double obbLargestFaceArea(const Obb& box);

bool contains(const Aabb& box, const DVec3& p, double tolerance);
bool contains(const Obb& box, const DVec3& p, double tolerance);

// Box from principal axes of the points' covariance (the classic PCA box).
Obb pcaObb(std::span<const DVec3> points);

// Tight OBB: minimum volume over candidate orientations made of the PCA axes, the hull's
// face normals (each with the minimum-area rectangle of the projection onto the face
// plane) and hull-edge directions; never larger than pcaObb. Flat or collinear input gives
// a flat box (half extent 0 along the normal).
Obb fitObb(std::span<const DVec3> points);
// Same, reusing a hull of the points already built (any tolerance).
Obb fitObb(const Hull3& hull, std::span<const DVec3> points);

// Flat box of a planar point set with unit normal n: half extent 0 along n, the
// rectangle is the minimum-area rectangle of the points projected onto the plane.
Obb flatObb(std::span<const DVec3> points, const DVec3& normal);

}  // namespace radbake
