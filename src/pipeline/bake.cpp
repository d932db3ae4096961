// bake(): every stage of src/radbake.h in order, in memory. The module boundary of the
// library: nothing thrown below escapes (reported to Diagnostics instead).
#include "pipeline/bake.h"
#include "pipeline/bake_stages.h"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <functional>
#include <new>

#include "bake/lightmap_budget.h"
#include "bake/lightmap_mesh.h"
#include "core/memory.h"
#include "core/parallel.h"
#include "core/regular_file.h"
#include "export/hash.h"
#include "geometry/parts.h"
#include "io/import.h"
#include "pipeline/solution_cache.h"
#include "readout/realtime_emission.h"
#include "radiosity/solver.h"
#include "scene/two_sided.h"

namespace radbake {
namespace {

constexpr int kPreviewWidth = 800;
constexpr int kPreviewHeight = 600;

// False (after reporting) when there is nothing to bake; warns when every value would be 0.
bool checkBakeable(const Scene& scene, Diagnostics& diagnostics) {
    const SourceLocation where{scene.source_path, 0, 0};
    if (std::none_of(scene.meshes.begin(), scene.meshes.end(), [](const Mesh& m) { return !m.triangles.empty(); })) {
        diagnostics.error(where, "nothing to bake: the scene has no surfaces");
        return false;
    }
    const bool emits = std::any_of(scene.meshes.begin(), scene.meshes.end(), [&](const Mesh& m) {
        return !m.triangles.empty() && m.material < scene.materials.size() && scene.materials[m.material].isEmitter();
    });
    if (!emits && scene.lights.empty() && !scene.sky.shines())
        diagnostics.warning(where, "the scene has no emissive surface and no light: every baked value will be 0 "
                                   "(VRML's headlight is not baked; --sky and --sun add daylight)");
    return true;
}

LightmapOptions lightmapOptions(const LightmapSettings& settings) {
    LightmapOptions options;
    options.atlas_size = settings.atlas_size;
    options.padding = settings.padding;
    options.texel_tolerance = settings.texel_tolerance;
    return options;
}

void renderPreviews(Bake& out, ParallelRunner& runner, Diagnostics& diagnostics) {
    const Scene& scene = *out.scene;
    const Camera* camera = scene.cameras.empty() ? nullptr : &scene.cameras.front();
    const BakedLightmaps* baked = out.lightmaps ? &*out.lightmaps : nullptr;
    // The view shades lightmap irradiance with the albedo; radiance atlases hold it already, so
    // that view reads the vertices instead.
    const BakedLightmaps* shaded = baked && baked->files.quantity == LightmapQuantity::Irradiance ? baked : nullptr;
    RgbImage view = renderBakedView(scene, out.vertices, shaded ? &shaded->lightmaps : nullptr,
                                    shaded ? &shaded->files.meshes : nullptr, camera, kPreviewWidth, kPreviewHeight,
                                    diagnostics, &runner);
    const double view_exposure = autoExposure(view);
    out.previews.push_back({"preview/" + scene.name + "_view.png", std::move(view), view_exposure});
    if (!baked) return;
    // One exposure for every atlas (the first, fullest one's), so their brightness compares.
    const std::vector<LightmapImage>& images = baked->lightmaps.images;
    const double exposure = images.empty() ? 1.0 : autoExposure(toRgbImage(images.front()));
    for (size_t k = 0; k < images.size(); ++k)
        out.previews.push_back(
            {"preview/" + scene.name + "_atlas_" + std::to_string(k) + ".png", toRgbImage(images[k]), exposure});
}

void fillSceneReport(const Scene& scene, Bake& out) {
    BakeReport& report = out.report;
    report.generator = radbakeGenerator();
    report.scene = scene.source_path;
    report.meshes = scene.meshes.size();
    for (const Mesh& mesh : scene.meshes) {
        report.vertices += mesh.positions.size();
        report.triangles += mesh.triangles.size();
        report.two_sided_meshes += mesh.back ? 1 : 0;
        report.two_sided_closed_meshes += mesh.closed_two_sided ? 1 : 0;
    }
    report.hard_edge_vertices = scene.crease_split.vertices;
    report.hard_edge_copies = scene.crease_split.added;
    report.refused_inputs = scene.refused_inputs.size();
    report.probes = out.options.probes ? out.options.probes->size() : 0;
}

void fillLightmapReport(const BakedLightmaps& baked, const LightmapOptions& options, double metres_per_unit,
                        LightmapReport& report) {
    const LightmapLayout& layout = baked.lightmaps.layout;
    report.baked = true;
    report.texels_per_unit = options.texels_per_metre * metres_per_unit;
    report.atlas_size = options.atlas_size;
    report.padding = options.padding;
    report.charts = layout.charts.size();
    report.atlases = layout.atlases.size();
    report.atlas_texels = 0;
    for (const LightmapAtlas& atlas : layout.atlases)
        report.atlas_texels += static_cast<size_t>(atlas.width) * static_cast<size_t>(atlas.height);
    report.covered_texels = baked.lightmaps.covered_texels;
    report.interpolated_texels = baked.lightmaps.interpolated_texels;
    report.hidden_texels = baked.lightmaps.hidden_texels;
    report.texel_tolerance = options.texel_tolerance;
    report.occupancy = layout.occupancy;
    report.realtime_lights = baked.shadowmask.lights.size();
    report.shadowmask_lights_without_channel = baked.shadowmask.lights_without_channel;
    report.shadowmask_texels_over_channels = baked.shadowmask.texels_over_channels;
}

// The parts and the solve into out.solution; false (status unset) when stopped or failed.
bool solveFresh(Bake& out, ParallelRunner& runner, Progress& progress, Diagnostics& diagnostics) {
    // The solve's phases report its fraction and time left as one (the solver knows what follows).
    progress.beginStage("the solve");
    struct EndStage {
        Progress& progress;
        ~EndStage() { progress.endStage(); }
    } end_stage{progress};
    progress.beginPhase("parts");
    checkMemoryBudget(memoryBudgetMegabytes(out.options.solver.max_memory_mb), "parts");
    const PartSet parts = buildParts(*out.scene, PartOptions{}, diagnostics);
    if (progress.cancelled() || diagnostics.hasErrors()) return false;
    progress.endPhase();  // the solver names its own phases (elements, links, solve, ...)
    out.solution = solveRadiosity(*out.scene, parts, out.options.solver, runner, progress, diagnostics);
    return out.solution && !progress.cancelled() && !diagnostics.hasErrors();
}

// `radbake solve`: the stages up to the solve, kept when the solution file already holds this
// scene's solution for these solver settings; sets out.status (InputError, the Bake's default,
// on a failure nothing reported).
void solveStages(Bake& out, bool& kept, Progress& progress, Diagnostics& diagnostics) {
    StageRun run{out, ParallelRunner(out.options.threading, progress.cancelFlag()), progress, diagnostics};
    const Scene& scene = *out.scene;
    if (!checkBakeable(scene, diagnostics)) return (void)run.stopped();
    const std::string key = solutionKey(scene, out.options.solver);
    // The lead's file decides (the other ranks may run where it is not).
    const Ranks& ranks = run.runner.ranks();
    std::string holds = ranks.lead() && solutionFileHolds(key, out.options.solution_file) ? "kept" : "";
    ranks.broadcast(holds);
    kept = !holds.empty();
    if (!kept) {
        if (!solveFresh(out, run.runner, progress, diagnostics)) return (void)run.stopped();
        out.report.solve = out.solution->stats;
        if (!ranks.lead()) return (void)(out.status = BakeStatus::Ok);
        progress.beginPhase("write");
        if (!saveSolution(*out.solution, key, out.options.solution_file, diagnostics)) {
            diagnostics.error({out.options.solution_file, 0, 0}, "the solution was not written (the warning above says why)");
            return (void)run.stopped();
        }
        progress.endPhase();
    }
    if (!run.stopped()) out.status = BakeStatus::Ok;
}

}  // namespace

// Each probe writes its own slot, so the values do not depend on the thread count.
std::vector<DVec3> evaluateProbes(const Solution& solution, const ReadoutOptions& readout,
                                  const std::vector<Probe>& probes, double metres_per_unit, ParallelRunner& runner,
                                  Progress& progress, size_t begin, size_t end) {
    begin = std::min(begin, probes.size());
    end = std::clamp(end, begin, probes.size());
    std::vector<DVec3> irradiance(end - begin, DVec3(0.0));
    if (!carriesLight(solution)) return irradiance;
    std::atomic<size_t> done{0};
    runner.forEach(end - begin, 4, [&](size_t k) {
        const Probe& probe = probes[begin + k];
        irradiance[k] = probeIrradiance(solution, readout, probe.position * metres_per_unit, probe.normal);
        progress.update(static_cast<double>(++done) / static_cast<double>(end - begin));
    });
    return irradiance;
}

ReadoutReport readoutReport(const ReadoutWork& work) {
    return {.points = work.points, .rays = work.counts.rays, .form_factors = work.counts.form_factors};
}

bool StageRun::stopped() {
    if (progress.cancelled()) out.status = BakeStatus::Cancelled;
    else if (diagnostics.hasErrors()) out.status = BakeStatus::InputError;
    else return false;
    return true;
}

void StageRun::beginPhase(const char* name) {
    progress.beginPhase(name);
    checkMemoryBudget(memoryBudgetMegabytes(out.options.solver.max_memory_mb), name);
}

bool prepareStages(StageRun& run, std::optional<LightmapCharts>& charts) {
    Bake& out = run.out;
    const Scene& scene = *out.scene;
    BakeOptions& options = out.options;
    Diagnostics& diagnostics = run.diagnostics;
    out.report.threads = run.runner.threads();
    if (!checkBakeable(scene, diagnostics)) return !run.stopped();
    // Every input file is read once: the scene file's own hash is the first input's.
    std::vector<std::string> inputs = scene.input_files;
    const bool source_listed = !inputs.empty() && inputs.front() ==
                                   std::filesystem::path(scene.source_path).lexically_normal().string();
    if (!source_listed && !scene.source_path.empty() && std::filesystem::is_regular_file(scene.source_path))
        inputs.insert(inputs.begin(), scene.source_path);  // a scene built in memory from a file
    std::string hashes;
    for (size_t i = 0; i < inputs.size(); ++i) {
        // A texture named but absent (warned at import) is an input too: "absent" is its
        // state, so adding the file changes the provenance. So is one that is not a regular
        // file (a FIFO, a device, a directory: warned too), which is never read.
        std::error_code ec;
        const std::filesystem::file_status status = std::filesystem::status(inputs[i], ec);
        if (!std::filesystem::exists(status) || !std::filesystem::is_regular_file(status)) {
            hashes += "absent\n";
            continue;
        }
        std::optional<std::string> hash = sha256File(inputs[i], diagnostics);
        if (!hash) return !run.stopped();
        if (i == 0 && !scene.source_path.empty()) out.scene_sha256 = *hash;
        hashes += *hash + "\n";
    }
    if (!scene.input_files.empty()) out.inputs_sha256 = sha256Hex(hashes);

    if (!options.lightmaps.enabled && !options.lightmaps.scales.empty())
        diagnostics.warning(options.lightmaps.scales.front().location,
                            "lightmap scales have no effect: the bake has no lightmaps");
    if (!options.lightmaps.enabled && options.lightmaps.directional)
        diagnostics.warning({scene.source_path, 0, 0}, "--directional has no effect: the bake has no lightmaps");
    if (!options.lightmaps.enabled && options.lightmaps.quantity == LightmapQuantity::Radiance)
        diagnostics.warning({scene.source_path, 0, 0}, "--lightmap-quantity has no effect: the bake has no lightmaps");
    // Before the solve: a lightmap budget error should not cost a solve first.
    if (options.lightmaps.enabled) {
        charts = chartBakeLightmaps(scene, options, diagnostics);
        if (!charts) return !run.stopped();
        options.lightmaps.texels_per_unit =
            charts->options.texels_per_metre * static_cast<double>(options.import.unit_scale);
    }
    return !run.stopped();
}

ReadoutOptions readoutOptionsOf(const BakeOptions& options) {
    // --texel-tolerance 0 (the reference preset) reads every vertex and texel with the exhaustive gather.
    ReadoutOptions readout = options.readout;
    if (!(options.lightmaps.texel_tolerance > 0.0)) readout.gather = GatherMode::Exhaustive;
    return readout;
}

void completeLightmaps(StageRun& run, BakedLightmaps baked, const LightmapOptions& used, const Solution* solution,
                       const ReadoutOptions& readout) {
    Bake& out = run.out;
    const Scene& scene = *out.scene;
    const BakeOptions& options = out.options;
    ParallelRunner& runner = run.runner;
    Diagnostics& diagnostics = run.diagnostics;
    const double metres_per_unit = static_cast<double>(options.import.unit_scale);
    if (options.lightmaps.quantity == LightmapQuantity::Radiance)
        toReflectedRadiance(scene, used.padding, baked.lightmaps);
    baked.files.quantity = options.lightmaps.quantity;
    if (solution) baked.shadowmask = bakeShadowmask(*solution, baked.lightmaps.layout, used.padding, runner, diagnostics);
    for (size_t k = 0; k < baked.shadowmask.images.size(); ++k)
        baked.files.shadowmask_files.push_back("lightmaps/" + scene.name + "_" + std::to_string(k) + "_shadowmask.png");
    if (options.lightmaps.directional && solution)
        baked.directions = bakeLightmapDirections(*solution, readout, baked.lightmaps.layout, used.padding, runner);
    for (size_t k = 0; k < baked.directions.images.size(); ++k)
        baked.files.direction_files.push_back("lightmaps/" + scene.name + "_" + std::to_string(k) + "_direction.exr");
    for (const ShadowmaskLight& light : baked.shadowmask.lights)
        if (light.channel >= 0) baked.files.shadowmask_channels.emplace_back(light.name, light.channel);
    baked.files.meshes = lightmapMeshes(scene, baked.lightmaps.layout);
    for (size_t k = 0; k < baked.lightmaps.layout.atlases.size(); ++k)
        baked.files.atlas_files.push_back("lightmaps/" + scene.name + "_" + std::to_string(k) + ".exr");
    fillLightmapReport(baked, used, metres_per_unit, out.report.lightmaps);  // after the shadowmask
    out.report.texel_readout = readoutReport(baked.lightmaps.work);
    out.lightmaps = std::move(baked);
}

void finishStages(StageRun& run) {
    Bake& out = run.out;
    if (out.options.preview) {
        run.beginPhase("preview");
        renderPreviews(out, run.runner, run.diagnostics);
        if (run.stopped()) return;
    }
    run.progress.endPhase();
    out.report.phases = run.progress.phaseSeconds();
    out.report.seconds = run.progress.totalSeconds();
    out.report.peak_rss_mb = peakRssMegabytes();
    out.report.ranks = run.runner.ranks().size();
    out.report.exchanged_mb = static_cast<double>(run.runner.ranks().exchangedBytes()) / (1024.0 * 1024.0);
    out.report.exchanges = run.runner.ranks().exchanges();
    out.report.exchange_seconds = run.runner.ranks().exchangeSeconds();
    out.report.shared_seconds = run.runner.ranks().sharedSeconds();
    out.report.warnings = run.diagnostics.warningCount();
    out.status = BakeStatus::Ok;
}

namespace {

// Every stage after the import; sets out.status.
void bakeStages(Bake& out, Progress& progress, Diagnostics& diagnostics) {
    StageRun run{out, ParallelRunner(out.options.threading, progress.cancelFlag()), progress, diagnostics};
    ParallelRunner& runner = run.runner;
    const auto stopped = [&] { return run.stopped(); };
    const auto beginPhase = [&](const char* name) { run.beginPhase(name); };
    std::optional<LightmapCharts> charts;
    if (!prepareStages(run, charts)) return;
    const Scene& scene = *out.scene;
    BakeOptions& options = out.options;
    const double metres_per_unit = static_cast<double>(options.import.unit_scale);

    std::string solution_key;
    if (!options.solution_file.empty()) {
        beginPhase("saved solution");
        solution_key = solutionKey(scene, options.solver);
        out.solution = loadSolution(scene, options.solver, solution_key, options.solution_file, runner.threads(),
                                    diagnostics, runner.ranks());
        if (stopped()) return;
    }
    if (!out.solution) {
        if (!solveFresh(out, runner, progress, diagnostics)) return (void)stopped();
        if (!options.solution_file.empty() && runner.ranks().lead())
            saveSolution(*out.solution, solution_key, options.solution_file, diagnostics);
    }
    out.report.options = options.solver;
    out.report.solve = out.solution->stats;
    if (runner.ranks().size() > 1) return readOutAcrossRanks(run, std::move(charts));

    const RealtimeEmissionLeftOut realtime_emission(*out.solution);  // after the solution is saved
    beginPhase("vertices");
    const ReadoutOptions readout = readoutOptionsOf(options);
    out.vertices = bakeVertices(scene, *out.solution, readout, runner, &progress);
    if (stopped()) return;
    out.report.vertex_readout = readoutReport(out.vertices.work);
    if (charts) {
        beginPhase("lightmaps");
        const LightmapOptions used = charts->options;
        BakedLightmaps baked;
        const bool baked_ok =
            bakeLightmaps(scene, *out.solution, readout, std::move(*charts), runner, baked.lightmaps, diagnostics,
                          &progress);
        if (stopped()) return;
        if (!baked_ok) {
            out.status = BakeStatus::InputError;
            return;
        }
        completeLightmaps(run, std::move(baked), used, &*out.solution, readout);
    }

    if (options.probes) {
        beginPhase("probes");
        out.probe_irradiance =
            evaluateProbes(*out.solution, readout, *options.probes, metres_per_unit, runner, progress, 0, SIZE_MAX);
        if (stopped()) return;
    }
    finishStages(run);
}

// The located error for an allocation failure or a budget overrun at the library's boundary.
void reportMemory(const std::string& scene_path, const std::string& phase, const MemoryBudgetExceeded* over,
                  Diagnostics& diagnostics) {
    const std::string during = phase.empty() ? "baking" : "in the " + phase + " phase";
    if (!over) {
        diagnostics.error({scene_path, 0, 0}, outOfMemoryMessage(during));
        return;
    }
    char message[256];
    std::snprintf(message, sizeof message,
                  "the bake stopped %s: it holds %.0f MiB, above its memory budget of %.0f MiB (--max-memory; "
                  "default 3/4 of this machine's memory)",
                  during.c_str(), over->used_mb, over->budget_mb);
    diagnostics.error({scene_path, 0, 0}, message);
}

Bake bakeOwned(std::unique_ptr<Scene> scene, const BakeOptions& options, Progress& progress,
               Diagnostics& diagnostics, const Stages& stages) {
    Bake out;
    out.scene = std::move(scene);
    const std::string scene_path = out.scene->source_path;
    try {
        out.options = options;
        if (!markRealtimeLights(*out.scene, options.realtime_lights, diagnostics)) {
            out.status = BakeStatus::InputError;
            return out;
        }
        addBackTwins(*out.scene);  // before every stage: each side of a two-sided mesh is a mesh of its own
        fillSceneReport(*out.scene, out);
        stages(out, progress, diagnostics);
    } catch (const std::bad_alloc&) {
        reportMemory(scene_path, progress.currentPhase(), nullptr, diagnostics);
        out.status = BakeStatus::InputError;
    } catch (const MemoryBudgetExceeded& e) {
        reportMemory(scene_path, progress.currentPhase(), &e, diagnostics);
        out.status = BakeStatus::InputError;
    } catch (const std::exception& e) {
        diagnostics.error({scene_path, 0, 0}, std::string("bake failed: ") + e.what());
        out.status = BakeStatus::InputError;
    } catch (...) {
        diagnostics.error({scene_path, 0, 0}, "bake failed (unknown error)");
        out.status = BakeStatus::InputError;
    }
    if (out.status == BakeStatus::Ok && progress.cancelled()) out.status = BakeStatus::Cancelled;
    return out;
}

// Hands a scene to bakeOwned; an allocation failing on the way is reported, not thrown.
Bake bakeScene(Scene&& scene, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics,
               const Stages& stages = bakeStages) {
    const std::string scene_path = scene.source_path;
    try {
        return bakeOwned(std::make_unique<Scene>(std::move(scene)), options, progress, diagnostics, stages);
    } catch (const std::bad_alloc&) {
        reportMemory(scene_path, progress.currentPhase(), nullptr, diagnostics);
    }
    Bake failed;
    failed.status = BakeStatus::InputError;
    return failed;
}

}  // namespace

std::optional<LightmapCharts> chartBakeLightmaps(const Scene& scene, const BakeOptions& options,
                                                 Diagnostics& diagnostics) {
    const LightmapBudget budget{.texels_per_unit = options.lightmaps.texels_per_unit,
                                .metres_per_unit = static_cast<double>(options.import.unit_scale),
                                .max_texels = options.lightmaps.max_texels};
    LightmapOptions lightmap_options = lightmapOptions(options.lightmaps);
    if (!options.lightmaps.scales.empty())
        lightmap_options.mesh_texel_scale = meshTexelScales(scene, options.lightmaps.scales, diagnostics);
    return chartLightmapsWithinBudget(scene, std::move(lightmap_options), budget, diagnostics);
}

const char* toString(BakeStatus status) {
    switch (status) {
        case BakeStatus::Ok: return "ok";
        case BakeStatus::InputError: return "input error";
        case BakeStatus::Cancelled: return "cancelled";
    }
    return "?";
}

// Reads the scene at `path` (options.import) and runs `stages` on it.
Bake importAndRun(const std::string& path, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics,
                  const Stages& stages) {
    progress.beginPhase("import");
    ImportOptions import = options.import;
    if (!(import.max_memory_mb > 0.0)) import.max_memory_mb = options.solver.max_memory_mb;  // one budget
    std::optional<Scene> scene = importScene(path, import, diagnostics);  // reports, never throws
    if (!scene) {
        Bake failed;
        failed.options = options;
        failed.status = progress.cancelled() ? BakeStatus::Cancelled : BakeStatus::InputError;
        return failed;
    }
    return bakeScene(std::move(*scene), options, progress, diagnostics, stages);
}

Bake bake(const std::string& path, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics) {
    return importAndRun(path, options, progress, diagnostics, bakeStages);
}

SolveOnly solveOnly(const std::string& path, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics) {
    SolveOnly result;
    if (options.solution_file.empty()) {
        diagnostics.error({path, 0, 0}, "the solve alone needs a solution file to write");
        return result;
    }
    // Refused before the solve, as it would be replaced after it.
    if (const std::string why = whyNotReplaceable(options.solution_file); !why.empty()) {
        diagnostics.error({options.solution_file, 0, 0}, "cannot write the solution file: " + why);
        return result;
    }
    const Bake solved = importAndRun(path, options, progress, diagnostics,
                                     [&](Bake& out, Progress& p, Diagnostics& d) { solveStages(out, result.kept, p, d); });
    result.status = solved.status;
    result.stats = solved.report.solve;
    if (solved.scene) result.input_files = solved.scene->input_files;
    result.seconds = progress.totalSeconds();
    return result;
}

Bake bake(Scene scene, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics) {
    BakeOptions in_metres = options;
    in_metres.import = ImportOptions{};  // a scene in memory is in metres already
    return bakeScene(std::move(scene), in_metres, progress, diagnostics);
}

}  // namespace radbake
