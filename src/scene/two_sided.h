#pragma once
// Two-sided surfaces: a mesh that is not `solid` (VRML `solid FALSE`, a VRML 1.0 IndexedFaceSet
// not declared SOLID with a known vertex ordering, an Assimp material marked two-sided: glTF
// `doubleSided`) receives, reflects and emits on both sides, each side with its own light.
//
// The pipeline step below gives each such mesh a back twin: a mesh of its own with the same
// vertices, the winding reversed, the normals negated and the same material, appended after
// every original mesh. Every later stage then works on one-sided polygons unchanged; the few
// that must know (parts, rays, overlap checks, summaries, outputs) read Mesh::twin and
// Mesh::back. Triangle t of a twin is triangle t of its front reversed ((a, b, c) -> (a, c, b)),
// with the same polygon numbering.
#include <cstddef>
#include <cstdint>

#include "scene/scene.h"

namespace radbake {

// Appends a back twin for every two-sided mesh that has none yet, links the pair (twin, back)
// and returns how many it added. Running it again adds nothing.
size_t addBackTwins(Scene& scene);

// The mesh whose surface this one is: itself, or for a back twin its front.
inline uint32_t frontMesh(const Scene& scene, uint32_t mesh) {
    const Mesh& m = scene.meshes[mesh];
    return m.back && m.twin < scene.meshes.size() ? m.twin : mesh;
}

// The suffix a back twin's name carries after its front's ("wall (back)").
inline constexpr const char* kBackSuffix = " (back)";

}  // namespace radbake
