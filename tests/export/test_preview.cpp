// Preview PNGs: tone curve, auto exposure, and the rendered view of a baked scene.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>


#include "bake/lightmap_bake.h"
#include "bake/lightmap_mesh.h"
#include "bake/lightmap_pack.h"
#include "export/preview.h"
#include "temp_files.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

using namespace radbake;

namespace {

struct Decoded {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
    const uint8_t* at(int x, int y) const { return &rgb[(static_cast<size_t>(y) * width + x) * 3]; }
};

Decoded decodePng(const std::string& png) {
    Decoded out;
    int channels = 0;
    stbi_uc* data = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(png.data()), static_cast<int>(png.size()),
                                          &out.width, &out.height, &channels, 3);
    REQUIRE(data != nullptr);
    CHECK(channels == 3);
    out.rgb.assign(data, data + static_cast<size_t>(out.width) * out.height * 3);
    stbi_image_free(data);
    return out;
}

RgbImage imageOf(int width, int height, std::vector<float> rgb) {
    RgbImage image;
    image.width = width;
    image.height = height;
    image.rgb = std::move(rgb);
    return image;
}

RgbImage uniformImage(int width, int height, float value) {
    return imageOf(width, height, std::vector<float>(static_cast<size_t>(width) * height * 3, value));
}

// One mesh: the quad p0, p0 + a, p0 + a + b, p0 + b (counter-clockwise seen from a x b), one polygon.
Mesh quadMesh(const Vec3& p0, const Vec3& a, const Vec3& b, uint32_t material) {
    Mesh mesh;
    mesh.name = "quad";
    mesh.positions = {p0, p0 + a, p0 + a + b, p0 + b};
    mesh.triangles = {UVec3(0, 1, 2), UVec3(0, 2, 3)};
    mesh.triangle_polygon = {0, 0};
    mesh.polygon_count = 1;
    mesh.material = material;
    return mesh;
}

// A closed octahedron of the given radius (outward faces), one polygon per face.
Mesh octahedron(const Vec3& centre, float radius, uint32_t material) {
    Mesh mesh;
    mesh.name = "marker";
    mesh.positions = {centre + Vec3(radius, 0, 0), centre - Vec3(radius, 0, 0), centre + Vec3(0, radius, 0),
                      centre - Vec3(0, radius, 0), centre + Vec3(0, 0, radius), centre - Vec3(0, 0, radius)};
    mesh.triangles = {UVec3(0, 2, 4), UVec3(2, 1, 4), UVec3(1, 3, 4), UVec3(3, 0, 4),
                      UVec3(2, 0, 5), UVec3(1, 2, 5), UVec3(3, 1, 5), UVec3(0, 3, 5)};
    for (uint32_t t = 0; t < 8; ++t) mesh.triangle_polygon.push_back(t);
    mesh.polygon_count = 8;
    mesh.material = material;
    return mesh;
}

Material material(const Vec3& reflectance, const Vec3& emission) {
    Material m;
    m.reflectance = reflectance;
    m.emission = emission;
    return m;
}

// A vertex bake holding `value` at every vertex.
VertexBake uniformBake(const Scene& scene, const Vec3& value) {
    VertexBake bake;
    for (const Mesh& mesh : scene.meshes) bake.values.emplace_back(mesh.positions.size(), value);
    return bake;
}

Camera cameraAt(const Vec3& position, const Quat& orientation, double field_of_view) {
    Camera camera;
    camera.position = position;
    camera.orientation = orientation;
    camera.field_of_view = static_cast<float>(field_of_view);
    return camera;
}

Vec3 pixel(const RgbImage& image, int x, int y) {
    const float* p = &image.rgb[(static_cast<size_t>(y) * image.width + x) * 3];
    return Vec3(p[0], p[1], p[2]);
}

// Red emitter at x in [-2, -0.5], green at [0.5, 2], both y in [-1, 1], z = 0, facing +Z.
Scene twoEmitters() {
    Scene scene;
    scene.name = "two_emitters";
    scene.materials = {material(Vec3(0.5f), Vec3(3, 0, 0)), material(Vec3(0.5f), Vec3(0, 3, 0))};
    scene.meshes.push_back(quadMesh(Vec3(-2, -1, 0), Vec3(1.5f, 0, 0), Vec3(0, 2, 0), 0));
    scene.meshes.push_back(quadMesh(Vec3(0.5f, -1, 0), Vec3(1.5f, 0, 0), Vec3(0, 2, 0), 1));
    return scene;
}

// Pixel centre (x + 0.5 - W/2, H/2 - y - 0.5) x pixel_size x distance is where the ray meets
// the plane z = 0. With tan(fov / 2) = 0.5, the smaller side S spans it: pixel_size = 0.5 / (S/2);
// at distance 5 and S = 32 a pixel is 0.15625 m. `mirrored`: seen from behind (x flips).
void checkEmitterPixels(const RgbImage& image, bool mirrored) {
    const double pixel_m = 5.0 * 0.5 / (0.5 * std::min(image.width, image.height));
    int red = 0, green = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            double wx = (x + 0.5 - 0.5 * image.width) * pixel_m;
            const double wy = (0.5 * image.height - y - 0.5) * pixel_m;
            if (mirrored) wx = -wx;
            Vec3 expected(0.0f);
            if (std::abs(wy) < 1.0 && wx > -2.0 && wx < -0.5) expected = Vec3(3, 0, 0);
            if (std::abs(wy) < 1.0 && wx > 0.5 && wx < 2.0) expected = Vec3(0, 3, 0);
            const Vec3 got = pixel(image, x, y);
            CHECK(got == expected);
            red += got.x > 0;
            green += got.y > 0;
        }
    // 10 x 12 pixel centres fall inside each 1.5 m x 2 m emitter (0.15625 m pixels).
    CHECK(red == 120);
    CHECK(green == 120);
}

}  // namespace

TEST_CASE("encodePreviewPng gives the documented 8-bit values") {
    const float nan = std::nanf("");
    const RgbImage image = imageOf(4, 2, {0, 0, 0,    1, 1, 1,  3, 3, 3,    1, 0, 0,  //
                                          -1, nan, 1e30f, 0.001f, 0.001f, 0.001f, 0.5f, 0.5f, 0.5f, 0, 0, 2});
    const Decoded png = decodePng(encodePreviewPng(image, 1.0));
    REQUIRE(png.width == 4);
    REQUIRE(png.height == 2);
    auto expect = [&](int x, int y, int r, int g, int b) {
        CAPTURE(x);
        CAPTURE(y);
        CHECK(int(png.at(x, y)[0]) == r);
        CHECK(int(png.at(x, y)[1]) == g);
        CHECK(int(png.at(x, y)[2]) == b);
    };
    expect(0, 0, 0, 0, 0);
    expect(1, 0, 188, 188, 188);  // L = 1 -> 0.5 -> sRGB 0.7354
    expect(2, 0, 225, 225, 225);  // L = 3 -> 0.75 -> sRGB 0.8808
    expect(3, 0, 234, 0, 0);      // L = 0.2126 -> red 1 / 1.2126 -> sRGB 0.9186
    expect(0, 1, 0, 0, 255);      // negative and NaN black; 1e30 saturates
    expect(1, 1, 3, 3, 3);        // linear segment: 12.92 x 0.000999 x 255 = 3.29
    expect(2, 1, 156, 156, 156);  // L = 0.5 -> 1/3 -> sRGB 0.6125
    // Blue 2: L = 0.1444, blue 2 / 1.1444 = 1.75 clamps to 255.
    expect(3, 1, 0, 0, 255);

    // Exposure multiplies first: 0.5 at exposure 2 is 1 at exposure 1.
    const Decoded doubled = decodePng(encodePreviewPng(uniformImage(1, 1, 0.5f), 2.0));
    CHECK(int(doubled.at(0, 0)[0]) == 188);
    CHECK(encodePreviewPng(RgbImage{}, 1.0).empty());
    CHECK(encodePreviewPng(imageOf(2, 2, {1, 1, 1}), 1.0).empty());  // inconsistent size
    // Deterministic bytes.
    CHECK(encodePreviewPng(image, 1.0) == encodePreviewPng(image, 1.0));
}

TEST_CASE("writePreviewPng: an image that cannot be encoded is an error at the file, and no file is written") {
    testfs::TempDir tmp;
    Diagnostics diagnostics;
    const std::filesystem::path good = tmp.path / "good.png";
    REQUIRE(writePreviewPng(good, uniformImage(3, 2, 1.0f), 1.0, diagnostics));
    CHECK(diagnostics.all().empty());
    CHECK(testfs::readBytes(good) == encodePreviewPng(uniformImage(3, 2, 1.0f), 1.0));

    const std::filesystem::path empty = tmp.path / "empty.png";
    CHECK_FALSE(writePreviewPng(empty, RgbImage{}, 1.0, diagnostics));
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].location.file == empty.string());
    CHECK(diagnostics.all()[0].message == "cannot encode the preview PNG: the image is empty (0x0)");
    CHECK_FALSE(std::filesystem::exists(empty));

    const std::filesystem::path inconsistent = tmp.path / "inconsistent.png";
    CHECK_FALSE(writePreviewPng(inconsistent, imageOf(2, 2, {1, 1, 1}), 1.0, diagnostics));
    REQUIRE(diagnostics.errorCount() == 2);
    CHECK(diagnostics.all()[1].message == "cannot encode the preview PNG: the image has 3 values for 2x2 pixels");
    CHECK_FALSE(std::filesystem::exists(inconsistent));
}

TEST_CASE("autoExposure maps the log-average luminance to mid grey (128)") {
    for (float level : {1e-4f, 0.37f, 5.0f, 2e4f}) {
        CAPTURE(level);
        const RgbImage image = uniformImage(6, 5, level);
        const double exposure = autoExposure(image);
        CHECK(exposure == doctest::Approx(kPreviewKey / level).epsilon(1e-6));
        const Decoded png = decodePng(encodePreviewPng(image, exposure));
        for (uint8_t byte : png.rgb) CHECK(int(byte) == 128);
    }
    CHECK(autoExposure(uniformImage(3, 3, 0.0f)) == 1.0);
    // Black pixels are left out; the key of {1, 4} is their geometric mean 2.
    const RgbImage mixed = imageOf(4, 1, {0, 0, 0, 1, 1, 1, 4, 4, 4, 0, 0, 0});
    CHECK(autoExposure(mixed) == doctest::Approx(kPreviewKey / 2.0).epsilon(1e-9));
    // Luminance, not the channel mean: pure green 1 has L = 0.7152.
    const RgbImage green = imageOf(1, 1, {0, 1, 0});
    CHECK(autoExposure(green) == doctest::Approx(kPreviewKey / 0.7152).epsilon(1e-9));
}

TEST_CASE("renderBakedView: a red emitter on the left and a green one on the right, where the camera puts them") {
    const Scene scene = twoEmitters();
    const VertexBake bake = uniformBake(scene, Vec3(0.0f));
    const double fov = 2.0 * std::atan(0.5);
    Diagnostics diagnostics;

    SUBCASE("landscape: the field of view spans the height") {
        const Camera camera = cameraAt(Vec3(0, 0, 5), Quat(1, 0, 0, 0), fov);
        const RgbImage image = renderBakedView(scene, bake, nullptr, nullptr, &camera, 64, 32, diagnostics);
        REQUIRE(image.width == 64);
        REQUIRE(image.height == 32);
        checkEmitterPixels(image, false);
        // Red columns 19..28 and rows 10..21, as the field of view says.
        CHECK(pixel(image, 19, 10) == Vec3(3, 0, 0));
        CHECK(pixel(image, 28, 21) == Vec3(3, 0, 0));
        CHECK(pixel(image, 18, 15) == Vec3(0.0f));
        CHECK(pixel(image, 29, 15) == Vec3(0.0f));
        CHECK(pixel(image, 20, 9) == Vec3(0.0f));
        CHECK(pixel(image, 35, 15) == Vec3(0, 3, 0));
    }
    SUBCASE("portrait: the field of view spans the width") {
        const Camera camera = cameraAt(Vec3(0, 0, 5), Quat(1, 0, 0, 0), fov);
        const RgbImage image = renderBakedView(scene, bake, nullptr, nullptr, &camera, 32, 64, diagnostics);
        checkEmitterPixels(image, false);
    }
    SUBCASE("from behind (turned half a turn about +Y): red on the right, back faces show the front's light") {
        const Camera camera = cameraAt(Vec3(0, 0, -5), Quat(0, 0, 1, 0), fov);
        const RgbImage image = renderBakedView(scene, bake, nullptr, nullptr, &camera, 64, 32, diagnostics);
        checkEmitterPixels(image, true);
    }
    CHECK(diagnostics.errorCount() == 0);
    CHECK(diagnostics.warningCount() == 0);
}

TEST_CASE("renderBakedView: reflected light is reflectance x baked + emission") {
    Scene scene;
    scene.materials = {material(Vec3(0.5f, 0.25f, 0.8f), Vec3(0.1f, 0, 0))};
    scene.meshes.push_back(quadMesh(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 0));
    const VertexBake bake = uniformBake(scene, Vec3(2.0f, 4.0f, 1.0f));
    const Camera camera = cameraAt(Vec3(0, 0, 3), Quat(1, 0, 0, 0), 0.5);
    Diagnostics diagnostics;
    const RgbImage image = renderBakedView(scene, bake, nullptr, nullptr, &camera, 8, 8, diagnostics);
    // The quad fills the view (half-width 3 tan 0.25 = 0.77 < 1).
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const Vec3 p = pixel(image, x, y);
            CHECK(p.x == doctest::Approx(1.1).epsilon(1e-6));
            CHECK(p.y == doctest::Approx(1.0).epsilon(1e-6));
            CHECK(p.z == doctest::Approx(0.8).epsilon(1e-6));
        }
}

namespace {

struct LightmappedQuad {
    Scene scene;
    Lightmaps lightmaps;
    std::vector<LightmapMesh> meshes;
};

// A 2 m x 1.5 m quad, its lightmap charts packed and evaluated from `irradiance` (H, so texels
// hold H / pi), and its lightmap meshes.
LightmappedQuad lightmappedQuad(const IrradianceFunction& irradiance) {
    LightmappedQuad out;
    out.scene.materials = {material(Vec3(0.5f), Vec3(0.0f))};
    out.scene.meshes.push_back(quadMesh(Vec3(-1, -0.75f, 0), Vec3(2, 0, 0), Vec3(0, 1.5f, 0), 0));
    LightmapOptions options;
    options.texels_per_metre = 16.0;
    options.atlas_size = 128;
    Diagnostics diagnostics;
    LightmapLayout layout;
    REQUIRE(packLightmapCharts(buildLightmapCharts(out.scene, options), options, layout, diagnostics));
    ParallelRunner runner(Threading{.threads = 1});
    out.lightmaps = evaluateLightmaps(layout, irradiance, options.padding, runner);
    out.meshes = lightmapMeshes(out.scene, out.lightmaps.layout);
    REQUIRE(out.meshes.size() == 1);
    REQUIRE(!out.meshes[0].triangles.empty());
    return out;
}

}  // namespace

TEST_CASE("renderBakedView: the lightmap path and the vertex path agree") {
    const Camera camera = cameraAt(Vec3(0.3f, 0.2f, 4), Quat(1, 0, 0, 0), 1.0);
    SUBCASE("uniformly lit quad: equal, pixel for pixel") {
        const Vec3 value(0.2f, 0.4f, 0.6f);
        const LightmappedQuad quad = lightmappedQuad([&](const SurfacePoint&) {  return kPi * DVec3(value); });
        const VertexBake bake = uniformBake(quad.scene, value);
        Diagnostics diagnostics;
        const RgbImage by_vertex = renderBakedView(quad.scene, bake, nullptr, nullptr, &camera, 48, 40, diagnostics);
        const RgbImage by_lightmap =
            renderBakedView(quad.scene, bake, &quad.lightmaps, &quad.meshes, &camera, 48, 40, diagnostics);
        CHECK(diagnostics.warningCount() == 0);
        int lit = 0;
        for (int y = 0; y < 40; ++y)
            for (int x = 0; x < 48; ++x) {
                const Vec3 a = pixel(by_vertex, x, y), b = pixel(by_lightmap, x, y);
                CHECK((a.x > 0) == (b.x > 0));  // same silhouette
                if (a.x == 0) continue;
                ++lit;
                for (int k = 0; k < 3; ++k) {
                    CHECK(a[k] == doctest::Approx(0.5 * value[k]).epsilon(1e-6));
                    CHECK(b[k] == doctest::Approx(0.5 * value[k]).epsilon(1e-5));
                }
            }
        // tan(0.5) x 4 = 2.185 m across 40 pixels: 0.1093 m pixels; the 2 x 1.5 m quad covers ~251.
        CHECK(lit > 200);
        CHECK(lit < 300);
    }
    SUBCASE("ramps in x (red) and y (green): agree within one texel's change") {
        // H / pi = (0.5 + 0.25 x, 0.5 + 0.2 y, 0.5): linear, so the vertex bake's interpolation
        // is exact; the lightmap's bilinear filter is exact between texel centres and, near the
        // quad's edge, off by at most the ramp over one texel (1/16 m): 0.25 / 16 = 0.016. A
        // mirrored u or v would be off by up to 0.5 (x) or 0.3 (y).
        const LightmappedQuad quad = lightmappedQuad(
            [](const SurfacePoint& at) { const DVec3& p = at.p_world;  return kPi * DVec3(0.5 + 0.25 * p.x, 0.5 + 0.2 * p.y, 0.5); });
        VertexBake bake;
        bake.values.emplace_back();
        for (const Vec3& p : quad.scene.meshes[0].positions) bake.values[0].push_back(Vec3(0.5f + 0.25f * p.x, 0.5f + 0.2f * p.y, 0.5f));
        Diagnostics diagnostics;
        const RgbImage by_vertex = renderBakedView(quad.scene, bake, nullptr, nullptr, &camera, 48, 40, diagnostics);
        const RgbImage by_lightmap =
            renderBakedView(quad.scene, bake, &quad.lightmaps, &quad.meshes, &camera, 48, 40, diagnostics);
        double worst = 0.0;
        int lit = 0;
        float red_lo = 1e30f, red_hi = -1e30f;
        for (int y = 0; y < 40; ++y)
            for (int x = 0; x < 48; ++x) {
                const Vec3 a = pixel(by_vertex, x, y), b = pixel(by_lightmap, x, y);
                for (int k = 0; k < 3; ++k) worst = std::max(worst, static_cast<double>(std::abs(a[k] - b[k])));
                if (b.x == 0) continue;
                ++lit;
                red_lo = std::min(red_lo, b.x);
                red_hi = std::max(red_hi, b.x);
            }
        MESSAGE("worst lightmap/vertex difference on the ramp: " << worst);
        CHECK(worst <= 0.5 * 0.016 + 1e-6);  // reflectance 0.5 halves it
        // The bound above means something only if the quad is in view and its ramp shows: the
        // 2 m wide quad's red goes over 0.5 x 0.25 x 2 = 0.25 (less a pixel at each side).
        CHECK(lit > 200);
        CHECK(red_hi - red_lo > 0.2f);
    }
}

TEST_CASE("renderBakedView: the default camera sees the whole scene") {
    // Eight markers of distinct colours at the corners of a 8 x 2 x 2 box.
    Scene scene;
    for (int k = 0; k < 8; ++k) {
        scene.materials.push_back(material(Vec3(0.5f), Vec3(float(k + 1), 0, 0)));
        const Vec3 corner((k & 1) ? 5.0f : -3.0f, (k & 2) ? 2.0f : 0.0f, (k & 4) ? 1.0f : -1.0f);
        scene.meshes.push_back(octahedron(corner, 0.25f, static_cast<uint32_t>(k)));
    }
    const VertexBake bake = uniformBake(scene, Vec3(0.0f));
    Diagnostics diagnostics;
    const RgbImage image = renderBakedView(scene, bake, nullptr, nullptr, nullptr, 80, 60, diagnostics);
    CHECK(diagnostics.errorCount() == 0);
    std::vector<int> seen(8, 0);
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
            const Vec3 p = pixel(image, x, y);
            if (p.x == 0) continue;
            const int k = static_cast<int>(p.x) - 1;
            REQUIRE(k >= 0);
            REQUIRE(k < 8);
            CHECK(p.x == float(k + 1));
            ++seen[k];
            // Nothing touches the image's border: the whole scene is inside.
            CHECK(x > 0);
            CHECK(y > 0);
            CHECK(x < 79);
            CHECK(y < 59);
        }
    for (int k = 0; k < 8; ++k) {
        CAPTURE(k);
        CHECK(seen[k] >= 2);
    }

    // Geometrically: every corner of the bounding box (markers included) projects inside the
    // view's smaller half-angle.
    const Camera camera = defaultPreviewCamera(scene);
    const glm::dmat3 rotation(glm::mat3_cast(camera.orientation));
    const double limit = std::tan(0.5 * camera.field_of_view);
    for (int k = 0; k < 8; ++k) {
        const DVec3 corner((k & 1) ? 5.25 : -3.25, (k & 2) ? 2.25 : -0.25, (k & 4) ? 1.25 : -1.25);
        const DVec3 local = glm::transpose(rotation) * (corner - DVec3(camera.position));
        REQUIRE(local.z < 0.0);  // in front
        CHECK(std::abs(local.x / local.z) < limit);
        CHECK(std::abs(local.y / local.z) < limit);
    }
}

TEST_CASE("renderBakedView does not depend on the thread count") {
    const Scene scene = twoEmitters();
    const VertexBake bake = uniformBake(scene, Vec3(0.3f));
    Diagnostics diagnostics;
    RgbImage one, two;
    {
        ParallelRunner runner(Threading{.threads = 1});
        one = renderBakedView(scene, bake, nullptr, nullptr, nullptr, 50, 37, diagnostics, &runner);
    }
    {
        ParallelRunner runner(Threading{.threads = 2});
        two = renderBakedView(scene, bake, nullptr, nullptr, nullptr, 50, 37, diagnostics, &runner);
    }
    CHECK(one.rgb == two.rgb);
    CHECK(encodePreviewPng(one, autoExposure(one)) == encodePreviewPng(two, autoExposure(two)));
    // Bad sizes are reported, not rendered.
    Diagnostics bad;
    CHECK(renderBakedView(scene, bake, nullptr, nullptr, nullptr, 0, 10, bad).rgb.empty());
    CHECK(bad.errorCount() == 1);
}
