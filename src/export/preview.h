#pragma once
// `--preview`: tone-mapped PNGs of the lightmap atlases and a view of the baked scene, so a
// person can look at a bake (issue 5). preview.cpp is the only file that includes
// stb_image_write.h. Nothing here throws; everything is deterministic and independent of the
// thread count.
#include <filesystem>
#include <string>
#include <vector>

#include "bake/lightmap_bake.h"
#include "bake/lightmap_mesh.h"
#include "readout/vertex_bake.h"
#include "core/diagnostics.h"
#include "core/parallel.h"
#include "core/exr_io.h"
#include "scene/scene.h"

namespace radbake {

// 8-bit sRGB PNG bytes (no file I/O) of a linear RGB image (row 0 at the top), tone-mapped:
// c = value * exposure; Reinhard on luminance (L = 0.2126 R + 0.7152 G + 0.0722 B, each
// channel scaled by 1 / (1 + L), so hue is kept and L maps to L / (1 + L)); each channel
// clamped to [0, 1] (negative and NaN give 0); the sRGB transfer (IEC 61966-2-1); rounded to
// the nearest of 0..255. So grey 1 encodes to 188, grey 3 to 225, pure red (1, 0, 0) to
// (234, 0, 0). Empty string for an empty or inconsistent image.
std::string encodePreviewPng(const RgbImage& linear, double exposure);

// 8-bit RGBA pixels (top row first) as PNG bytes, no conversion: how the glb re-encodes a
// texture that is neither PNG nor JPEG. Empty when the image is empty, inconsistent or too large.
std::string encodeRgba8Png(int width, int height, const std::vector<uint8_t>& rgba);

// A zlib stream (RFC 1950) of `bytes`, as PNG's IDAT wants it (stb_image_write's deflate):
// the lightmap PNGs (lightmap_png.h) are 16-bit, which stb_image_write does not write. Empty
// on failure.
std::string zlibCompress(const std::string& bytes);

// encodePreviewPng written to `path`. An image that cannot be encoded (empty, inconsistent,
// too large for the encoder, out of memory) is an error at `path` and nothing is written: a
// 0-byte PNG would be listed in the manifest as if it were a preview. False after reporting.
bool writePreviewPng(const std::filesystem::path& path, const RgbImage& linear, double exposure,
                     Diagnostics& diagnostics);

// The exposure that maps the image's key, the log-average luminance exp(mean(ln L)) of its
// pixels with L > 0, to kPreviewKey, the scene value that encodePreviewPng shows as mid grey
// (sRGB 128 of 255): a uniform image of any brightness encodes to 128. 1 for an all-black
// image (or one with no finite positive luminance).
double autoExposure(const RgbImage& linear);

// A lightmap atlas as an image to encode or write (its texel states dropped).
RgbImage toRgbImage(const LightmapImage& image);

// L / (1 + L) = 0.2158605 (the linear value of sRGB 128 / 255) gives L = 0.2752833.
inline constexpr double kPreviewKey = 0.2752833;

// The baked scene seen from `camera` (nullptr: a default camera framing the scene's bounding
// sphere, looking at its centre from the direction (1, 1, 2) / sqrt(6) (front, right and
// above, as VRML's default view looks down -Z), +Y up, 45 degree field of view). The field of
// view is the smaller of the two view angles. Per pixel (ray through its centre): the first
// surface hit; outgoing radiance = reflectance * baked + emission (DESIGN.md section 2), with
// `baked` from the lightmap (bilinear at the hit's TEXCOORD_1) when `lightmaps` and
// `lightmap_meshes` are given, else the vertex bake interpolated at the hit; background
// black. Back faces show their front's light (the same radiance), since the bake is one-sided
// and a closed room seen from outside should still show its light. Linear RGB, row 0 at the
// top. Rows are rendered in parallel under the caller's TBB thread limit.
// On the runner's threads (none given: all cores); each pixel writes its own slot, so the
// image does not depend on the thread count.
RgbImage renderBakedView(const Scene& scene, const VertexBake& bake, const Lightmaps* lightmaps,
                         const std::vector<LightmapMesh>* lightmap_meshes, const Camera* camera, int width,
                         int height, Diagnostics& diagnostics, ParallelRunner* runner = nullptr);

// The camera renderBakedView uses when given none (exposed for tests).
Camera defaultPreviewCamera(const Scene& scene);

}  // namespace radbake
