// Texture decoding with stb_image (the only file that includes stb_image.h).
#include "scene/texture_image.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <memory>

#include "core/memory.h"
#include "core/read_policy.h"
#include "core/regular_file.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC  // private copy: no symbol clash with any other stb user
#include <stb_image.h>

namespace radbake {
namespace {

// stb_image over texture.embedded, or over the file at texture.path, opened once and only
// when it is a regular file (stb_image would wait forever on a FIFO, read /dev/zero forever).
class ImageSource {
public:
    ImageSource(const TextureRef& texture, std::string& why, const ReadPolicy* policy) : texture_(texture) {
        if (!texture.embedded) file_ = openRegularFile(texture.path, why, kDefaultMaxInputBytes, openedCheckOf(policy));
    }
    bool opened() const { return texture_.embedded || file_; }

    bool info(int* w, int* h, int* c) const {
        return texture_.embedded ? stbi_info_from_memory(bytes(), size(), w, h, c) : stbi_info_from_file(rewound(), w, h, c);
    }
    bool isHdr() const {
        return texture_.embedded ? stbi_is_hdr_from_memory(bytes(), size()) : stbi_is_hdr_from_file(rewound());
    }
    bool is16Bit() const {
        return texture_.embedded ? stbi_is_16_bit_from_memory(bytes(), size()) : stbi_is_16_bit_from_file(rewound());
    }
    float* loadFloat(int* w, int* h, int* c, int wanted) const {
        return texture_.embedded ? stbi_loadf_from_memory(bytes(), size(), w, h, c, wanted)
                                 : stbi_loadf_from_file(rewound(), w, h, c, wanted);
    }
    stbi_us* load16(int* w, int* h, int* c, int wanted) const {
        return texture_.embedded ? stbi_load_16_from_memory(bytes(), size(), w, h, c, wanted)
                                 : stbi_load_from_file_16(rewound(), w, h, c, wanted);
    }
    stbi_uc* load8(int* w, int* h, int* c, int wanted) const {
        return texture_.embedded ? stbi_load_from_memory(bytes(), size(), w, h, c, wanted)
                                 : stbi_load_from_file(rewound(), w, h, c, wanted);
    }

private:
    const stbi_uc* bytes() const { return reinterpret_cast<const stbi_uc*>(texture_.embedded->data()); }
    int size() const { return static_cast<int>(std::min<size_t>(texture_.embedded->size(), INT_MAX)); }
    // Each call reads the file from its start, whatever the call before it read.
    std::FILE* rewound() const {
        std::rewind(file_.get());
        return file_.get();
    }

    const TextureRef& texture_;
    InputFile file_;
};

std::string failure(const char* fallback) { return stbi_failure_reason() ? stbi_failure_reason() : fallback; }

}  // namespace

bool textureDecodeFits(int width, int height, int channels, double bytes_per_value, double max_memory_mb,
                       std::string& error) {
    const double pixels = static_cast<double>(width) * static_cast<double>(height);
    // The decoder's buffer (up to 16 bits a value, and its inflate scratch) besides ours.
    const double bytes = pixels * std::max(channels, 1) * (bytes_per_value + 2.0 * sizeof(uint16_t));
    const double budget_mb = memoryBudgetMegabytes(max_memory_mb);
    const std::string size = "a " + std::to_string(width) + " x " + std::to_string(height) + " image";
    if (pixels > kMaxTexturePixels && !(max_memory_mb > 0.0)) {
        error = size + " has more than " + std::to_string(static_cast<long long>(kMaxTexturePixels)) +
                " pixels (give --max-memory to allow more)";
        return false;
    }
    if (fitsMemoryBudget(budget_mb, bytes)) return true;
    error = size + " decodes to about " + bytesText(bytes) + ", more than the memory budget of " +
            bytesText(budget_mb * 1048576.0) + " leaves (--max-memory)";
    return false;
}

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

std::optional<TextureImage> readTextureImage(const TextureRef& texture, bool srgb, std::string& error,
                                             double max_memory_mb, bool* too_large, const ReadPolicy* policy) {
    const ImageSource source(texture, error, policy);
    if (!source.opened()) return std::nullopt;
    TextureImage image;
    int channels = 0;
    if (!source.info(&image.width, &image.height, &channels)) {
        error = failure("unknown image format");
        return std::nullopt;
    }
    if (!textureDecodeFits(image.width, image.height, channels, sizeof(float), max_memory_mb, error)) {
        if (too_large) *too_large = true;
        return std::nullopt;
    }
    image.channels = channels;
    const size_t count = static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * static_cast<size_t>(channels);
    const bool alpha = channels == 2 || channels == 4;
    // Colour channels of one texel; the last one is alpha when the image has one.
    auto isColour = [&](size_t i) { return !alpha || (i % static_cast<size_t>(channels)) != static_cast<size_t>(channels - 1); };
    int w = 0, h = 0, c = 0;
    if (source.isHdr()) {
        std::unique_ptr<float, void (*)(void*)> data(source.loadFloat(&w, &h, &c, channels), stbi_image_free);
        if (!data) {
            error = failure("cannot decode");
            return std::nullopt;
        }
        image.values.assign(data.get(), data.get() + count);
    } else if (source.is16Bit()) {
        std::unique_ptr<stbi_us, void (*)(void*)> data(source.load16(&w, &h, &c, channels), stbi_image_free);
        if (!data) {
            error = failure("cannot decode");
            return std::nullopt;
        }
        image.values.resize(count);
        for (size_t i = 0; i < count; ++i) {
            const float encoded = static_cast<float>(data.get()[i]) / 65535.0f;
            image.values[i] = srgb && isColour(i) ? srgbToLinear(encoded) : encoded;
        }
    } else {
        std::unique_ptr<stbi_uc, void (*)(void*)> data(source.load8(&w, &h, &c, channels), stbi_image_free);
        if (!data) {
            error = failure("cannot decode");
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

int imageChannels(const TextureRef& texture, const ReadPolicy* policy) {
    std::string why;
    const ImageSource source(texture, why, policy);
    int width = 0, height = 0, channels = 0;
    return source.opened() && source.info(&width, &height, &channels) ? channels : 0;
}

bool readImageRgba8(const TextureRef& texture, int& width, int& height, std::vector<uint8_t>& rgba, std::string& error,
                    const ReadPolicy* policy) {
    const ImageSource source(texture, error, policy);
    if (!source.opened()) return false;
    int channels = 0;
    if (!source.info(&width, &height, &channels)) {
        error = failure("unknown image format");
        return false;
    }
    if (!textureDecodeFits(width, height, 4, 1.0, 0.0, error)) return false;
    std::unique_ptr<stbi_uc, void (*)(void*)> data(source.load8(&width, &height, &channels, 4), stbi_image_free);
    if (!data) {
        error = failure("cannot decode");
        return false;
    }
    rgba.assign(data.get(), data.get() + static_cast<size_t>(width) * static_cast<size_t>(height) * 4);
    return true;
}

}  // namespace radbake
