#pragma once
// Material textures -> per-polygon reflectance and emission (DESIGN.md section 2: the solve
// is per polygon, so a texture is averaged over the part of it each polygon's UVs cover).
#include "core/diagnostics.h"
#include "core/read_policy.h"
#include "scene/scene.h"

namespace radbake {

// For every material with a base-colour or emissive texture: reads the image (in linear
// colour), averages it over each polygon of each mesh using the material (the UV triangle
// sampled on a grid, wrapped by repeat; the whole image for a mesh without UVs) and sets
// Mesh::polygon_reflectance / polygon_emission:
//   texture times the material's colour; with TextureRef::rgb_replaces (VRML97) an RGB
//   texture replaces the colour and an intensity one modulates it.
// Every texture named (base colour, emissive, normal map) is appended to Scene::input_files,
// found or not. One located warning per texture that cannot be read (the material's colour
// is used) and one per material whose texture has alpha cutouts (baked as opaque).
// A texture file `policy` refuses (outside the read roots, not a regular file) is one located
// warning naming it, noted in Scene::refused_inputs and dropped from its materials, unread.
// importScene calls it before validation, which clamps the values.
// A texture larger than --max-memory allows (`max_memory_mb`, texture_image.h's
// textureDecodeFits) is refused from its header: warned, dropped from its materials (never
// decoded, nor embedded in the glb), as a missing one.
void applyTextures(Scene& scene, const ReadPolicy& policy, double max_memory_mb, Diagnostics& diagnostics);

}  // namespace radbake
