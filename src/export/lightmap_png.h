#pragma once
// The lightmap as a texture a browser shows right (issue 33): each atlas also as an 8-bit PNG
// beside its EXR (lightmaps/<name>_<k>.png), embedded in the glb and referenced from the
// materials through MOZ_lightmap (gltf_writer.h).
//
// Encoding "rgbe8", Radiance's shared exponent in an RGBA PNG: a texel's three channels share
// the exponent in alpha, each keeps an 8-bit mantissa,
//     value = 0                            for alpha = 0
//     value = code * 2^(alpha - 136)       for alpha >= 1   (code = the channel's byte)
// so the texel's brightest channel keeps its value within 0.4 % (its code is 128 or more)
// whatever the atlas's range. Browsers decode any PNG to 8 bits, and a single linear or log
// scale cannot hold both a lamp's hot spot and a room's shadows in 8 bits (docs/gltf.md).
// No sRGB curve; the alpha is not coverage.
// Loaders decode the codes to linear floats before sampling (examples/web); the EXR keeps
// every value exactly.
#include <array>
#include <cstdint>
#include <string>

#include "core/exr_io.h"

namespace radbake {

struct LightmapPng {
    std::string file;   // relative to the bake folder: "lightmaps/<name>_<k>.png"
    std::string bytes;  // the PNG file
};

// The RGBA bytes of one texel; negative and NaN channels give 0, values beyond the largest
// exponent the largest code.
std::array<uint8_t, 4> encodeRgbe(float r, float g, float b);

// The value one channel's code stands for with the texel's exponent byte.
float decodeRgbe(uint8_t code, uint8_t exponent);

// The PNG (RGBA, 8 bits, row 0 at the top) of `image`, with a tEXt chunk naming the
// encoding. Empty when the image is empty or inconsistent.
std::string encodeLightmapPng(const RgbImage& image);

}  // namespace radbake
