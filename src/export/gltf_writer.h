#pragma once
// glTF 2.0 binary (.glb) of a scene's meshes with the baked value per vertex, written by
// hand (JSON text + one binary buffer). One glTF mesh with one triangle primitive and one
// node per radbake Mesh; POSITION, NORMAL, _RADBAKE_LIGHT (the baked value: linear float VEC3,
// may exceed 1), COLOR_0 (the same clamped to [0, 1], as glTF requires of colours) and uint32
// indices; one glTF material per Scene material a primitive uses (in order of first use),
// with baseColorFactor = reflectance and emissiveFactor = emission (emission above 1 is
// normalised and carried by KHR_materials_emissive_strength).
//
// Source UVs (Mesh::uv0) are TEXCOORD_0, in glTF's convention (v down: (u, 1 - v) of the
// source's v-up UVs). A material whose meshes all have them carries its textures: base colour
// (baseColorFactor 1 for a VRML97 RGB texture, which replaces the colour), emissive and
// normal map, each an image embedded in the BIN chunk (PNG and JPEG as the file's bytes, or
// the bytes the source model embedded; other formats re-encoded to PNG), one texture per image
// and a repeating sampler; normal-mapped primitives carry TANGENT.
//
// With lightmaps (GltfOptions::lightmaps), a mesh that has charts is written from its
// LightmapMesh instead (vertices split at chart seams), as one primitive per atlas it uses,
// since an engine binds one lightmap per primitive:
//   POSITION, NORMAL (the source normals carried over with interpolateSource when the mesh
//   has them, else the face normal of the source triangle), _RADBAKE_LIGHT and COLOR_0 (the
//   vertex bake carried over with interpolateSource; no COLOR_0 with a lightmap texture,
//   below), TEXCOORD_1 = the lightmap UVs (u right, v down from the
//   image's top row, in [0, 1] of the atlas) and TEXCOORD_0 = the source UVs carried over with
//   interpolateSource, or, for a mesh without source UVs, the lightmap accessor again: glTF
//   wants UV sets numbered from 0 without gaps.
//   primitive extras: {"radbake_lightmap": "lightmaps/x_0.exr", "radbake_lightmap_index": 0}
//   mesh extras:      {"radbake_lightmaps": [the mesh's files, by atlas index]}
//   asset extras:     "radbake_lightmaps": every atlas file (and "radbake_lightmap_pngs").
// Each primitive on atlas k uses a material of its own for (source material, k), with extras
// naming the atlas: an importer that merges the primitives of one material (Blender) would
// otherwise lose which lightmap each uses. It keeps the source name, or, for a material
// spread over several atlases, is named "<material> (lightmap k)".
// With GltfOptions::lightmap_textures, that material also carries the atlas's PNG
// (lightmap_png.h, embedded, clamped and not mipmapped) through the lightmap UVs:
//   "extensions": {"MOZ_lightmap": {"index": T, "texCoord": 1, "intensity": pi}}
//   "extras": {..., "radbake_lightmap_png": "lightmaps/x_0.png", "radbake_lightmap_encoding": "rgbe8"}
// A loader decodes the PNG's codes to linear values before sampling (examples/web); intensity pi
// turns the decoded H/pi into the irradiance three.js adds the light map to.
// MOZ_lightmap (Mozilla Hubs, three.js's lightMap) rather than MSFT_lightmap (Babylon.js):
// three.js adds a light map to the irradiance and shades it with the albedo, which is what
// the texels mean (Babylon.js's loader applies MSFT_lightmap as a shadow map
// that multiplies the dynamic lighting; examples/babylonjs makes it multiply the albedo). Listed in extensionsUsed, not extensionsRequired: a loader without it
// still draws the meshes. Those primitives have no COLOR_0 (glTF multiplies the base colour
// by it, so an engine would apply the baked light twice); _RADBAKE_LIGHT keeps the vertex light.
// Meshes without charts are written as without lightmaps; with no lightmaps the output is
// unchanged.
//
// GltfOptions::export_lights adds the scene's lights as KHR_lights_punctual (off by default:
// they are baked, an engine would light the scene twice), each with extras.radbake_baked.
#include <filesystem>
#include <string>

#include "readout/vertex_bake.h"
#include "core/diagnostics.h"
#include "export/lightmap_files.h"
#include "export/lightmap_png.h"
#include "scene/scene.h"

namespace radbake {

struct GltfOptions {
    std::string generator = "radbake";  // asset.generator, e.g. "radbake 0.1.0"
    const LightmapFiles* lightmaps = nullptr;  // when set, meshes with charts carry TEXCOORD_1
    // With lightmaps: one PNG per atlas (lightmap_png.h), embedded and referenced from the
    // materials by MOZ_lightmap. Null: the atlases are named in extras only.
    const std::vector<LightmapPng>* lightmap_textures = nullptr;
    // Also write the scene's lights (KHR_lights_punctual), marked as baked. Off by default:
    // their light is in the bake already, so an engine would light the scene twice.
    bool export_lights = false;
};

// The whole .glb file as bytes; empty after reporting an error (bake does not match the scene).
std::string encodeGlb(const Scene& scene, const VertexBake& bake, const GltfOptions& options,
                      Diagnostics& diagnostics);

bool writeGlb(const std::filesystem::path& path, const Scene& scene, const VertexBake& bake,
              const GltfOptions& options, Diagnostics& diagnostics);

// True when `bake` has one value per vertex of every mesh; otherwise reports and returns false.
bool checkBakeMatchesScene(const Scene& scene, const VertexBake& bake, Diagnostics& diagnostics);

}  // namespace radbake
