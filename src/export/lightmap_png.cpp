#include "export/lightmap_png.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "export/preview.h"

namespace radbake {
namespace {

// PNG's CRC-32 (ISO 3309, as the PNG specification's sample code), over chunk type and data.
uint32_t crc32(const std::string& bytes) {
    static const std::array<uint32_t, 256> table = [] {
        std::array<uint32_t, 256> t{};
        for (uint32_t n = 0; n < 256; ++n) {
            uint32_t c = n;
            for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[n] = c;
        }
        return t;
    }();
    uint32_t c = 0xFFFFFFFFu;
    for (const char b : bytes) c = table[(c ^ static_cast<uint8_t>(b)) & 0xFF] ^ (c >> 8);
    return c ^ 0xFFFFFFFFu;
}

void appendBigEndian(std::string& out, uint32_t value) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((value >> shift) & 0xFF));
}

std::string textChunk(const std::string& keyword, const std::string& text) {
    const std::string body = "tEXt" + keyword + '\0' + text;
    std::string chunk;
    appendBigEndian(chunk, static_cast<uint32_t>(body.size() - 4));
    chunk += body;
    appendBigEndian(chunk, crc32(body));
    return chunk;
}

// Signature (8 bytes) and IHDR (4 length + 4 type + 13 data + 4 CRC): the text goes after.
constexpr size_t kAfterIhdr = 8 + 25;

}  // namespace

float lightmapPngScale(const RgbImage& image) {
    float peak = 0.0f;
    for (const float v : image.rgb)
        if (std::isfinite(v)) peak = std::max(peak, v);
    return peak > 0.0f ? peak : 1.0f;
}

std::string encodeLightmapPng(const RgbImage& image, float scale) {
    if (!(scale > 0.0f) || !std::isfinite(scale) || image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3)
        return {};
    std::vector<uint8_t> bytes(image.rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i) {
        const double v = static_cast<double>(image.rgb[i]) / static_cast<double>(scale);
        bytes[i] = v > 0.0 ? static_cast<uint8_t>(std::lround(std::min(v, 1.0) * 255.0)) : 0;  // NaN: 0
    }
    std::string png = encodeRgb8Png(image.width, image.height, bytes);
    if (png.size() < kAfterIhdr || png.compare(12, 4, "IHDR") != 0) return {};
    char number[32];
    std::snprintf(number, sizeof number, "%.9g", static_cast<double>(scale));
    png.insert(kAfterIhdr, textChunk("radbake:lightmap_scale", number) +
                               textChunk("radbake:encoding", "linear RGB: value = byte / 255 * radbake:lightmap_scale"));
    return png;
}

}  // namespace radbake
