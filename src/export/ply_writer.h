#pragma once
// Binary little-endian PLY of all the scene's meshes merged into one vertex list.
//
//   element vertex N: float x y z, float nx ny nz, float red green blue
//   element face F:   list uchar int vertex_indices (triangles)
//
// red/green/blue hold the baked value (by default H / pi, DESIGN.md section 2) as linear
// floats that may exceed 1; these are the names MeshLab, CloudCompare and Blender read as
// vertex colour (they clamp for display). A header comment repeats this for readers.
//
// With lightmaps (PlyOptions::lightmaps), meshes with charts are written from their
// LightmapMesh (vertices split at chart seams; normals and baked values carried over as in
// the .glb) and every vertex gains, after the colour:
//   float u1 v1      the lightmap UV (u right, v down from the image's top row)
//   uchar lightmap   the atlas index, 255 for the vertices of meshes without charts
// and header comments "comment lightmap <k> lightmaps/<name>_<k>.exr" name the atlas files.
#include <filesystem>
#include <string>

#include "readout/vertex_bake.h"
#include "core/diagnostics.h"
#include "export/lightmap_files.h"
#include "scene/scene.h"

namespace radbake {

struct PlyOptions {
    std::string generator = "radbake";  // written as a header comment
    const LightmapFiles* lightmaps = nullptr;  // when set, vertices carry u1 v1 and the atlas index
};

// The whole .ply file as bytes; empty after reporting an error.
std::string encodePly(const Scene& scene, const VertexBake& bake, const PlyOptions& options,
                      Diagnostics& diagnostics);

bool writePly(const std::filesystem::path& path, const Scene& scene, const VertexBake& bake,
              const PlyOptions& options, Diagnostics& diagnostics);

}  // namespace radbake
