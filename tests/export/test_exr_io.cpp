// EXR round trips: what writeExr stores is what readExr returns (half: exactly the nearest
// halves of the input; float: the same floats), string attributes survive, errors are located.
#include <doctest/doctest.h>

#include <stdlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <vector>
#include <string>

#include "core/exr_io.h"
#include "temp_files.h"

using namespace radbake;
namespace fs = std::filesystem;
using testfs::readBytes;
using testfs::TempDir;

namespace {

// Values spanning what lightmaps hold: zero, tiny, ordinary, bright HDR, not representable in half.
RgbImage testImage(int width, int height) {
    RgbImage image;
    image.width = width;
    image.height = height;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                image.rgb.push_back(static_cast<float>(0.001 * std::pow(1.37, x + 2 * y + c) + 1e-7 * x));
    image.rgb[0] = 0.0f;
    image.rgb[4] = 1.0f / 3.0f;
    image.rgb[5] = 4000.5f;
    image.attributes = {{"radbake:options", "--quality draft"}, {"radbake:scene_hash", "sha256:abc123"},
                        {"radbake:version", "0.1.0"}};
    return image;
}

}  // namespace

TEST_CASE("half EXR round trip gives the nearest halves and keeps the attributes") {
    TempDir tmp;
    const RgbImage image = testImage(7, 5);
    Diagnostics diagnostics;
    REQUIRE(writeExr(tmp.path / "a.exr", image, ExrWriteOptions{}, diagnostics));
    const auto back = readExr(tmp.path / "a.exr", diagnostics);
    REQUIRE(back);
    CHECK_FALSE(diagnostics.hasErrors());
    CHECK(back->width == 7);
    CHECK(back->height == 5);
    CHECK(back->half);
    REQUIRE(back->rgb.size() == image.rgb.size());
    int differing_from_input = 0;
    for (size_t i = 0; i < image.rgb.size(); ++i) {
        CHECK(back->rgb[i] == roundToHalf(image.rgb[i]));
        if (back->rgb[i] != image.rgb[i]) ++differing_from_input;
    }
    CHECK(differing_from_input > 0);  // the file really is half precision
    CHECK(back->rgb[4] == doctest::Approx(1.0 / 3.0).epsilon(1.0 / 2048.0));  // half: 11-bit significand
    CHECK(back->rgb[5] == 4000.0f);                                            // spacing 2 at 2048..4096, tie to even
    CHECK(back->attributes == image.attributes);
}

TEST_CASE("float EXR round trip gives the same floats") {
    TempDir tmp;
    const RgbImage image = testImage(3, 9);
    Diagnostics diagnostics;
    REQUIRE(writeExr(tmp.path / "f.exr", image, ExrWriteOptions{true}, diagnostics));
    const auto back = readExr(tmp.path / "f.exr", diagnostics);
    REQUIRE(back);
    CHECK_FALSE(back->half);
    CHECK(back->rgb == image.rgb);
    CHECK(back->attributes == image.attributes);
}

TEST_CASE("rows are stored top row first") {
    TempDir tmp;
    RgbImage image;
    image.width = 2;
    image.height = 3;
    image.rgb.assign(18, 0.0f);
    image.rgb[(2 * 2 + 1) * 3 + 1] = 2.0f;  // x=1, y=2 (bottom row), green
    Diagnostics diagnostics;
    REQUIRE(writeExr(tmp.path / "r.exr", image, ExrWriteOptions{}, diagnostics));
    const auto back = readExr(tmp.path / "r.exr", diagnostics);
    REQUIRE(back);
    CHECK(back->rgb == image.rgb);
}

TEST_CASE("half output clamps what half cannot hold, with a warning; float keeps it") {
    TempDir tmp;
    RgbImage image;
    image.width = 2;
    image.height = 1;
    image.rgb = {1e6f, -1e6f, std::nanf(""), 65504.0f, 2.5f, std::numeric_limits<float>::infinity()};
    Diagnostics diagnostics;
    REQUIRE(writeExr(tmp.path / "h.exr", image, ExrWriteOptions{}, diagnostics));
    REQUIRE(diagnostics.warningCount() == 1);
    CHECK(diagnostics.all()[0].message.find("4 values outside half range") == 0);
    const auto back = readExr(tmp.path / "h.exr", diagnostics);
    REQUIRE(back);
    CHECK(back->rgb == std::vector<float>{65504.0f, -65504.0f, 0.0f, 65504.0f, 2.5f, 65504.0f});
    REQUIRE(writeExr(tmp.path / "f.exr", image, ExrWriteOptions{true}, diagnostics));
    CHECK(diagnostics.warningCount() == 1);
    const auto full = readExr(tmp.path / "f.exr", diagnostics);
    REQUIRE(full);
    CHECK(full->rgb[0] == 1e6f);
    CHECK(std::isnan(full->rgb[2]));
    CHECK(std::isinf(full->rgb[5]));
}

TEST_CASE("EXR errors are reported with the file, and a bad write leaves no file") {
    TempDir tmp;
    Diagnostics diagnostics;
    RgbImage wrong;
    wrong.width = 4;
    wrong.height = 4;
    wrong.rgb.assign(10, 1.0f);
    CHECK_FALSE(writeExr(tmp.path / "w.exr", wrong, ExrWriteOptions{}, diagnostics));
    CHECK_FALSE(fs::exists(tmp.path / "w.exr"));
    CHECK_FALSE(writeExr(tmp.path / "no" / "such" / "dir.exr", testImage(2, 2), ExrWriteOptions{}, diagnostics));
    CHECK_FALSE(readExr(tmp.path / "missing.exr", diagnostics));
    {
        std::FILE* f = std::fopen((tmp.path / "junk.exr").c_str(), "wb");
        REQUIRE(f);
        std::fputs("not an exr file at all", f);
        std::fclose(f);
    }
    CHECK_FALSE(readExr(tmp.path / "junk.exr", diagnostics));
    REQUIRE(diagnostics.errorCount() == 4);
    CHECK(diagnostics.all()[0].location.file == (tmp.path / "w.exr").string());
    CHECK(diagnostics.all()[0].message.find("4x4 with 10 values") != std::string::npos);
    CHECK(diagnostics.all()[2].location.file == (tmp.path / "missing.exr").string());
    CHECK(diagnostics.all()[3].location.file == (tmp.path / "junk.exr").string());
}
