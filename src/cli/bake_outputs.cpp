// Lightmap, preview and manifest outputs of `radbake bake`.
#include "cli/bake_outputs.h"

#include <cmath>
#include <cstdio>

#include "export/exr_io.h"
#include "export/preview.h"

namespace radbake::cli {
namespace {

constexpr int kPreviewWidth = 800;
constexpr int kPreviewHeight = 600;

RgbImage toRgbImage(const LightmapImage& image) {
    RgbImage out;
    out.width = image.width;
    out.height = image.height;
    out.rgb = image.rgb;
    return out;
}

std::string formatNumber(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g", value);
    return buffer;
}

}  // namespace

double texelToleranceFor(Quality quality) {
    switch (quality) {
        case Quality::Draft: return 0.05;
        case Quality::Medium: return 0.02;
        case Quality::High: return 0.01;
        case Quality::Reference: return 0.0;
    }
    return 0.0;
}

size_t chartTexels(const Scene& scene, const LightmapOptions& options) {
    size_t texels = 0;
    for (const LightmapChart& chart : buildLightmapCharts(scene, options))
        texels += static_cast<size_t>(chart.width) * static_cast<size_t>(chart.height);
    return texels;
}

bool chooseTexelDensity(const Scene& scene, LightmapArgs& args, float unit_scale, Diagnostics& diagnostics) {
    const double per_unit = static_cast<double>(unit_scale);
    LightmapOptions options;
    options.atlas_size = args.atlas_size;
    options.padding = args.padding;
    // The imported scene is in metres; the option counts texels per scene unit.
    options.texel_density = args.texel_density > 0.0 ? args.texel_density / per_unit : kDefaultTexelsPerMetre;
    const size_t wanted = chartTexels(scene, options);
    size_t texels = wanted;
    if (texels > args.max_texels && args.texel_density > 0.0) {
        const double fits = args.texel_density * std::sqrt(static_cast<double>(args.max_texels) / texels);
        diagnostics.error({scene.source_path, 0, 0},
                          "lightmaps at --texel-density " + formatNumber(args.texel_density) + " need " +
                              std::to_string(texels) + " texels, above --max-texels " +
                              std::to_string(args.max_texels) + ": give a density of about " + formatNumber(fits) +
                              " or less, or raise --max-texels");
        return false;
    }
    // Texels grow with the square of the density; the minimum chart size keeps tiny charts
    // from shrinking, so step down until the charts fit (or the density cannot help).
    for (int step = 0; texels > args.max_texels && step < 8; ++step) {
        options.texel_density *= 0.97 * std::sqrt(static_cast<double>(args.max_texels) / texels);
        texels = chartTexels(scene, options);
    }
    if (texels > args.max_texels) {
        diagnostics.error({scene.source_path, 0, 0},
                          "lightmaps need " + std::to_string(texels) + " texels even at " +
                              formatNumber(options.texel_density * per_unit) +
                              " texels per unit, above --max-texels " + std::to_string(args.max_texels) +
                              " (too many small charts): raise --max-texels or bake with --no-lightmaps");
        return false;
    }
    if (texels != wanted)
        diagnostics.warning({scene.source_path, 0, 0},
                            "lightmaps at the default " + formatNumber(kDefaultTexelsPerMetre) +
                                " texels per metre would need " + std::to_string(wanted) +
                                " texels, above --max-texels " + std::to_string(args.max_texels) + ": baked at " +
                                formatNumber(options.texel_density * per_unit) +
                                " texels per unit instead (" + std::to_string(texels) +
                                " texels); --texel-density or --max-texels choose otherwise");
    args.texels_per_metre = options.texel_density;
    return true;
}

bool bakeSceneLightmaps(const Scene& scene, const Solution& solution, const LightmapArgs& args, float unit_scale,
                        BakedLightmaps& baked, LightmapReport& report, Diagnostics& diagnostics) {
    LightmapOptions options;
    options.texel_density = args.texels_per_metre;
    options.atlas_size = args.atlas_size;
    options.padding = args.padding;
    options.texel_tolerance = args.texel_tolerance;
    if (!bakeLightmaps(scene, solution, options, baked.lightmaps, diagnostics)) return false;
    const LightmapLayout& layout = baked.lightmaps.layout;
    baked.files.meshes = lightmapMeshes(scene, layout);
    baked.files.atlas_files.clear();
    for (size_t k = 0; k < layout.atlases.size(); ++k)
        baked.files.atlas_files.push_back("lightmaps/" + scene.name + "_" + std::to_string(k) + ".exr");

    report.baked = true;
    report.texels_per_unit = options.texel_density * static_cast<double>(unit_scale);
    report.atlas_size = args.atlas_size;
    report.padding = args.padding;
    report.charts = layout.charts.size();
    report.atlases = layout.atlases.size();
    report.atlas_texels = 0;
    for (const LightmapAtlas& atlas : layout.atlases)
        report.atlas_texels += static_cast<size_t>(atlas.width) * static_cast<size_t>(atlas.height);
    report.covered_texels = baked.lightmaps.covered_texels;
    report.interpolated_texels = baked.lightmaps.interpolated_texels;
    report.texel_tolerance = options.texel_tolerance;
    report.occupancy = layout.occupancy;
    return true;
}

bool stageLightmapExrs(OutputTransaction& transaction, const BakedLightmaps& baked,
                       const std::vector<std::pair<std::string, std::string>>& provenance, bool exr_float,
                       Diagnostics& diagnostics) {
    const std::vector<LightmapImage>& images = baked.lightmaps.images;
    for (size_t k = 0; k < images.size(); ++k) {
        RgbImage image = toRgbImage(images[k]);
        image.attributes = provenance;
        image.attributes.emplace_back("radbake:atlas", std::to_string(k) + " of " + std::to_string(images.size()));
        image.attributes.emplace_back("radbake:quantity", "H/pi: irradiance over pi, W m^-2 sr^-1, linear");
        if (!writeExr(transaction.stage(baked.files.atlas_files[k]), image, ExrWriteOptions{exr_float}, diagnostics))
            return false;
    }
    return true;
}

bool stagePreviews(OutputTransaction& transaction, const Scene& scene, const VertexBake& bake,
                   const BakedLightmaps* baked, Diagnostics& diagnostics) {
    const Camera* camera = scene.cameras.empty() ? nullptr : &scene.cameras.front();
    const RgbImage view = renderBakedView(scene, bake, baked ? &baked->lightmaps : nullptr,
                                          baked ? &baked->files.meshes : nullptr, camera, kPreviewWidth,
                                          kPreviewHeight, diagnostics);
    if (diagnostics.hasErrors()) return false;
    if (!writePreviewPng(transaction.stage("preview/" + scene.name + "_view.png"), view, autoExposure(view), diagnostics))
        return false;
    if (!baked) return true;
    // One exposure for every atlas (the first, fullest one's), so their brightness compares.
    const std::vector<LightmapImage>& images = baked->lightmaps.images;
    const double exposure = images.empty() ? 1.0 : autoExposure(toRgbImage(images.front()));
    for (size_t k = 0; k < images.size(); ++k) {
        if (!writePreviewPng(transaction.stage("preview/" + scene.name + "_atlas_" + std::to_string(k) + ".png"),
                             toRgbImage(images[k]), exposure, diagnostics))
            return false;
    }
    return true;
}

}  // namespace radbake::cli
