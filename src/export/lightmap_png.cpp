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

std::string chunk(const char* type, const std::string& data) {
    const std::string body = type + data;
    std::string out;
    appendBigEndian(out, static_cast<uint32_t>(data.size()));
    out += body;
    appendBigEndian(out, crc32(body));
    return out;
}

}  // namespace

std::array<uint8_t, 4> encodeRgbe(float r, float g, float b) {
    const auto clean = [](float v) { return v > 0.0f ? static_cast<double>(v) : 0.0; };  // NaN: 0
    const std::array<double, 3> rgb = {clean(r), clean(g), clean(b)};
    const double peak = std::max({rgb[0], rgb[1], rgb[2]});
    if (!(peak > std::ldexp(1.0, -136))) return {0, 0, 0, 0};  // below half the smallest code: 0
    if (!std::isfinite(peak) || peak >= std::ldexp(255.5, 127 - 8)) return {255, 255, 255, 255};
    int exponent = 0;
    std::frexp(peak, &exponent);  // peak = f 2^exponent, f in [0.5, 1): its code in [128, 256]
    if (std::lround(std::ldexp(peak, 8 - exponent)) > 255) ++exponent;
    exponent = std::max(exponent, -127);  // alpha 1: the tiniest values keep fewer bits
    std::array<uint8_t, 4> texel{};
    for (int c = 0; c < 3; ++c) texel[c] = static_cast<uint8_t>(std::lround(std::ldexp(rgb[c], 8 - exponent)));
    texel[3] = static_cast<uint8_t>(exponent + 128);
    return texel;
}

float decodeRgbe(uint8_t code, uint8_t exponent) {
    if (exponent == 0) return 0.0f;
    return static_cast<float>(std::ldexp(static_cast<double>(code), static_cast<int>(exponent) - 136));
}

std::string encodeLightmapPng(const RgbImage& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3)
        return {};
    try {
        // Scanlines of RGBA bytes, each after its filter byte: Sub (1), the difference from
        // the pixel to the left, which smooth light makes small.
        const size_t width = static_cast<size_t>(image.width);
        const size_t row_bytes = width * 4;
        std::string rows;
        rows.reserve((row_bytes + 1) * static_cast<size_t>(image.height));
        std::string line(row_bytes, '\0');
        for (int y = 0; y < image.height; ++y) {
            for (size_t x = 0; x < width; ++x) {
                const float* rgb = &image.rgb[(static_cast<size_t>(y) * width + x) * 3];
                const std::array<uint8_t, 4> texel = encodeRgbe(rgb[0], rgb[1], rgb[2]);
                for (int c = 0; c < 4; ++c) line[4 * x + c] = static_cast<char>(texel[c]);
            }
            rows.push_back('\1');
            for (size_t b = 0; b < row_bytes; ++b)
                rows.push_back(static_cast<char>(static_cast<uint8_t>(line[b]) - (b >= 4 ? static_cast<uint8_t>(line[b - 4]) : 0)));
        }
        const std::string packed = zlibCompress(rows);
        if (packed.empty()) return {};
        std::string header;
        appendBigEndian(header, static_cast<uint32_t>(image.width));
        appendBigEndian(header, static_cast<uint32_t>(image.height));
        header += std::string("\x08\x06\x00\x00\x00", 5);  // 8 bits, RGBA, deflate, adaptive filters, no interlace
        return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", header) +
               chunk("tEXt", std::string("radbake:encoding") + '\0' +
                                 "rgbe8: value = 0 for alpha 0, else channel * 2^(alpha - 136) (linear, shared exponent)") +
               chunk("IDAT", packed) + chunk("IEND", "");
    } catch (...) {  // allocation failure: no PNG
        return {};
    }
}

}  // namespace radbake
