#pragma once
// Golden-file comparison (`radbake compare A B`): two bake directories, or two files of the
// same kind, compared value by value.
//
//   .exr        R, G, B of every texel (the images must have the same size)
//   .glb        _RADBAKE_LIGHT (else COLOR_0) of every vertex of every primitive of every mesh (same meshes, same
//               primitives, same vertex counts, same lightmap file per primitive); a
//               primitive's TEXCOORD_1 (lightmap UVs) must match exactly
//   .ply        red, green, blue of every vertex (same vertex count); u1 v1 and lightmap,
//               when present, must match exactly
//   probes.csv  r, g, b of every probe (same probes: x..nz must match as written)
//
// Lightmap UVs are layout, not values: with different UVs a texel of one bake is not the
// same surface point in the other, so the files are not comparable (exit 2).
//
// A value pair (a, b) is within tolerance when |a - b| <= abs_tol or
// |a - b| <= rel_tol * max(|a|, |b|): abs_tol covers dark values, rel_tol bright ones. A NaN
// on one side only is an infinite difference. Directories are compared file by file over
// every file of these kinds under A (recursively); a file missing from B, or one of these
// kinds present only in B, makes the directories not comparable. Other files (manifest.json,
// stats.json, preview PNGs) are ignored: they hold hashes, timings and tone-mapped pictures.
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace radbake {

struct CompareOptions {
    double rel_tol = 1e-3;  // a little above half precision's rounding (2^-11 ~ 4.9e-4)
    double abs_tol = 1e-6;  // in the files' own units (H/pi, W/m^2 for probes)
};

struct ChannelDifference {
    std::string name;        // "R", "red", "r", ...
    double rmse = 0.0;
    double max_abs = 0.0;    // largest |a - b|
    double max_rel = 0.0;    // largest |a - b| / max(|a|, |b|) (0 when both are 0)
    double worst_excess = 0.0;  // min(abs/abs_tol, rel/rel_tol) at the worst place; > 1 fails
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
