#pragma once
// What the mesh writers need to know of a bake's lightmaps: the lightmap meshes (split at
// chart seams, with TEXCOORD_1) and the file each atlas was written to.
#include <string>
#include <utility>
#include <vector>

#include "bake/lightmap_mesh.h"
#include "bake/lightmap_quantity.h"

namespace radbake {

struct LightmapFiles {
    std::vector<LightmapMesh> meshes;      // one per Scene mesh (lightmapMeshes); empty ones have no charts
    std::vector<std::string> atlas_files;  // per atlas, relative to the bake directory: "lightmaps/<name>_<k>.exr"
    LightmapQuantity quantity = LightmapQuantity::Irradiance;  // what the texels hold
    // With real-time lights: per atlas its shadowmask PNG ("lightmaps/<name>_<k>_shadowmask.png"),
    // and each masked light's name and channel (bake/shadowmask.h).
    std::vector<std::string> shadowmask_files;
    std::vector<std::pair<std::string, int>> shadowmask_channels;
    // With --directional: per atlas its direction EXR ("lightmaps/<name>_<k>_direction.exr").
    std::vector<std::string> direction_files;
};

}  // namespace radbake
