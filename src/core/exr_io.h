#pragma once
// OpenEXR images of RGB light (lightmaps), written and read back. This pair of files is the
// only place that includes OpenEXR (DESIGN.md section 3); nothing here throws.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"

namespace radbake {

// Linear RGB, row-major with the top row first (y down, as the file and glTF's UVs have it).
struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // width * height * 3
    // String header attributes (name, value), e.g. {"radbake:version", "0.1.0"}; read back
    // in name order. Names must not collide with OpenEXR's own (channels, compression, ...).
    std::vector<std::pair<std::string, std::string>> attributes;
    bool half = true;  // on disk: 16-bit half (default) or 32-bit float channels
};

struct ExrWriteOptions {
    bool use_float = false;  // --exr-float: 32-bit channels instead of half
};

// ZIP-compressed scanline EXR with channels B, G, R. Values are rounded to the nearest half
// unless use_float; in half, values beyond +-65504 are clamped to it and NaN becomes 0, with a
// warning (infinite texels would show as burnt-out spots). False after reporting (bad size, I/O failure); a failed write leaves no file.
bool writeExr(const std::filesystem::path& path, const RgbImage& image, const ExrWriteOptions& options,
              Diagnostics& diagnostics);

// Reads R, G and B (half, float or uint channels, converted to float) and every string
// attribute. A missing colour channel is an error; nullopt after reporting.
std::optional<RgbImage> readExr(const std::filesystem::path& path, Diagnostics& diagnostics);

// `value` rounded to the nearest 16-bit half, as writeExr stores it (for tests and compare).
float roundToHalf(float value);

}  // namespace radbake
