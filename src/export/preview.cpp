// Preview PNGs: tone mapping, PNG encoding (the only file that includes stb_image_write.h)
// and a ray-cast view of the baked scene.
#include "export/preview.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>


#include "export/output_transaction.h"
#include "visibility/ray_caster.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC  // private copy: no symbol clash with any other stb user
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace radbake {
namespace {

// Rec. 709 / sRGB primaries' luminance weights.
double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// IEC 61966-2-1 transfer, linear [0, 1] -> encoded [0, 1].
double srgbEncode(double linear) {
    if (linear <= 0.0031308) return 12.92 * linear;
    return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

uint8_t toByte(double linear) {
    if (!(linear > 0.0)) return 0;  // negative and NaN
    const double encoded = srgbEncode(std::min(linear, 1.0));
    return static_cast<uint8_t>(std::lround(std::clamp(encoded, 0.0, 1.0) * 255.0));
}

bool consistent(const RgbImage& image) {
    return image.width > 0 && image.height > 0 &&
           image.rgb.size() == static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3;
}

void appendBytes(void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<size_t>(size));
}

// The PNG, or empty with `why` set.
std::string encodePng(const RgbImage& linear, double exposure, std::string& why) {
    if (linear.width <= 0 || linear.height <= 0) {
        why = "the image is empty (" + std::to_string(linear.width) + "x" + std::to_string(linear.height) + ")";
        return {};
    }
    if (!consistent(linear)) {
        why = "the image has " + std::to_string(linear.rgb.size()) + " values for " + std::to_string(linear.width) +
              "x" + std::to_string(linear.height) + " pixels";
        return {};
    }
    if (linear.width > INT_MAX / 3) {  // the encoder's row stride is an int
        why = "the image is too wide for the PNG encoder";
        return {};
    }
    if (!std::isfinite(exposure) || exposure < 0.0) exposure = 1.0;
    try {
        std::vector<uint8_t> bytes(linear.rgb.size());
        for (size_t p = 0; p < linear.rgb.size(); p += 3) {
            double c[3];
            for (int k = 0; k < 3; ++k) {
                const double value = static_cast<double>(linear.rgb[p + k]) * exposure;
                c[k] = std::isfinite(value) ? std::max(value, 0.0) : (value > 0.0 ? 1e30 : 0.0);
            }
            // Reinhard on luminance: L -> L / (1 + L), the same factor on every channel.
            const double scale = 1.0 / (1.0 + luminance(c[0], c[1], c[2]));
            for (int k = 0; k < 3; ++k) bytes[p + k] = toByte(c[k] * scale);
        }
        std::string png;
        if (!stbi_write_png_to_func(appendBytes, &png, linear.width, linear.height, 3, bytes.data(), linear.width * 3) ||
            png.empty()) {
            why = "the PNG encoder failed";
            return {};
        }
        return png;
    } catch (...) {  // allocation failure: no PNG
        why = "out of memory";
        return {};
    }
}

}  // namespace

std::string encodeRgba8Png(int width, int height, const std::vector<uint8_t>& rgba) {
    if (width <= 0 || height <= 0 || width > INT_MAX / 4 ||
        rgba.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * 4)
        return {};
    try {
        std::string png;
        if (!stbi_write_png_to_func(appendBytes, &png, width, height, 4, rgba.data(), width * 4)) return {};
        return png;
    } catch (...) {  // allocation failure: no PNG
        return {};
    }
}

std::string zlibCompress(const std::string& bytes) {
    if (bytes.size() > static_cast<size_t>(INT_MAX)) return {};
    int length = 0;
    unsigned char* packed = stbi_zlib_compress(reinterpret_cast<unsigned char*>(const_cast<char*>(bytes.data())),
                                               static_cast<int>(bytes.size()), &length, 8);
    if (!packed) return {};
    std::string out;
    try {
        out.assign(reinterpret_cast<const char*>(packed), static_cast<size_t>(length));
    } catch (...) {  // allocation failure: nothing
        out.clear();
    }
    STBIW_FREE(packed);
    return out;
}

std::string encodePreviewPng(const RgbImage& linear, double exposure) {
    std::string why;
    return encodePng(linear, exposure, why);
}

bool writePreviewPng(const std::filesystem::path& path, const RgbImage& linear, double exposure,
                     Diagnostics& diagnostics) {
    std::string why;
    const std::string png = encodePng(linear, exposure, why);
    if (png.empty()) {
        diagnostics.error({path.string(), 0, 0}, "cannot encode the preview PNG: " + why);
        return false;
    }
    return writeFileBytes(path, png, diagnostics);
}

RgbImage toRgbImage(const LightmapImage& image) {
    RgbImage out;
    out.width = image.width;
    out.height = image.height;
    out.rgb = image.rgb;
    return out;
}

double autoExposure(const RgbImage& linear) {
    if (!consistent(linear)) return 1.0;
    // Serial, in pixel order: the same sum, bit for bit, every time.
    double log_sum = 0.0;
    size_t count = 0;
    for (size_t p = 0; p < linear.rgb.size(); p += 3) {
        const double l = luminance(linear.rgb[p], linear.rgb[p + 1], linear.rgb[p + 2]);
        if (!(l > 0.0) || !std::isfinite(l)) continue;
        log_sum += std::log(l);
        ++count;
    }
    if (count == 0) return 1.0;
    const double key = std::exp(log_sum / static_cast<double>(count));
    return key > 0.0 && std::isfinite(key) ? kPreviewKey / key : 1.0;
}

Camera defaultPreviewCamera(const Scene& scene) {
    Aabb bounds;
    for (const Mesh& mesh : scene.meshes)
        for (const UVec3& t : mesh.triangles)
            for (int k = 0; k < 3; ++k)
                if (t[k] < mesh.positions.size() && isFinite(mesh.positions[t[k]])) bounds.add(DVec3(mesh.positions[t[k]]));
    Camera camera;
    camera.name = "radbake default";
    camera.field_of_view = static_cast<float>(kPi / 4.0);
    const DVec3 centre = bounds.empty() ? DVec3(0.0) : bounds.center();
    double radius = bounds.empty() ? 0.0 : 0.5 * glm::length(bounds.extent());
    if (!(radius > 0.0)) radius = 1.0;  // empty or point-sized scene: any framing will do
    // The bounding sphere fits the smaller view angle, so it fits both.
    const double distance = radius / std::sin(0.5 * static_cast<double>(camera.field_of_view));
    const DVec3 backward = glm::normalize(DVec3(1.0, 1.0, 2.0));  // camera +Z, away from the scene
    const DVec3 right = glm::normalize(glm::cross(DVec3(0.0, 1.0, 0.0), backward));
    const DVec3 up = glm::cross(backward, right);
    camera.position = Vec3(centre + distance * backward);
    camera.orientation = glm::normalize(glm::quat_cast(Mat3(Vec3(right), Vec3(up), Vec3(backward))));
    return camera;
}

namespace {

// Pixel (x, y) -> world ray. Pixels are square; the smaller image side spans field_of_view.
struct ViewRays {
    DVec3 position;
    DVec3 right, up, backward;  // camera axes in world space
    double pixel_size = 0.0;     // tangent of the angle of one pixel at the centre
    double half_width = 0.0, half_height = 0.0;

    ViewRays(const Camera& camera, int width, int height) {
        position = DVec3(camera.position);
        const glm::dmat3 rotation(glm::mat3_cast(glm::normalize(camera.orientation)));
        right = glm::normalize(rotation[0]);
        up = glm::normalize(rotation[1]);
        backward = glm::normalize(rotation[2]);
        const double fov = std::clamp(static_cast<double>(camera.field_of_view), 1e-4, kPi - 1e-4);
        pixel_size = std::tan(0.5 * fov) / (0.5 * std::min(width, height));
        half_width = 0.5 * width;
        half_height = 0.5 * height;
    }
    DVec3 direction(int x, int y) const {
        const double cx = (x + 0.5 - half_width) * pixel_size;
        const double cy = (half_height - (y + 0.5)) * pixel_size;  // row 0 at the top
        return cx * right + cy * up - backward;
    }
};

// Bilinear sample of an atlas at (u right, v down from the top row), clamped at the border.
DVec3 sampleBilinear(const LightmapImage& image, const DVec2& uv) {
    const double x = uv.x * image.width - 0.5, y = uv.y * image.height - 0.5;
    const double x0f = std::floor(x), y0f = std::floor(y);
    const double fx = x - x0f, fy = y - y0f;
    auto texel = [&](double xi, double yi) {
        const int cx = static_cast<int>(std::clamp(xi, 0.0, image.width - 1.0));
        const int cy = static_cast<int>(std::clamp(yi, 0.0, image.height - 1.0));
        const size_t i = (static_cast<size_t>(cy) * image.width + cx) * 3;
        return DVec3(image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]);
    };
    return (1 - fx) * (1 - fy) * texel(x0f, y0f) + fx * (1 - fy) * texel(x0f + 1, y0f) +
           (1 - fx) * fy * texel(x0f, y0f + 1) + fx * fy * texel(x0f + 1, y0f + 1);
}

// What one render needs: the traced geometry (the scene, or the lightmap meshes in their
// place) and where each traced mesh takes its baked value from.
struct Setup {
    Scene traced;                    // meshes index-aligned with the source scene
    std::vector<uint8_t> from_lightmap;  // per mesh: the traced mesh is lightmap mesh m
    bool vertex_bake_ok = true;      // bake.values matches the scene's meshes
};

bool lightmapsUsable(const Scene& scene, const Lightmaps* lightmaps, const std::vector<LightmapMesh>* meshes) {
    if (!lightmaps || !meshes || meshes->size() != scene.meshes.size()) return false;
    for (const LightmapImage& image : lightmaps->images)
        if (image.width <= 0 || image.height <= 0 ||
            image.rgb.size() != static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3)
            return false;
    return true;
}

Setup makeSetup(const Scene& scene, const VertexBake& bake, bool use_lightmaps,
                const std::vector<LightmapMesh>* lightmap_meshes) {
    Setup setup;
    setup.traced.name = scene.name;
    setup.traced.source_path = scene.source_path;
    setup.from_lightmap.assign(scene.meshes.size(), 0);
    setup.vertex_bake_ok = bake.values.size() == scene.meshes.size();
    for (size_t m = 0; m < scene.meshes.size() && setup.vertex_bake_ok; ++m)
        setup.vertex_bake_ok = bake.values[m].size() == scene.meshes[m].positions.size();
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        Mesh traced;
        traced.name = scene.meshes[m].name;
        traced.material = scene.meshes[m].material;
        const LightmapMesh* lm = use_lightmaps ? &(*lightmap_meshes)[m] : nullptr;
        const bool lightmapped = lm && !lm->triangles.empty() && lm->uv.size() == lm->positions.size() &&
                                 lm->atlas.size() == lm->positions.size();
        if (lightmapped) {
            traced.positions = lm->positions;
            traced.triangles = lm->triangles;
        } else {  // no charts (or no lightmaps): the source mesh, lit by the vertex bake
            traced.positions = scene.meshes[m].positions;
            traced.triangles = scene.meshes[m].triangles;
        }
        setup.from_lightmap[m] = lightmapped ? 1 : 0;
        setup.traced.meshes.push_back(std::move(traced));
    }
    return setup;
}

struct Shader {
    const Scene& scene;
    const VertexBake& bake;
    const Lightmaps* lightmaps;
    const std::vector<LightmapMesh>* lightmap_meshes;
    const Setup& setup;

    DVec3 vertexValue(uint32_t m, uint32_t v) const {
        if (!setup.vertex_bake_ok) return DVec3(0.0);
        return DVec3(bake.values[m][v]);
    }

    // H / pi at the hit: lightmap (bilinear at the interpolated TEXCOORD_1) or vertex bake.
    DVec3 baked(const RayHit& hit) const {
        const uint32_t m = hit.triangle.mesh;
        const UVec3 tri = setup.traced.meshes[m].triangles[hit.triangle.triangle];
        const double w[3] = {1.0 - hit.u - hit.v, hit.u, hit.v};
        if (!setup.from_lightmap[m]) {
            DVec3 sum(0.0);
            for (int k = 0; k < 3; ++k) sum += w[k] * vertexValue(m, tri[k]);
            return sum;
        }
        const LightmapMesh& lm = (*lightmap_meshes)[m];
        const int atlas = lm.atlas[tri.x];
        if (atlas >= 0 && static_cast<size_t>(atlas) < lightmaps->images.size()) {
            DVec2 uv(0.0);
            for (int k = 0; k < 3; ++k) uv += w[k] * DVec2(lm.uv[tri[k]]);
            return sampleBilinear(lightmaps->images[atlas], uv);
        }
        // An unplaced chart: carry the vertex bake over to the lightmap mesh's corners.
        DVec3 sum(0.0);
        if (setup.vertex_bake_ok)
            for (int k = 0; k < 3; ++k) sum += w[k] * DVec3(interpolateSource(lm, tri[k], bake.values[m]));
        return sum;
    }

    // reflectance * baked + emission; back faces show the front's radiance.
    DVec3 radiance(const RayHit& hit) const {
        const Mesh& source = scene.meshes[hit.triangle.mesh];
        if (source.material >= scene.materials.size()) return baked(hit);
        // The source polygon's own colours (a texture may set them per polygon).
        const uint32_t m = hit.triangle.mesh;
        const uint32_t t = setup.from_lightmap[m] ? (*lightmap_meshes)[m].source_triangle[hit.triangle.triangle]
                                                  : hit.triangle.triangle;
        const uint32_t polygon = t < source.triangle_polygon.size() ? source.triangle_polygon[t] : 0;
        return DVec3(polygonReflectance(scene, source, polygon)) * baked(hit) +
               DVec3(polygonEmission(scene, source, polygon));
    }
};

// Fewer than this many pixels a side, or more than this many in all, is a caller's mistake.
constexpr long long kMaxPixels = 1LL << 28;

}  // namespace

RgbImage renderBakedView(const Scene& scene, const VertexBake& bake, const Lightmaps* lightmaps,
                         const std::vector<LightmapMesh>* lightmap_meshes, const Camera* camera, int width,
                         int height, Diagnostics& diagnostics, ParallelRunner* runner) {
    const SourceLocation where{scene.source_path, 0, 0};
    std::unique_ptr<ParallelRunner> own_runner;
    if (!runner) runner = (own_runner = std::make_unique<ParallelRunner>(Threading{})).get();
    RgbImage image;
    if (width <= 0 || height <= 0 || static_cast<long long>(width) * height > kMaxPixels) {
        diagnostics.error(where, "preview: bad image size " + std::to_string(width) + " x " + std::to_string(height));
        return image;
    }
    try {
        image.width = width;
        image.height = height;
        image.rgb.assign(static_cast<size_t>(width) * height * 3, 0.0f);

        const bool use_lightmaps = lightmapsUsable(scene, lightmaps, lightmap_meshes);
        if ((lightmaps || lightmap_meshes) && !use_lightmaps)
            diagnostics.warning(where, "preview: the lightmaps do not match the scene; showing the vertex bake");
        const Setup setup = makeSetup(scene, bake, use_lightmaps, lightmap_meshes);
        if (!setup.vertex_bake_ok)
            diagnostics.warning(where, "preview: the vertex bake does not match the scene; showing emission only");

        // The scene's own caster already warned about unusable triangles; only errors matter here.
        Diagnostics build_diagnostics;
        const std::unique_ptr<RayCaster> caster = RayCaster::build(setup.traced, build_diagnostics, runner->threads());
        for (const Diagnostic& d : build_diagnostics.all())
            if (d.severity == Severity::Error) diagnostics.error(d.location, "preview: " + d.message);
        if (!caster) return image;

        const Camera view_camera = camera ? *camera : defaultPreviewCamera(scene);
        const ViewRays rays(view_camera, width, height);
        const Shader shader{scene, bake, use_lightmaps ? lightmaps : nullptr, lightmap_meshes, setup};
        const double t_max = std::numeric_limits<double>::infinity();
        // Each pixel writes its own slot: the image does not depend on the thread count.
        runner->forRanges(static_cast<size_t>(height), 1, [&](size_t row_begin, size_t row_end) {
            for (int y = static_cast<int>(row_begin); y < static_cast<int>(row_end); ++y)
                for (int x = 0; x < width; ++x) {
                    const std::optional<RayHit> hit = caster->closestHit(rays.position, rays.direction(x, y), t_max);
                    if (!hit) continue;
                    const DVec3 value = shader.radiance(*hit);
                    float* out = &image.rgb[(static_cast<size_t>(y) * width + x) * 3];
                    for (int k = 0; k < 3; ++k) out[k] = static_cast<float>(value[k]);
                }
        });
        caster->reportLateErrors(diagnostics);
    } catch (const std::exception& e) {
        diagnostics.error(where, std::string("preview: ") + e.what());
    } catch (...) {
        diagnostics.error(where, "preview: unknown failure while rendering");
    }
    return image;
}

}  // namespace radbake
