#pragma once
// glTF 2.0 binary (.glb) of a scene's meshes with the baked value per vertex, written by
// hand (JSON text + one binary buffer). One glTF mesh with one triangle primitive and one
// node per radbake Mesh; POSITION, NORMAL, _RADBAKE_LIGHT (the baked value: linear float VEC3,
// may exceed 1), COLOR_0 (the same clamped to [0, 1], as glTF requires of colours) and uint32
// indices; one glTF material per Scene material with baseColorFactor =
// reflectance and emissiveFactor = emission (emission above 1 is normalised and carried by
// KHR_materials_emissive_strength).
//
// Source UVs (Mesh::uv0) are TEXCOORD_0, in glTF's convention (v down: (u, 1 - v) of the
// source's v-up UVs). A material whose meshes all have them carries its textures: base colour
// (baseColorFactor 1 for a VRML97 RGB texture, which replaces the colour), emissive and
// normal map, each an image embedded in the BIN chunk (PNG and JPEG as the file's bytes, or
// the bytes the source model embedded; other formats re-encoded to PNG), one texture per image
// and one repeating sampler; normal-mapped primitives carry TANGENT.
//
// With lightmaps (GltfOptions::lightmaps), a mesh that has charts is written from its
// LightmapMesh instead (vertices split at chart seams), as one primitive per atlas it uses,
// since an engine binds one lightmap per primitive:
//   POSITION, NORMAL (the source normals carried over with interpolateSource when the mesh
//   has them, else the face normal of the source triangle), _RADBAKE_LIGHT and COLOR_0 (the
//   vertex bake carried over with interpolateSource), TEXCOORD_1 = the lightmap UVs (u right, v down from the
//   image's top row, in [0, 1] of the atlas) and TEXCOORD_0 = the source UVs carried over with
//   interpolateSource, or, for a mesh without source UVs, the lightmap accessor again: glTF
//   wants UV sets numbered from 0 without gaps.
//   primitive extras: {"radbake_lightmap": "lightmaps/x_0.exr", "radbake_lightmap_index": 0}
//   mesh extras:      {"radbake_lightmaps": [the mesh's files, by atlas index]}
//   asset extras:     "radbake_lightmaps": every atlas file.
// glTF has no EXR images, so the files are named in extras rather than as textures. Meshes
// without charts are written as without lightmaps; with no lightmaps the output is unchanged.
#include <filesystem>
#include <string>

#include "bake/vertex_bake.h"
#include "core/diagnostics.h"
#include "export/lightmap_files.h"
#include "scene/scene.h"

namespace radbake {

struct GltfOptions {
    std::string generator = "radbake";  // asset.generator, e.g. "radbake 0.1.0"
    const LightmapFiles* lightmaps = nullptr;  // when set, meshes with charts carry TEXCOORD_1
};

// The whole .glb file as bytes; empty after reporting an error (bake does not match the scene).
std::string encodeGlb(const Scene& scene, const VertexBake& bake, const GltfOptions& options,
                      Diagnostics& diagnostics);

bool writeGlb(const std::filesystem::path& path, const Scene& scene, const VertexBake& bake,
              const GltfOptions& options, Diagnostics& diagnostics);

// True when `bake` has one value per vertex of every mesh; otherwise reports and returns false.
bool checkBakeMatchesScene(const Scene& scene, const VertexBake& bake, Diagnostics& diagnostics);

}  // namespace radbake
