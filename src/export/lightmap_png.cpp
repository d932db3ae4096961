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
    try {
        // Scanlines of big-endian 16-bit samples, each after its filter byte: Sub (1), the
        // difference from the pixel to the left, which smooth light makes small.
        const size_t row_bytes = static_cast<size_t>(image.width) * 6;
        std::string rows;
        rows.reserve((row_bytes + 1) * static_cast<size_t>(image.height));
        std::string line(row_bytes, '\0');
        for (int y = 0; y < image.height; ++y) {
            for (size_t i = 0; i < static_cast<size_t>(image.width) * 3; ++i) {
                const double v = static_cast<double>(image.rgb[static_cast<size_t>(y) * image.width * 3 + i]) / scale;
                const uint16_t q = v > 0.0 ? static_cast<uint16_t>(std::lround(std::min(v, 1.0) * 65535.0)) : 0;  // NaN: 0
                line[2 * i] = static_cast<char>(q >> 8);
                line[2 * i + 1] = static_cast<char>(q & 0xFF);
            }
            rows.push_back('\1');
            for (size_t b = 0; b < row_bytes; ++b)
                rows.push_back(static_cast<char>(static_cast<uint8_t>(line[b]) - (b >= 6 ? static_cast<uint8_t>(line[b - 6]) : 0)));
        }
        const std::string packed = zlibCompress(rows);
        if (packed.empty()) return {};
        std::string header;
        appendBigEndian(header, static_cast<uint32_t>(image.width));
        appendBigEndian(header, static_cast<uint32_t>(image.height));
        header += std::string("\x10\x02\x00\x00\x00", 5);  // 16 bits, RGB, deflate, adaptive filters, no interlace
        char number[32];
        std::snprintf(number, sizeof number, "%.9g", static_cast<double>(scale));
        return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", header) +
               chunk("tEXt", std::string("radbake:lightmap_scale") + '\0' + number) +
               chunk("tEXt", std::string("radbake:encoding") + '\0' +
                                 "linear RGB, 16 bits: value = sample / 65535 * radbake:lightmap_scale") +
               chunk("IDAT", packed) + chunk("IEND", "");
    } catch (...) {  // allocation failure: no PNG
        return {};
    }
}

}  // namespace radbake
