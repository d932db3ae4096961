#pragma once
// The lightmap as a texture engines read (issue 14): each atlas also as an 8-bit PNG beside
// its EXR (lightmaps/<name>_<k>.png), embedded in the glb and referenced from the materials
// through MOZ_lightmap (gltf_writer.h).
//
// HDR encoding: a linear scale factor per atlas, in a 16-bit RGB PNG. Each channel is stored as
//     q = round(65535 * clamp(value / scale, 0, 1))      (no sRGB transfer curve)
// and reads back as value = q / 65535 * scale, within scale / 131070, where value is the
// EXR's (H/pi by default) and scale is the atlas's largest channel value, so no texel clips (1
// for an atlas without light). Linear, not sRGB or RGBM, because the loaders that read a
// lightmap extension (three.js, Hubs) sample its texture as linear data and multiply it by
// one intensity: a plain scale is the one HDR encoding they decode without a custom shader.
// 16 bits because 8 do not hold a room's range: the Cornell Box's block faces in shade sit
// near 1 % of the atlas's peak, 2 or 3 steps of 8 bits, and came out blotched and tinted (each
// channel rounding its own way). A browser decodes a 16-bit PNG to 8 bits (those steps
// again); Blender and engines' importers keep 16. The EXR keeps the full value.
// The scale is in the glb (material extras radbake_lightmap_scale; MOZ_lightmap intensity)
// and in the PNG itself, as tEXt chunks: "radbake:lightmap_scale" (the number, %.9g: the
// float exactly) and "radbake:encoding".
#include <string>

#include "core/exr_io.h"

namespace radbake {

struct LightmapPng {
    std::string file;     // relative to the bake folder: "lightmaps/<name>_<k>.png"
    std::string bytes;    // the PNG file
    float scale = 1.0f;   // value = q / 65535 * scale
};

// The atlas's largest finite channel value, or 1 when it has none above 0.
float lightmapPngScale(const RgbImage& image);

// The PNG (RGB, 16 bits, row 0 at the top) of `image` at `scale`, with its tEXt chunks;
// negative and NaN values give 0. Empty when the image is empty or inconsistent, or the
// scale is not a positive finite number.
std::string encodeLightmapPng(const RgbImage& image, float scale);

// The texel value a 16-bit sample of an atlas at `scale` stands for.
inline float decodeLightmapSample(unsigned short q, float scale) { return static_cast<float>(q) / 65535.0f * scale; }

}  // namespace radbake
