#pragma once
// Golden-file comparison (`radbake compare A B`): two bake directories, or two files of the
// same kind, compared value by value.
//
//   .exr        R, G, B of every texel (the images must have the same size)
//   .glb        per vertex of every primitive of every mesh (same meshes, same primitives, same
//               vertex counts, same attributes, same lightmap file per primitive): the light
//               R, G, B (_RADBAKE_LIGHT, else COLOR_0) and the geometry: x y z (POSITION),
//               nx ny nz (NORMAL), u0 v0 (TEXCOORD_0), u1 v1 (TEXCOORD_1, the lightmap UVs)
//   .ply        per vertex (same vertex count, same properties): red, green, blue and x y z,
//               nx ny nz, u1 v1; the atlas index `lightmap` must match exactly
//   probes.csv  r, g, b of every probe (same probes: x..nz must match as written)
//
// A light value pair (a, b) is within tolerance when |a - b| <= abs_tol or
// |a - b| <= rel_tol * max(|a|, |b|): abs_tol covers dark values, rel_tol bright ones. Geometry
// is compared component by component against absolute tolerances only (CompareOptions), so
// that a moved vertex, a turned normal or a shifted UV fails (exit 1, naming the vertex) even
// when the vertex count is kept. A NaN on one side only is an infinite difference. Directories
// are compared file by file over every file of these kinds under A (recursively); a file
// missing from B, or one of these kinds present only in B, makes the directories not
// comparable. Other files (manifest.json, stats.json, timings.json, preview PNGs) are ignored:
// they hold hashes, counts, timings and tone-mapped pictures.
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace radbake {

struct CompareOptions {
    double rel_tol = 1e-3;  // a little above half precision's rounding (2^-11 ~ 4.9e-4)
    double abs_tol = 1e-6;  // in the files' own units (H/pi, W/m^2 for probes)
    // Geometry, absolute per component. Positions: times the extent of A's positions (the
    // diagonal of their bounding box over the whole file); 1e-6 is about 16 float roundings
    // (2^-24 ~ 6e-8) of a coordinate the size of the extent, far below any real move.
    double position_tol = 1e-6;
    double normal_tol = 1e-5;  // unit normals' components: about 0.0006 degrees
    double uv_tol = 1e-6;      // UVs in [0, 1]: under 1/60 texel of the largest (16384) atlas
};

struct ChannelDifference {
    std::string name;        // "R", "red", "r", ..., and the geometry's "x", "nx", "u1", ...
    double rmse = 0.0;
    double max_abs = 0.0;    // largest |a - b|
    double max_rel = 0.0;    // largest |a - b| / max(|a|, |b|) (0 when both are 0)
    double worst_excess = 0.0;  // at the worst place: min(abs/abs_tol, rel/rel_tol), geometry abs/tol; > 1 fails
    size_t worst = 0;        // index of the worst sample (texel, vertex or probe)
    std::string worst_place; // e.g. "texel (12, 40)", "mesh 'floor' vertex 17"
    double worst_a = 0.0, worst_b = 0.0;
};

struct FileDifference {
    std::string file;  // relative to the compared directories, or the file name given
    std::string kind;  // "exr", "glb", "ply", "probes"
    size_t samples = 0;
    bool comparable = true;
    std::string problem;  // why not comparable
    std::vector<ChannelDifference> channels;
    bool within = true;   // every value of every channel within tolerance
};

struct CompareResult {
    std::vector<FileDifference> files;
    std::vector<std::string> problems;  // not comparable as a whole (layout, missing files)
    // 0 within tolerance, 1 differences beyond it, 2 not comparable.
    int exitCode() const;
};

// Never throws; unreadable files are reported as not comparable.
CompareResult comparePaths(const std::filesystem::path& a, const std::filesystem::path& b,
                           const CompareOptions& options);

// A table of every file and channel, then one line naming the worst place of each failure.
std::string formatCompareResult(const CompareResult& result);

}  // namespace radbake
