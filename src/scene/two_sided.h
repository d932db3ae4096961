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
#include <vector>

#include "scene/scene.h"

namespace radbake {

// Closed two-sided meshes need no back twin. A mesh that is closed and consistently oriented
// with its fronts facing out (welded by position, every directed edge once and its reverse
// once, every edge-connected piece enclosing a positive volume) has backs that face only its
// own volume, and light enters that volume only from inside it. So when the mesh does not
// emit (a two-sided emitter's backs emit into its own volume: the outward two-sided furnace),
// no point or spot light is inside it or on its surface, and no emitting triangle of any mesh
// reaches into it (a corner or centroid inside or on the surface, or an edge crossing it), its
// backs are dark, H = 0 exactly: this marks it closed_two_sided and solid (one-sided from here
// on, a closed solid occluder in the parts again) and returns how many it marked. Open, inside-out
// or lit meshes are left two-sided. addBackTwins runs it first; `radbake info` reports it.
size_t settleClosedTwoSided(Scene& scene);

// Appends a back twin for every two-sided mesh that has none yet (after settleClosedTwoSided,
// which it runs first), links the pair (twin, back) and returns how many it added. Running it
// again adds nothing.
size_t addBackTwins(Scene& scene);

// Per mesh, per polygon: the fraction of a back twin's polygon in contact with another surface
// that covers it from in front (two_sided.cpp: a zero-width gap, dark exactly); empty for
// meshes that are not back twins or have nothing covered.
std::vector<std::vector<double>> backContactCoverage(const Scene& scene);

// Backs in a zero-width gap (two_sided.cpp): a back twin's polygon that another surface
// touches from in front (coplanar within 1e-5 of the extent, overlapping, no farther in front
// than that) is dark over the covered part, exactly in the limit of zero distance; left as it
// is, it and the surface it faces trade nearly all their light across the gap (a form factor
// near 1, row sums above 1 with duplicates), a two-surface furnace that graz.wrl's solve iterated
// 148 times. Each such polygon's reflectance and emission are scaled by its open fraction (0
// when covered over 99 %, unchanged under 1 %); geometry and occlusion are untouched, so no
// light passes through anything. addBackTwins runs it on the twins it adds; returns how many
// polygons it changed (added to Scene::covered_back_polygons).
size_t coverBacksInContact(Scene& scene);

// The mesh whose surface this one is: itself, or for a back twin its front.
inline uint32_t frontMesh(const Scene& scene, uint32_t mesh) {
    const Mesh& m = scene.meshes[mesh];
    return m.back && m.twin < scene.meshes.size() ? m.twin : mesh;
}

// The suffix a back twin's name carries after its front's ("wall (back)").
inline constexpr const char* kBackSuffix = " (back)";

}  // namespace radbake
