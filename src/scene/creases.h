#pragma once
// Hard edges: a vertex shared by faces that meet at an edge sharper than the mesh's crease
// angle becomes one vertex per crease group (the faces around it joined through edges
// within the crease angle), so each face's corners carry that face's normal and light
// (VRML97 creaseAngle, ISO/IEC 14772-1 IndexedFaceSet; VRML 1.0 ShapeHints). Smooth surfaces keep
// their shared vertices, and the triangles of one polygon are never split from each other.
#include <cstddef>

#include "scene/scene.h"

namespace radbake {

// Below this 1 - cos(angle) two faces count as coplanar whatever the crease angle (about
// 0.8 degrees, the lightmap seams' coplanar rule): a wall modelled as several polygons
// whose float corners bend it by a hair stays one smooth surface.
inline constexpr double kCreaseCoplanar = 1e-4;

// Splits the vertices of one mesh. A mesh with normals of its own is left alone: its file
// says which corners are smooth (Assimp keeps corners with different normals apart, and
// VRML97 ignores creaseAngle where normals are given). Copies take the vertex's position,
// colour and uv0. Returns the vertices added; `split` counts the vertices that were shared
// across a hard edge.
size_t splitHardEdges(Mesh& mesh, size_t* split = nullptr);

// Every mesh of the scene; adds what it did to scene.crease_split. Running it again
// changes nothing.
void splitHardEdges(Scene& scene);

}  // namespace radbake
