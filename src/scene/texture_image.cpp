// Texture decoding with stb_image (the only file that includes stb_image.h).
#include "scene/texture_image.h"

#include <cmath>
#include <memory>

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC  // private copy: no symbol clash with any other stb user
#include <stb_image.h>

namespace radbake {

float srgbToLinear(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

Vec4 TextureImage::texel(int64_t x, int64_t y) const {
    if (width <= 0 || height <= 0 || channels <= 0) return Vec4(1.0f);
    x %= width;
    y %= height;
    if (x < 0) x += width;
    if (y < 0) y += height;
    const float* v = values.data() + (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
                                         static_cast<size_t>(channels);
    switch (channels) {
        case 1: return Vec4(v[0], v[0], v[0], 1.0f);
        case 2: return Vec4(v[0], v[0], v[0], v[1]);
        case 3: return Vec4(v[0], v[1], v[2], 1.0f);
        default: return Vec4(v[0], v[1], v[2], v[3]);
    }
}

std::optional<TextureImage> readTextureImage(const std::string& path, bool srgb, std::string& error) {
    TextureImage image;
    int channels = 0;
    if (!stbi_info(path.c_str(), &image.width, &image.height, &channels)) {
        error = stbi_failure_reason() ? stbi_failure_reason() : "unknown image format";
        return std::nullopt;
    }
    image.channels = channels;
    const size_t count = static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * static_cast<size_t>(channels);
    const bool alpha = channels == 2 || channels == 4;
    // Colour channels of one texel; the last one is alpha when the image has one.
    auto isColour = [&](size_t i) { return !alpha || (i % static_cast<size_t>(channels)) != static_cast<size_t>(channels - 1); };
    int w = 0, h = 0, c = 0;
    if (stbi_is_hdr(path.c_str())) {
        std::unique_ptr<float, void (*)(void*)> data(stbi_loadf(path.c_str(), &w, &h, &c, channels), stbi_image_free);
        if (!data) {
            error = stbi_failure_reason() ? stbi_failure_reason() : "cannot decode";
            return std::nullopt;
        }
        image.values.assign(data.get(), data.get() + count);
    } else if (stbi_is_16_bit(path.c_str())) {
        std::unique_ptr<stbi_us, void (*)(void*)> data(stbi_load_16(path.c_str(), &w, &h, &c, channels), stbi_image_free);
        if (!data) {
            error = stbi_failure_reason() ? stbi_failure_reason() : "cannot decode";
            return std::nullopt;
        }
        image.values.resize(count);
        for (size_t i = 0; i < count; ++i) {
            const float encoded = static_cast<float>(data.get()[i]) / 65535.0f;
            image.values[i] = srgb && isColour(i) ? srgbToLinear(encoded) : encoded;
        }
    } else {
        std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(path.c_str(), &w, &h, &c, channels), stbi_image_free);
        if (!data) {
            error = stbi_failure_reason() ? stbi_failure_reason() : "cannot decode";
            return std::nullopt;
        }
        float table[256];  // the 256 possible values, decoded once
        for (int b = 0; b < 256; ++b) table[b] = static_cast<float>(b) / 255.0f;
        float decoded[256];
        for (int b = 0; b < 256; ++b) decoded[b] = srgb ? srgbToLinear(table[b]) : table[b];
        image.values.resize(count);
        for (size_t i = 0; i < count; ++i) image.values[i] = isColour(i) ? decoded[data.get()[i]] : table[data.get()[i]];
    }
    return image;
}

int imageChannels(const std::string& path) {
    int width = 0, height = 0, channels = 0;
    return stbi_info(path.c_str(), &width, &height, &channels) ? channels : 0;
}

bool readImageRgba8(const std::string& path, int& width, int& height, std::vector<uint8_t>& rgba, std::string& error) {
    int channels = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(path.c_str(), &width, &height, &channels, 4), stbi_image_free);
    if (!data) {
        error = stbi_failure_reason() ? stbi_failure_reason() : "cannot decode";
        return false;
    }
    rgba.assign(data.get(), data.get() + static_cast<size_t>(width) * static_cast<size_t>(height) * 4);
    return true;
}

}  // namespace radbake
