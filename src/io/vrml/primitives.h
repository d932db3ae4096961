#pragma once
// Object-space tessellation of the VRML primitive shapes (Box/Cube, Sphere, Cylinder, Cone),
// shared by the VRML97 and VRML 1.0 readers. Each function appends to `mesh`: triangles are
// counter-clockwise seen from outside, polygon ids continue from mesh.polygon_count and each
// polygon's triangles are contiguous. Shapes are centred at the origin with their axis along
// +Y, as VRML defines them; the caller transforms the appended vertices to world space.
//
// Every face is one planar convex polygon (a box side, a side quad, a cap n-gon), which is
// what the radiosity stage wants as a patch. convex_solid is set only when the mesh held
// nothing before and the appended shape is closed (all its parts present).
#include "scene/scene.h"

namespace radbake::vrml {

// Segments around the axis of Sphere, Cylinder and Cone. 32 keeps the largest deviation of
// the polygon from the circle at 1 - cos(pi/32) = 0.48% of the radius.
inline constexpr int kRoundSegments = 32;
// Latitude bands of a Sphere (pole to pole).
inline constexpr int kSphereBands = 16;
// Crease angle given to round shapes so their sides shade smoothly while caps stay sharp:
// neighbouring side faces meet at 2 pi / 32 = 0.196 rad, sides meet caps at pi/2 or more.
inline constexpr float kRoundCreaseAngle = 0.5f;

void appendBox(Mesh& mesh, Vec3 size);
void appendSphere(Mesh& mesh, float radius);
void appendCylinder(Mesh& mesh, float radius, float height, bool side, bool top, bool bottom);
void appendCone(Mesh& mesh, float bottom_radius, float height, bool side, bool bottom);

enum class Primitive { Box, Sphere, Cylinder, Cone };

// Gives a primitive just appended to an empty mesh, still in object space, the texture
// coordinates ISO/IEC 14772-1 defines for it (6.4 Box, 6.14 Cone, 6.17 Cylinder, 6.43 Sphere):
// each box face and each cap holds the whole image upright as the standard views it; sides wrap
// it counter-clockwise seen from above from s = 0 at -Z, t from 0 at the bottom to 1 at the top
// (a sphere's t by latitude). Vertices whose corners need different coordinates (face edges, the
// seam at -Z, poles and apex) are split. `size` is the Box's size, or (radius, height, 0).
void primitiveTextureCoordinates(Mesh& mesh, Primitive kind, Vec3 size);

}  // namespace radbake::vrml
