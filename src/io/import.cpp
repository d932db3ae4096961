#include "io/import.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/exr_io.h"
#include "core/memory.h"
#include "io/assimp/assimp_reader.h"
#include "io/vrml/vrml_reader.h"
#include "scene/creases.h"
#include "scene/daylight.h"
#include "scene/textures.h"
#include "scene/validate.h"

namespace radbake {
namespace {

// Units and emission are applied once here, so every reader works in its file's own units.
void applyScales(Scene& scene, const ImportOptions& options) {
    const float s = options.unit_scale;
    if (s != 1.0f) {
        for (Mesh& mesh : scene.meshes)
            for (Vec3& p : mesh.positions) p *= s;
        for (Light& light : scene.lights) {
            light.position *= s;
            if (light.type != LightType::Directional) light.radius *= s;
        }
        for (Camera& camera : scene.cameras) camera.position *= s;
    }
    if (options.emission_scale != 1.0f)
        for (Material& material : scene.materials) material.emission *= options.emission_scale;
}

std::string firstBytes(const std::string& path, size_t count) {
    std::ifstream in(path, std::ios::binary);
    std::string bytes(count, '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(count));
    bytes.resize(static_cast<size_t>(in.gcount()));
    return bytes;
}

std::optional<Scene> importPhases(const std::string& path, const ImportOptions& options, Diagnostics& diagnostics,
                                  const char*& phase);

// The environment map --sky names, read whole; null after a located error. A NaN or infinite
// texel is an error (no light to bake by); a negative one, which some HDR tools leave, is
// clamped to 0 and counted.
std::shared_ptr<EnvironmentMap> readEnvironmentMap(const std::string& path, size_t max_bytes, MemoryGauge& memory,
                                                   Diagnostics& diagnostics) {
    const SourceLocation at{path, 0, 0};
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        diagnostics.error(at, "cannot open environment map (no such regular file)");
        return nullptr;
    }
    if (std::filesystem::file_size(path, ec) > max_bytes) {
        diagnostics.error(at, "environment map is larger than the input limit of " + std::to_string(max_bytes) + " bytes");
        return nullptr;
    }
    std::optional<RgbImage> image = readExr(path, diagnostics);
    if (!image) return nullptr;
    size_t negative = 0;
    for (size_t i = 0; i < image->rgb.size(); ++i) {
        float& value = image->rgb[i];
        if (!std::isfinite(value)) {
            const size_t texel = i / 3;
            diagnostics.error(at, "environment map texel (" + std::to_string(texel % image->width) + ", " +
                                      std::to_string(texel / image->width) + ") is not a finite radiance");
            return nullptr;
        }
        if (value < 0.0f) value = 0.0f, ++negative;
    }
    if (negative > 0)
        diagnostics.warning(at, "environment map: " + std::to_string(negative) +
                                    " negative channel values read as 0");
    if (image->width != 2 * image->height)
        diagnostics.warning(at, "environment map is " + std::to_string(image->width) + " x " +
                                    std::to_string(image->height) +
                                    ", not 2:1: read as equirectangular all the same");
    // The integral table beside the texels.
    if (!memory.reserve(double(image->width + 1) * (image->height + 1) * 3 * sizeof(double))) {
        diagnostics.error(at, "environment map does not fit in the memory budget");
        return nullptr;
    }
    return std::make_shared<EnvironmentMap>(
        makeEnvironmentMap(image->width, image->height, std::move(image->rgb), path));
}

}  // namespace

std::optional<Scene> importScene(const std::string& path, const ImportOptions& options,
                                 Diagnostics& diagnostics) {
    const char* phase = "reading the scene";
    try {
        return importPhases(path, options, diagnostics, phase);
    } catch (const std::bad_alloc&) {
        diagnostics.error({path, 0, 0}, outOfMemoryMessage(phase));
    } catch (const std::exception& e) {
        diagnostics.error({path, 0, 0}, std::string("import failed while ") + phase + ": " + e.what());
    }
    return std::nullopt;
}

namespace {

// importScene's work; `phase` names the step under way for the boundary's message.
std::optional<Scene> importPhases(const std::string& path, const ImportOptions& options, Diagnostics& diagnostics,
                                  const char*& phase) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        diagnostics.error({path, 0, 0}, "cannot open scene file (no such regular file)");
        return std::nullopt;
    }
    if (!(options.unit_scale > 0.0f) || !std::isfinite(options.unit_scale)) {
        diagnostics.error({}, "--unit-scale must be a positive finite number");
        return std::nullopt;
    }
    if (!(options.emission_scale >= 0.0f) || !std::isfinite(options.emission_scale)) {
        diagnostics.error({}, "--emission-scale must be a non-negative finite number");
        return std::nullopt;
    }
    if (const std::string problem = checkDaylight(options.daylight); !problem.empty()) {
        diagnostics.error({}, problem);
        return std::nullopt;
    }

    Scene scene;
    scene.source_path = path;
    scene.read_roots = options.read_roots;
    // The name outputs are called by: the file name without its format suffixes. Only the
    // last extension is a format (furnace_rho_0.99.wrl is "furnace_rho_0.99", not "furnace_rho_0").
    std::string stem = std::filesystem::path(path).filename().string();
    if (stem.size() > 3 && stem.ends_with(".gz")) stem.resize(stem.size() - 3);
    scene.name = std::filesystem::path(stem).stem().string();
    if (scene.name.empty()) scene.name = "scene";

    const ReadPolicy policy = readPolicyFor(path, options.read_roots, options.max_input_bytes);
    MemoryGauge memory(memoryBudgetMegabytes(options.max_memory_mb));
    std::vector<std::string> files_read;
    const bool ok = looksLikeVrml(firstBytes(path, 16))
                        ? readVrml(path,
                                   VrmlOptions{.strict = options.strict, .files_read = &files_read, .policy = &policy,
                                               .files_refused = &scene.refused_inputs, .memory = &memory},
                                   scene, diagnostics)
                        : readWithAssimp(path, scene, diagnostics,
                                         AssimpReads{.policy = &policy, .files_read = &files_read,
                                                     .files_refused = &scene.refused_inputs, .memory = &memory});
    if (!ok || diagnostics.hasErrors()) return std::nullopt;
    // The scene file first, then each other file once, in the order first read.
    files_read.insert(files_read.begin(), path);
    for (const std::string& file : files_read) {
        const std::string normal = std::filesystem::path(file).lexically_normal().string();
        if (std::find(scene.input_files.begin(), scene.input_files.end(), normal) == scene.input_files.end())
            scene.input_files.push_back(normal);
    }
    applyScales(scene, options);
    std::shared_ptr<EnvironmentMap> map;
    if (options.daylight.sky == SkyModel::Map) {
        phase = "reading the environment map";
        map = readEnvironmentMap(options.daylight.sky_map, options.max_input_bytes, memory, diagnostics);
        if (!map) return std::nullopt;
        // An input like the scene's files: the depfile names it, the provenance hashes it.
        const std::string normal = std::filesystem::path(options.daylight.sky_map).lexically_normal().string();
        if (std::find(scene.input_files.begin(), scene.input_files.end(), normal) == scene.input_files.end())
            scene.input_files.push_back(normal);
    }
    // After the scales: --emission-scale is the file's emitters only.
    size_t suns_taken = 0;
    if (const std::string problem = addDaylight(scene, options.daylight, std::move(map), &suns_taken);
        !problem.empty()) {
        diagnostics.error({path, 0, 0}, problem);
        return std::nullopt;
    }
    if (suns_taken > 0)
        diagnostics.note({options.daylight.sky_map, 0, 0},
                         std::to_string(suns_taken) + (suns_taken == 1 ? " sun" : " suns") +
                             " drawn in the environment map taken out as directional lights (their shadows sharp)");
    // After the emission scale (a textured emission is the scaled colour times the texture),
    // before validation (which clamps textured reflectance as it does the materials').
    phase = "reading textures";
    applyTextures(scene, policy, options.max_memory_mb, diagnostics);
    std::sort(scene.refused_inputs.begin(), scene.refused_inputs.end());
    scene.refused_inputs.erase(std::unique(scene.refused_inputs.begin(), scene.refused_inputs.end()),
                               scene.refused_inputs.end());
    phase = "validating the scene";
    if (!validateScene(scene, diagnostics, memory.budgetMegabytes())) return std::nullopt;
    // After validation (no degenerate triangles left to misjudge an edge), before the solve:
    // every later stage sees each face's corners as its own.
    phase = "splitting hard edges";
    splitHardEdges(scene);
    return scene;
}

}  // namespace

}  // namespace radbake
