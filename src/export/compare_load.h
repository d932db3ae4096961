#pragma once
// The files `radbake compare` reads (compare.h), loaded into plain structs: no comparison
// and no tolerance here. Each loader throws std::runtime_error saying what is wrong with the
// file; comparePaths catches it and reports the file as not comparable.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "core/exr_io.h"

namespace radbake {

// One run of vertices: a primitive of a glb mesh, or the vertex element of a PLY. Per-vertex
// arrays are flat (3 or 2 doubles a vertex) and empty when the file does not have them.
struct VertexBlock {
    std::string name;  // "mesh 'floor'", "mesh 'b' primitive 1"; empty for a PLY
    size_t count = 0;
    std::vector<double> light;      // 3: glb _RADBAKE_LIGHT (else COLOR_0); PLY red green blue
    std::vector<double> positions;  // 3: glb POSITION; PLY x y z
    std::vector<double> normals;    // 3: glb NORMAL; PLY nx ny nz
    std::vector<double> uv0;        // 2: glb TEXCOORD_0 (a PLY has none)
    std::vector<double> uv1;        // 2: glb TEXCOORD_1; PLY u1 v1 (the lightmap UVs)
    std::string lightmap;           // glb: the primitive's extras.radbake_lightmap
    std::vector<double> atlas;      // PLY: the per-vertex lightmap index (1 a vertex)
    bool has_atlas = false;         // the PLY has a 'lightmap' property
    std::string light_attribute;    // "_RADBAKE_LIGHT", "COLOR_0" or "red green blue"
};

// A .glb (one block per primitive of every mesh, in file order) or a .ply (one block).
struct MeshFile {
    std::vector<VertexBlock> blocks;
};

// probes.csv: the values r, g, b of each probe and, as written, the columns before them.
struct ProbeFile {
    std::string header;               // the first line
    std::vector<std::string> places;  // per probe: the columns before r, g, b (x..nz), as text
    std::vector<double> rgb;          // 3 per probe
};

// Binary glTF 2.0: float VEC3 light, POSITION and NORMAL, float VEC2 TEXCOORD_0/1 accessors.
MeshFile loadGlbFile(const std::filesystem::path& path);

// Binary little-endian PLY whose first element is `vertex` (as radbake writes it): red green
// blue (float, double or uchar / 255), x y z, nx ny nz, u1 v1 and lightmap when present.
MeshFile loadPlyFile(const std::filesystem::path& path);

ProbeFile loadProbesFile(const std::filesystem::path& path);

RgbImage loadExrFile(const std::filesystem::path& path);

}  // namespace radbake
