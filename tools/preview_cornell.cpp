// Eyeball check of --preview on a real scene: imports a scene (default: the bundled Cornell
// Box), bakes it through the library at draft quality (vertices and lightmaps), and writes
//   OUT_view_lightmap.png  the view through the lightmaps
//   OUT_view_vertex.png    the same view through the vertex bake, at the same exposure
//   OUT_atlas_<k>.png      each atlas
//   OUT_view_default.png   the default camera (through the lightmaps)
// Usage: preview_cornell OUT_PREFIX [SCENE] [WIDTH HEIGHT [TEXELS_PER_METRE]]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "radbake.h"

using namespace radbake;

namespace {

bool writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return static_cast<bool>(out);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The bundled Cornell Box, found from this file's own (absolute, as CMake compiles it) path.
std::string defaultScene() {
    return (std::filesystem::path(__FILE__).parent_path().parent_path() / "scenes" / "cornell_box.wrl").string();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s OUT_PREFIX [SCENE] [WIDTH HEIGHT [TEXELS_PER_METRE]]\n", argv[0]);
        return 2;
    }
    const std::string prefix = argv[1];
    const std::string scene_path = argc > 2 ? argv[2] : defaultScene();
    const int width = argc > 4 ? std::atoi(argv[3]) : 400;
    const int height = argc > 4 ? std::atoi(argv[4]) : 300;
    // The library's bake at draft quality, with lightmaps; the views below are rendered here.
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    if (argc > 5) options.lightmaps.texels_per_unit = std::atof(argv[5]);

    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic& d) { std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str()); };
    Progress progress(false);
    const Bake result = radbake::bake(scene_path, options, progress, diagnostics);
    if (!result.ok() || !result.lightmaps) return 1;
    const Scene* scene = result.scene.get();
    const VertexBake& bake = result.vertices;
    const Lightmaps& lightmaps = result.lightmaps->lightmaps;
    const std::vector<LightmapMesh>& meshes = result.lightmaps->files.meshes;

    const Camera* camera = scene->cameras.empty() ? nullptr : &scene->cameras.front();
    std::printf("scene %s: %zu meshes, %zu cameras, %zu atlases\n", scene_path.c_str(), scene->meshes.size(),
                scene->cameras.size(), lightmaps.images.size());

    // Charts whose texels are (nearly) black stand out in the atlas picture: name them.
    for (size_t c = 0; c < lightmaps.layout.charts.size(); ++c) {
        const LightmapChart& chart = lightmaps.layout.charts[c];
        if (chart.atlas < 0) continue;
        const LightmapImage& image = lightmaps.images[chart.atlas];
        double sum = 0.0;
        for (int j = 0; j < chart.height; ++j)
            for (int i = 0; i < chart.width; ++i) {
                const size_t t = (static_cast<size_t>(chart.y + j) * image.width + chart.x + i) * 3;
                sum += image.rgb[t] + image.rgb[t + 1] + image.rgb[t + 2];
            }
        const double mean = sum / (3.0 * chart.width * chart.height);
        std::printf("chart %zu: mesh %s, %dx%d texels at (%d, %d), normal (%.2f %.2f %.2f), mean H/pi %.4g\n", c,
                    scene->meshes[chart.mesh].name.c_str(), chart.width, chart.height, chart.x, chart.y,
                    chart.normal_world.x, chart.normal_world.y, chart.normal_world.z, mean);
    }

    // exposure <= 0: the image's own autoExposure. The vertex view reuses the lightmap view's
    // exposure, so the two pictures compare light for light.
    auto render = [&](const char* suffix, const Lightmaps* maps, const std::vector<LightmapMesh>* lm,
                      const Camera* view, double exposure) {
        const auto start = std::chrono::steady_clock::now();
        const RgbImage image = renderBakedView(*scene, bake, maps, lm, view, width, height, diagnostics);
        const double render_seconds = secondsSince(start);
        const double own = autoExposure(image);
        if (!(exposure > 0.0)) exposure = own;
        const std::string png = encodePreviewPng(image, exposure);
        const std::string path = prefix + suffix;
        std::printf("%s: %dx%d, render %.3f s, auto exposure %.4g, used %.4g, %zu bytes\n", path.c_str(), width,
                    height, render_seconds, own, exposure, png.size());
        writeBytes(path, png);
        return exposure;
    };
    const double view_exposure = render("_view_lightmap.png", &lightmaps, &meshes, camera, 0.0);
    render("_view_vertex.png", nullptr, nullptr, camera, view_exposure);
    render("_view_default.png", &lightmaps, &meshes, nullptr, 0.0);
    bool ok = true;
    const double atlas_exposure = lightmaps.images.empty() ? 1.0 : autoExposure(toRgbImage(lightmaps.images.front()));
    for (size_t k = 0; k < lightmaps.images.size(); ++k) {
        const std::string path = prefix + "_atlas_" + std::to_string(k) + ".png";
        const std::string png = encodePreviewPng(toRgbImage(lightmaps.images[k]), atlas_exposure);
        std::printf("%s: %dx%d, %zu bytes\n", path.c_str(), lightmaps.images[k].width, lightmaps.images[k].height,
                    png.size());
        ok = writeBytes(path, png) && ok;
    }
    return ok && !diagnostics.hasErrors() ? 0 : 1;
}
