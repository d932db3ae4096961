#pragma once
// glTF 2.0 binary (.glb) of a scene's meshes with the baked value per vertex, written by
// hand (JSON text + one binary buffer). One glTF mesh with one triangle primitive and one
// node per radbake Mesh; POSITION, NORMAL, COLOR_0 (the baked value: linear float VEC3, may
// exceed 1) and uint32 indices; one glTF material per Scene material with baseColorFactor =
// reflectance and emissiveFactor = emission (emission above 1 is normalised and carried by
// KHR_materials_emissive_strength).
#include <filesystem>
#include <string>

#include "bake/vertex_bake.h"
#include "core/diagnostics.h"
#include "scene/scene.h"

namespace radbake {

struct GltfOptions {
    std::string generator = "radbake";  // asset.generator, e.g. "radbake 0.1.0"
};

// The whole .glb file as bytes; empty after reporting an error (bake does not match the scene).
std::string encodeGlb(const Scene& scene, const VertexBake& bake, const GltfOptions& options,
                      Diagnostics& diagnostics);

bool writeGlb(const std::filesystem::path& path, const Scene& scene, const VertexBake& bake,
              const GltfOptions& options, Diagnostics& diagnostics);

// True when `bake` has one value per vertex of every mesh; otherwise reports and returns false.
bool checkBakeMatchesScene(const Scene& scene, const VertexBake& bake, Diagnostics& diagnostics);

}  // namespace radbake
