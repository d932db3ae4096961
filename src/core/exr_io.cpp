// The only file that includes OpenEXR. OpenEXR reports errors by throwing; every call is
// wrapped so that nothing crosses this boundary (DESIGN.md section 3).
#include "core/exr_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <half.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <system_error>
#include <vector>

namespace radbake {
namespace {

constexpr const char* kChannels[3] = {"R", "G", "B"};

SourceLocation at(const std::filesystem::path& path) { return SourceLocation{path.string(), 0, 0}; }

// One slice per channel over an interleaved RGB buffer of `type` (float or half), placed at
// the file's data window. OpenEXR converts half to float when reading, not when writing.
Imf::FrameBuffer rgbFrameBuffer(Imf::PixelType type, const char* rgb, const Imath::Box2i& window) {
    Imf::FrameBuffer frame;
    const size_t component = type == Imf::HALF ? sizeof(half) : sizeof(float);
    const size_t x_stride = 3 * component;
    const size_t y_stride = x_stride * static_cast<size_t>(window.max.x - window.min.x + 1);
    for (int c = 0; c < 3; ++c)
        frame.insert(kChannels[c], Imf::Slice::Make(type, rgb + c * component, window, x_stride, y_stride));
    return frame;
}

// Half overflows to infinity above 65504: an engine would show it as a burnt-out texel, so
// clamp to the largest half instead (and NaN to 0), counting what changed.
float toHalfRange(float value, size_t& clamped) {
    constexpr float kHalfMax = 65504.0f;
    if (std::isnan(value)) return ++clamped, 0.0f;
    if (value > kHalfMax || value < -kHalfMax) return ++clamped, std::clamp(value, -kHalfMax, kHalfMax);
    return value;
}

}  // namespace

float roundToHalf(float value) { return static_cast<float>(half(value)); }

bool writeExr(const std::filesystem::path& path, const RgbImage& image, const ExrWriteOptions& options,
              Diagnostics& diagnostics) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3) {
        diagnostics.error(at(path), "cannot write EXR: image is " + std::to_string(image.width) + "x" +
                                        std::to_string(image.height) + " with " + std::to_string(image.rgb.size()) +
                                        " values");
        return false;
    }
    try {
        Imf::Header header(image.width, image.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        const Imf::PixelType type = options.use_float ? Imf::FLOAT : Imf::HALF;
        for (const char* channel : kChannels) header.channels().insert(channel, Imf::Channel(type));
        for (const auto& [name, value] : image.attributes) header.insert(name, Imf::StringAttribute(value));
        Imf::OutputFile file(path.string().c_str(), header);
        std::vector<half> halves;
        if (type == Imf::HALF) {
            halves.reserve(image.rgb.size());
            size_t clamped = 0;
            for (float value : image.rgb) halves.push_back(half(toHalfRange(value, clamped)));  // round to nearest
            if (clamped > 0)
                diagnostics.warning(at(path), std::to_string(clamped) +
                                                  " values outside half range (or not finite) were clamped to "
                                                  "[-65504, 65504] (NaN to 0); 32-bit output keeps them");
        }
        const char* pixels = type == Imf::HALF ? reinterpret_cast<const char*>(halves.data())
                                               : reinterpret_cast<const char*>(image.rgb.data());
        file.setFrameBuffer(rgbFrameBuffer(type, pixels, header.dataWindow()));
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        std::error_code ignored;
        std::filesystem::remove(path, ignored);  // OpenEXR may have left a truncated file
        diagnostics.error(at(path), std::string("cannot write EXR: ") + e.what());
        return false;
    }
    return true;
}

std::optional<RgbImage> readExr(const std::filesystem::path& path, Diagnostics& diagnostics) {
    try {
        Imf::InputFile file(path.string().c_str());
        const Imf::Header& header = file.header();
        const Imath::Box2i window = header.dataWindow();
        RgbImage image;
        image.width = window.max.x - window.min.x + 1;
        image.height = window.max.y - window.min.y + 1;
        if (image.width <= 0 || image.height <= 0) {
            diagnostics.error(at(path), "EXR has an empty data window");
            return std::nullopt;
        }
        image.half = false;
        for (const char* channel : kChannels) {
            const Imf::Channel* found = header.channels().findChannel(channel);
            if (!found) {
                diagnostics.error(at(path), std::string("EXR has no ") + channel + " channel");
                return std::nullopt;
            }
            if (found->type == Imf::HALF) image.half = true;
        }
        image.rgb.assign(static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3, 0.0f);
        file.setFrameBuffer(rgbFrameBuffer(Imf::FLOAT, reinterpret_cast<const char*>(image.rgb.data()), window));
        file.readPixels(window.min.y, window.max.y);
        for (auto it = header.begin(); it != header.end(); ++it) {
            if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                image.attributes.emplace_back(it.name(), text->value());
        }
        std::sort(image.attributes.begin(), image.attributes.end());
        return image;
    } catch (const std::exception& e) {
        diagnostics.error(at(path), std::string("cannot read EXR: ") + e.what());
        return std::nullopt;
    }
}

}  // namespace radbake
