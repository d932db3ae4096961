#pragma once
// Texture images read from files (PNG, JPEG, TGA, BMP, GIF, PSD, HDR, PNM: what stb_image
// reads). texture_image.cpp is the only file that includes stb_image.h.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/read_policy.h"
#include "scene/scene.h"

namespace radbake {

struct TextureImage {
    int width = 0;
    int height = 0;
    int channels = 0;           // in the file: 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA
    std::vector<float> values;  // `channels` per texel, row 0 = the image's top row, linear

    // Colour (grey replicated) and alpha (1 without an alpha channel) of texel (x, y),
    // wrapped by repeat.
    Vec4 texel(int64_t x, int64_t y) const;
    bool hasAlpha() const { return channels == 2 || channels == 4; }
};

// Pixels a decoded texture may have unless --max-memory was given and holds more.
inline constexpr double kMaxTexturePixels = 64.0 * 1024.0 * 1024.0;

// Whether a width x height image of `channels` may be decoded into `bytes_per_value` values:
// at most kMaxTexturePixels unless `max_memory_mb` (--max-memory; 0: the default budget, 3/4
// of the machine) is given, and never more than the budget leaves now. Checked from the
// header (stbi_info), before any pixel is decoded; otherwise `error` says why.
bool textureDecodeFits(int width, int height, int channels, double bytes_per_value, double max_memory_mb,
                       std::string& error);

// Decodes an image into linear values: 8- and 16-bit colour channels are decoded from sRGB
// when `srgb` (colour textures; normal maps are data), HDR files are linear already; alpha
// is never sRGB. nullopt with `error` set when the file cannot be read or decoded.
// The image is the file at texture.path, or texture.embedded when set.
// Refused by textureDecodeFits: `too_large` (when given) is set. With a `policy`, the file
// opened must be one it allows.
std::optional<TextureImage> readTextureImage(const TextureRef& texture, bool srgb, std::string& error,
                                             double max_memory_mb = 0.0, bool* too_large = nullptr,
                                             const ReadPolicy* policy = nullptr);

// The image as 8-bit RGBA bytes as stored (no colour conversion; HDR is mapped by stb_image's
// default 1/2.2 gamma), for re-encoding to PNG. False with `error` set when it cannot be read
// (or, with a `policy`, the file opened is not one it allows).
bool readImageRgba8(const TextureRef& texture, int& width, int& height, std::vector<uint8_t>& rgba, std::string& error,
                    const ReadPolicy* policy = nullptr);

// The channel count the file holds (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), 0 when it
// cannot be read: cheap, it reads the header only.
int imageChannels(const TextureRef& texture, const ReadPolicy* policy = nullptr);

// sRGB transfer function (IEC 61966-2-1), encoded in [0, 1] -> linear.
float srgbToLinear(float encoded);

}  // namespace radbake
