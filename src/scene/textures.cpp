#include "scene/textures.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "core/read_policy.h"
#include "core/regular_file.h"
#include "scene/texture_image.h"

namespace radbake {
namespace {

// Alpha below this is a cutout (glTF's default alphaCutoff).
constexpr float kAlphaCutoff = 0.5f;
// A UV triangle is sampled at the centroids of an N x N subdivision: about two samples per
// texel it covers, between these bounds (a tiny triangle still averages over a few points,
// a huge one costs at most 1024 lookups).
constexpr int kMinGrid = 4;
constexpr int kMaxGrid = 32;

struct PolygonAverage {
    DVec3 colour{0.0};  // linear, area-weighted mean
    bool cutout = false;
};

struct ImageMean {
    Vec3 colour{0.0f};
    bool cutout = false;
};

ImageMean wholeImageMean(const TextureImage& image) {
    DVec3 sum(0.0);
    ImageMean mean;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const Vec4 t = image.texel(x, y);
            sum += DVec3(Vec3(t));
            mean.cutout = mean.cutout || t.w < kAlphaCutoff;
        }
    const double count = static_cast<double>(image.width) * static_cast<double>(image.height);
    mean.colour = count > 0.0 ? Vec3(sum / count) : Vec3(1.0f);
    return mean;
}

bool usableUv(const Mesh& mesh, const UVec3& t) {
    if (mesh.uv0.size() != mesh.positions.size()) return false;
    for (int k = 0; k < 3; ++k) {
        if (t[k] >= mesh.uv0.size()) return false;
        const Vec2& uv = mesh.uv0[t[k]];
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return false;
    }
    return true;
}

// Mean of the texture over one UV triangle (v up: v = 0 is the image's bottom row).
DVec3 uvTriangleMean(const TextureImage& image, const Vec2& a, const Vec2& b, const Vec2& c, bool& cutout) {
    const DVec2 pa(a), ab = DVec2(b) - pa, ac = DVec2(c) - pa;
    const double w = image.width, h = image.height;
    const double texel_area = 0.5 * std::abs(ab.x * ac.y - ab.y * ac.x) * w * h;
    const double grid_limit = std::min(std::ceil(std::sqrt(2.0 * texel_area)), static_cast<double>(kMaxGrid));
    const int n = std::max(kMinGrid, static_cast<int>(grid_limit));
    DVec3 sum(0.0);
    size_t count = 0;
    auto sample = [&](double s, double t) {
        const DVec2 uv = pa + (s / n) * ab + (t / n) * ac;
        const Vec4 texel = image.texel(static_cast<int64_t>(std::floor(uv.x * w)),
                                       static_cast<int64_t>(std::floor((1.0 - uv.y) * h)));
        sum += DVec3(Vec3(texel));
        cutout = cutout || texel.w < kAlphaCutoff;
        ++count;
    };
    for (int i = 0; i < n; ++i)
        for (int j = 0; i + j < n; ++j) {
            sample(i + 1.0 / 3.0, j + 1.0 / 3.0);                     // upright sub-triangle
            if (i + j + 1 < n) sample(i + 2.0 / 3.0, j + 2.0 / 3.0);  // inverted one beside it
        }
    return sum / static_cast<double>(count);
}

std::vector<PolygonAverage> polygonAverages(const Mesh& mesh, const TextureImage& image, const ImageMean& whole) {
    std::vector<PolygonAverage> averages(mesh.polygon_count);
    std::vector<double> areas(mesh.polygon_count, 0.0);
    for (size_t t = 0; t < mesh.triangles.size() && t < mesh.triangle_polygon.size(); ++t) {
        const uint32_t p = mesh.triangle_polygon[t];
        const UVec3& tri = mesh.triangles[t];
        if (p >= mesh.polygon_count || tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() ||
            tri.z >= mesh.positions.size())
            continue;  // validation reports these
        double area = triangleArea(mesh, t);
        if (!(area > 0.0) || !std::isfinite(area)) area = 0.0;
        PolygonAverage& average = averages[p];
        if (usableUv(mesh, tri)) {
            average.colour += area * uvTriangleMean(image, mesh.uv0[tri.x], mesh.uv0[tri.y], mesh.uv0[tri.z], average.cutout);
        } else {
            average.colour += area * DVec3(whole.colour);
            average.cutout = average.cutout || whole.cutout;
        }
        areas[p] += area;
    }
    for (uint32_t p = 0; p < mesh.polygon_count; ++p)
        averages[p].colour = areas[p] > 0.0 ? averages[p].colour / areas[p] : DVec3(whole.colour);
    return averages;
}

enum class Role { BaseColour, Emissive };

// Sets the per-polygon values of every mesh whose material has `path` in `role`.
void applyImage(Scene& scene, const std::string& path, Role role, const TextureImage& image,
                Diagnostics& diagnostics) {
    const ImageMean whole = wholeImageMean(image);
    for (size_t m = 0; m < scene.materials.size(); ++m) {
        const Material& material = scene.materials[m];
        const TextureRef& ref = role == Role::BaseColour ? material.base_color_texture : material.emissive_texture;
        if (ref.path != path) continue;
        // VRML97: an RGB texture replaces diffuseColor, an intensity one modulates it.
        const bool replaces = role == Role::BaseColour && ref.rgb_replaces && image.channels >= 3;
        const Vec3 factor = replaces ? Vec3(1.0f) : role == Role::BaseColour ? material.reflectance : material.emission;
        size_t cutout_polygons = 0;
        for (Mesh& mesh : scene.meshes) {
            if (mesh.material != m) continue;
            const std::vector<PolygonAverage> averages = polygonAverages(mesh, image, whole);
            std::vector<Vec3>& out = role == Role::BaseColour ? mesh.polygon_reflectance : mesh.polygon_emission;
            out.resize(mesh.polygon_count);
            for (uint32_t p = 0; p < mesh.polygon_count; ++p) {
                out[p] = factor * Vec3(averages[p].colour);
                if (averages[p].cutout) ++cutout_polygons;
            }
        }
        if (role == Role::BaseColour && cutout_polygons > 0)
            diagnostics.warning(ref.location, "material '" + material.name + "': " + std::to_string(cutout_polygons) +
                                                  " polygon(s) cover alpha below 0.5 in texture '" + path +
                                                  "'; alpha cutouts are baked as opaque");
    }
}

void noteInput(Scene& scene, const std::string& path) {
    const std::string normal = std::filesystem::path(path).lexically_normal().string();
    if (std::find(scene.input_files.begin(), scene.input_files.end(), normal) == scene.input_files.end())
        scene.input_files.push_back(normal);
}

// Every texture file the read policy refuses: one warning naming it, noted refused, and
// dropped from every material that names it, so it is neither read nor embedded in the glb.
// One in the read roots (a FIFO, a directory) stays an input: replacing it with an image rebuilds.
void refuseTextures(Scene& scene, const ReadPolicy& policy, Diagnostics& diagnostics) {
    std::map<std::string, bool> checked;  // path -> refused
    for (Material& material : scene.materials) {
        for (TextureRef* ref : {&material.base_color_texture, &material.emissive_texture, &material.normal_texture}) {
            if (ref->empty() || ref->embedded) continue;
            auto [it, first] = checked.try_emplace(ref->path, false);
            if (first) {
                const std::string why = policy.whyRefused(ref->path);
                if (why.empty()) continue;
                it->second = true;
                const bool colour = ref != &material.normal_texture;
                diagnostics.warning(ref->location, "cannot read texture '" + ref->path + "' (" + why + "); " +
                                                       (colour ? "the material's own colour is used" : "not written"));
                if (policy.whyOutside(ref->path).empty()) noteInput(scene, ref->path);
                scene.refused_inputs.push_back(ref->path);
            }
            if (it->second) *ref = TextureRef{};
        }
    }
}

// Removes every use of the texture at `path`: it is never decoded or embedded.
void dropTexture(Scene& scene, const std::string& path) {
    for (Material& material : scene.materials)
        for (TextureRef* ref : {&material.base_color_texture, &material.emissive_texture, &material.normal_texture})
            if (ref->path == path) *ref = TextureRef{};
}

}  // namespace

void applyTextures(Scene& scene, const ReadPolicy& policy, double max_memory_mb, Diagnostics& diagnostics) {
    refuseTextures(scene, policy, diagnostics);
    // Every texture once, in the order materials name them.
    std::vector<std::pair<std::string, Role>> images;
    std::map<std::string, TextureRef> first_named;
    for (const Material& material : scene.materials) {
        for (const TextureRef* ref : {&material.base_color_texture, &material.emissive_texture, &material.normal_texture}) {
            if (ref->empty()) continue;
            if (!ref->embedded) noteInput(scene, ref->path);  // an embedded one is in the model file
            first_named.try_emplace(ref->path, *ref);
        }
        if (!material.base_color_texture.empty()) images.emplace_back(material.base_color_texture.path, Role::BaseColour);
        if (!material.emissive_texture.empty()) images.emplace_back(material.emissive_texture.path, Role::Emissive);
    }
    std::sort(images.begin(), images.end());
    images.erase(std::unique(images.begin(), images.end()), images.end());

    std::set<std::string> failed;  // one warning per file, whatever its roles
    for (const auto& [path, role] : images) {
        if (failed.count(path)) continue;
        std::string error;
        const TextureRef& ref = first_named[path];
        bool too_large = false;
        const std::optional<TextureImage> image = readTextureImage(ref, true, error, max_memory_mb, &too_large, &policy);
        if (!image) {
            // A missing file, a FIFO or a directory alike: warned, and the bake goes on.
            diagnostics.warning(ref.location,
                                "cannot read texture '" + path + "' (" + error + "); the material's own colour is used");
            failed.insert(path);
            if (too_large) dropTexture(scene, path);
            continue;
        }
        applyImage(scene, path, role, *image, diagnostics);
    }
    // Normal maps are only passed through to the glb: say now when one is missing.
    for (const Material& material : scene.materials) {
        const std::string& path = material.normal_texture.path;
        if (path.empty() || material.normal_texture.embedded || failed.count(path)) continue;
        const std::string why = whyNotRegularFile(path);
        if (why.empty()) continue;
        diagnostics.warning(material.normal_texture.location, "cannot read normal map '" + path + "' (" + why + "); not written");
        failed.insert(path);
    }
}

}  // namespace radbake
