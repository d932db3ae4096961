// writeBake: every output of a bake staged into one OutputTransaction, committed only when
// all of them were written.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "core/memory.h"
#include "core/exr_io.h"
#include "export/gltf_writer.h"
#include "export/lightmap_png.h"
#include "export/manifest.h"
#include "export/output_transaction.h"
#include "export/ply_writer.h"
#include "export/probes.h"
#include "export/stats_json.h"
#include "pipeline/bake.h"

namespace radbake {
namespace {

// What an EXR header records of the bake: enough to tell which scene and settings made it.
// Nothing here depends on the thread count or the clock, so outputs stay byte-identical.
std::vector<std::pair<std::string, std::string>> provenance(const Bake& bake) {
    const BakeOptions& o = bake.options;
    const SolverOptions& solver = o.solver;
    char knobs[512];
    std::snprintf(knobs, sizeof knobs,
                  "quality=%s visibility=%s error_threshold=%g local_error_threshold=%g min_area=%g tolerance=%g "
                  "max_iterations=%d unit_scale=%g emission_scale=%g texel_density=%g atlas_size=%d padding=%d "
                  "texel_tolerance=%g",
                  toString(solver.quality), toString(solver.visibility), solver.error_threshold,
                  solver.local_error_threshold, solver.min_element_area, solver.iteration_tolerance,
                  solver.max_iterations, static_cast<double>(o.import.unit_scale),
                  static_cast<double>(o.import.emission_scale), o.lightmaps.texels_per_unit, o.lightmaps.atlas_size,
                  o.lightmaps.padding, o.lightmaps.texel_tolerance);
    std::vector<std::pair<std::string, std::string>> attributes = {
            {"radbake:version", radbakeGenerator()},
            {"radbake:scene", std::filesystem::path(bake.scene->source_path).filename().string()},
            {"radbake:scene_sha256", bake.scene_sha256},
            {"radbake:inputs_sha256", bake.inputs_sha256},
            {"radbake:inputs", std::to_string(bake.scene ? bake.scene->input_files.size() : 0)},
            {"radbake:options", knobs}};
    // Daylight changes every value; recorded only when given, so other EXRs keep their bytes.
    const DaylightOptions& daylight = o.import.daylight;
    if (daylight.any()) {
        char sky[256];
        std::snprintf(sky, sizeof sky, " sky_radiance=%g up=%s", daylight.sky_radiance, upAxisName(daylight.up).c_str());
        // A map by its file name; its bytes are among the inputs radbake:inputs_sha256 hashes.
        std::string text = std::string("sky=") +
                           (daylight.sky == SkyModel::Map ? std::filesystem::path(daylight.sky_map).filename().string()
                                                          : skyModelName(daylight.sky)) +
                           sky;
        if (daylight.sun) {
            char sun[192];
            std::snprintf(sun, sizeof sun, " sun=%g,%g sun_irradiance=%g sun_diameter=%g",
                          daylight.sun->azimuth_degrees, daylight.sun->elevation_degrees, daylight.sun_irradiance,
                          daylight.sun_diameter_degrees);
            text += sun;
        }
        attributes.emplace_back("radbake:daylight", text);
    }
    // --lightmap-scales changes the charts, so it belongs to what made the atlas.
    if (!o.lightmaps.scales.empty()) {
        std::string scales;
        for (const LightmapScaleRule& rule : o.lightmaps.scales) {
            char scale[32];
            std::snprintf(scale, sizeof scale, "%g", rule.scale);
            scales += (scales.empty() ? "" : "; ") + rule.name + " = " + scale;
        }
        attributes.emplace_back("radbake:lightmap_scales", scales);
    }
    return attributes;
}

// One EXR per atlas as lightmaps/<name>_<k>.exr, each with the provenance and its atlas number.
bool stageLightmapExrs(OutputTransaction& transaction, const Bake& bake, Diagnostics& diagnostics) {
    const BakedLightmaps& baked = *bake.lightmaps;
    const std::vector<LightmapImage>& images = baked.lightmaps.images;
    const auto attributes = provenance(bake);
    for (size_t k = 0; k < images.size(); ++k) {
        RgbImage image = toRgbImage(images[k]);
        image.attributes = attributes;
        image.attributes.emplace_back("radbake:atlas", std::to_string(k) + " of " + std::to_string(images.size()));
        image.attributes.emplace_back("radbake:quantity",
                                      baked.files.quantity == LightmapQuantity::Radiance
                                          ? "rho H/pi: reflected radiance, reflectance times irradiance over pi, W m^-2 sr^-1, linear"
                                          : "H/pi: irradiance over pi, W m^-2 sr^-1, linear");
        if (!writeExr(transaction.stage(baked.files.atlas_files[k]), image,
                      ExrWriteOptions{bake.options.lightmaps.exr_float}, diagnostics))
            return false;
    }
    const LightmapDirections& directions = baked.directions;
    for (size_t k = 0; k < directions.images.size(); ++k) {
        RgbImage image;
        image.width = directions.widths[k];
        image.height = directions.heights[k];
        image.rgb = directions.images[k];
        image.attributes = attributes;
        image.attributes.emplace_back("radbake:atlas", std::to_string(k) + " of " + std::to_string(directions.images.size()));
        image.attributes.emplace_back("radbake:quantity",
                                      "g (x y z, world): the lightmap's irradiance at normal n is lightmap * max(0, 1 + "
                                      "g . (n - n0)), n0 the surface normal (a linear fit to reads at n0 and 30 degree tilts)");
        if (!writeExr(transaction.stage(baked.files.direction_files[k]), image, ExrWriteOptions{true}, diagnostics))
            return false;
    }
    return true;
}

// Each atlas as a PNG an engine reads (lightmap_png.h), to be written beside its EXR as
// lightmaps/<name>_<k>.png and embedded in the glb. False after reporting.
bool encodeLightmapPngs(const Bake& bake, std::vector<LightmapPng>& pngs, Diagnostics& diagnostics) {
    const BakedLightmaps& baked = *bake.lightmaps;
    for (size_t k = 0; k < baked.lightmaps.images.size(); ++k) {
        const RgbImage image = toRgbImage(baked.lightmaps.images[k]);
        LightmapPng png;
        png.file = std::filesystem::path(baked.files.atlas_files[k]).replace_extension(".png").generic_string();
        png.bytes = encodeLightmapPng(image);
        if (png.bytes.empty()) {
            diagnostics.error({png.file, 0, 0}, "cannot encode lightmap atlas " + std::to_string(k) + " as a PNG");
            return false;
        }
        pngs.push_back(std::move(png));
    }
    return true;
}

bool stageAll(const Bake& bake, OutputTransaction& transaction, Diagnostics& diagnostics) {
    const Scene& scene = *bake.scene;
    const std::string generator = radbakeGenerator();
    const LightmapFiles* lightmap_files = bake.lightmaps ? &bake.lightmaps->files : nullptr;
    std::vector<LightmapPng> lightmap_pngs;
    if (bake.lightmaps && !encodeLightmapPngs(bake, lightmap_pngs, diagnostics)) return false;
    GltfOptions gltf;
    gltf.generator = generator;
    gltf.lightmaps = lightmap_files;
    gltf.lightmap_textures = bake.lightmaps ? &lightmap_pngs : nullptr;
    gltf.export_lights = bake.options.export_lights;
    if (!writeGlb(transaction.stage(scene.name + ".glb"), scene, bake.vertices, gltf, diagnostics)) return false;
    PlyOptions ply;
    ply.generator = generator;
    ply.lightmaps = lightmap_files;
    if (!writePly(transaction.stage(scene.name + ".ply"), scene, bake.vertices, ply, diagnostics)) return false;
    if (bake.lightmaps && !stageLightmapExrs(transaction, bake, diagnostics)) return false;
    for (const LightmapPng& png : lightmap_pngs)
        if (!writeFileBytes(transaction.stage(png.file), png.bytes, diagnostics)) return false;
    if (bake.lightmaps) {
        const Shadowmask& mask = bake.lightmaps->shadowmask;
        for (size_t k = 0; k < mask.images.size(); ++k)
            if (!writeFileBytes(transaction.stage(bake.lightmaps->files.shadowmask_files[k]),
                                encodeRgba8Png(mask.widths[k], mask.heights[k], mask.images[k]), diagnostics))
                return false;
    }
    for (const PreviewImage& preview : bake.previews)
        if (!writePreviewPng(transaction.stage(preview.file), preview.image, preview.exposure, diagnostics))
            return false;
    if (bake.options.probes && !writeProbesCsv(transaction.stage("probes.csv"), *bake.options.probes, bake.probe_irradiance,
                               diagnostics))
        return false;
    return true;
}

}  // namespace

std::string sceneNameOf(const std::string& path) {
    std::string file = std::filesystem::path(path).filename().string();
    if (file.size() > 3 && file.ends_with(".gz")) file.resize(file.size() - 3);
    const std::string name = std::filesystem::path(file).stem().string();
    return name.empty() ? "scene" : name;
}

bool claimOutputFolder(OutputTransaction& transaction, const std::string& scene_name, Diagnostics& diagnostics) {
    const std::filesystem::path manifest = transaction.outDir() / kManifestName;
    std::error_code ec;
    if (!std::filesystem::exists(std::filesystem::symlink_status(manifest, ec))) return true;
    std::string why;
    const std::optional<ManifestContents> previous = readManifest(manifest, why);
    if (!previous) {
        diagnostics.error({manifest.string(), 0, 0}, "cannot tell which files of this folder are radbake's: " + why +
                                                         "; nothing written (bake into another folder)");
        return false;
    }
    // An older manifest does not name its scene; its glb does (outputs are named by the scene).
    std::string scene = previous->scene;
    for (const std::string& file : previous->files)
        if (scene.empty() && file.find('/') == std::string::npos && file.ends_with(".glb"))
            scene = file.substr(0, file.size() - 4);
    if (!scene.empty() && scene != scene_name) {
        diagnostics.error({manifest.string(), 0, 0},
                          "this folder holds the bake of another scene ('" + scene + "'); nothing written (bake '" +
                              scene_name + "' into another folder, or remove the files its manifest lists)");
        return false;
    }
    for (const std::string& file : previous->files) transaction.retire(file);
    return true;
}

namespace {

bool commitStaged(const Bake& bake, OutputTransaction& transaction, Diagnostics& diagnostics, WrittenBake* written);

}  // namespace

bool commitBake(const Bake& bake, OutputTransaction& transaction, Diagnostics& diagnostics, WrittenBake* written) {
    // An allocation failing while encoding is reported; the transaction removes what was staged.
    try {
        return commitStaged(bake, transaction, diagnostics, written);
    } catch (const std::bad_alloc&) {
        diagnostics.error({transaction.outDir().string(), 0, 0}, outOfMemoryMessage("writing the outputs") +
                                                                     "; nothing written");
    }
    return false;
}

namespace {

bool commitStaged(const Bake& bake, OutputTransaction& transaction, Diagnostics& diagnostics, WrittenBake* written) {
    if (!bake.ok() || !bake.scene) {
        diagnostics.error({transaction.outDir().string(), 0, 0},
                          std::string("nothing written: the bake did not succeed (") + toString(bake.status) + ")");
        return false;
    }
    const auto start = std::chrono::steady_clock::now();
    if (!claimOutputFolder(transaction, bake.scene->name, diagnostics)) return false;
    if (!stageAll(bake, transaction, diagnostics)) return false;  // the destructor removes what was staged

    // stats.json and timings.json last but the manifest, so that the wall time covers every
    // other output.
    BakeReport report = bake.report;
    const double write_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report.phases.emplace_back("write", write_seconds);
    report.seconds += write_seconds;
    report.peak_rss_mb = peakRssMegabytes();
    if (!writeStatsJson(transaction.stage("stats.json"), report, diagnostics)) return false;
    if (!writeTimingsJson(transaction.stage(kTimingsJsonName), report, diagnostics)) return false;
    // The manifest last: the size and SHA-256 of every other output but timings.json (what
    // depends on the run), so the same inputs give the same manifest on any machine.
    const std::vector<std::string> outputs = transaction.staged();
    if (!writeManifest(transaction.stage(kManifestName), transaction.stagingDir(), outputs, radbakeGenerator(),
                       bake.scene->name, diagnostics))
        return false;
    if (!transaction.commit(diagnostics)) return false;
    if (written) *written = WrittenBake{.files = transaction.staged(), .changed = transaction.changedCount()};
    return true;
}

}  // namespace

bool writeBake(const Bake& bake, const std::filesystem::path& out_dir, Diagnostics& diagnostics,
               WrittenBake* written) {
    if (!bake.ok() || !bake.scene) {
        diagnostics.error({out_dir.string(), 0, 0},
                          std::string("nothing written: the bake did not succeed (") + toString(bake.status) + ")");
        return false;
    }
    OutputTransaction transaction(out_dir);
    return transaction.begin(diagnostics) && commitBake(bake, transaction, diagnostics, written);
}

bool bakeInto(const std::string& path, const std::filesystem::path& out_dir, const BakeOptions& options,
              Progress& progress, Diagnostics& diagnostics, Bake* result, WrittenBake* written) {
    OutputTransaction transaction(out_dir);
    if (!transaction.begin(diagnostics) || !claimOutputFolder(transaction, sceneNameOf(path), diagnostics))
        return false;
    Bake baked = bake(path, options, progress, diagnostics);
    const bool ok = baked.ok() && commitBake(baked, transaction, diagnostics, written);
    if (result) *result = std::move(baked);
    return ok;
}

}  // namespace radbake
