// `radbake bake SCENE`: import, solve, bake per-vertex light, write glb/ply/probes/stats.
// Every output goes through an OutputTransaction: on any error nothing new is left in OUTDIR.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>

#include "bake/vertex_bake.h"
#include "cli/bake_outputs.h"
#include "cli/commands.h"
#include "export/gltf_writer.h"
#include "export/hash.h"
#include "export/manifest.h"
#include "export/output_transaction.h"
#include "export/ply_writer.h"
#include "export/probes.h"
#include "export/stats_json.h"
#include "geometry/parts.h"
#include "io/import.h"
#include "radiosity/parallel.h"
#include "radiosity/solution.h"

namespace radbake::cli {
namespace {

struct BakeArgs {
    std::string scene;
    std::string out_dir;  // empty: baked/<scene name>
    std::string quality_name = "medium";
    std::string visibility_name = "exact";
    int threads = 0;
    std::string probes;
    ImportOptions import;
    bool quiet = false;
    bool preview = false;
    bool no_clustering = false;
    LightmapArgs lightmaps;
    // Raw knobs; applied over the preset only when given on the command line.
    double error_threshold = 0.0;
    double local_error_threshold = 0.0;
    double min_area = 0.0;
    double tolerance = 0.0;
    int max_iterations = 0;
    CLI::Option* error_threshold_option = nullptr;
    CLI::Option* local_error_threshold_option = nullptr;
    CLI::Option* min_area_option = nullptr;
    CLI::Option* tolerance_option = nullptr;
    CLI::Option* max_iterations_option = nullptr;
    CLI::Option* texel_tolerance_option = nullptr;
};

const std::vector<std::pair<std::string, Quality>> kQualities = {
    {"draft", Quality::Draft}, {"medium", Quality::Medium}, {"high", Quality::High}, {"reference", Quality::Reference}};
const std::vector<std::pair<std::string, VisibilityMode>> kVisibilities = {
    {"rays", VisibilityMode::Rays}, {"aabb", VisibilityMode::Aabb}, {"obb", VisibilityMode::Obb},
    {"exact", VisibilityMode::Exact}};

template <typename Enum>
std::vector<std::string> namesOf(const std::vector<std::pair<std::string, Enum>>& table) {
    std::vector<std::string> names;
    for (const auto& entry : table) names.push_back(entry.first);
    return names;
}

// `name` has passed CLI::IsMember, so it is in the table.
template <typename Enum>
Enum lookup(const std::vector<std::pair<std::string, Enum>>& table, const std::string& name) {
    for (const auto& [key, value] : table)
        if (key == name) return value;
    return table.front().second;
}

const std::string kGenerator = std::string("radbake ") + RADBAKE_VERSION;

SolverOptions solverOptions(const BakeArgs& args) {
    const Quality quality = lookup(kQualities, args.quality_name);
    SolverOptions options = SolverOptions::forQuality(quality);
    options.quality = quality;
    options.visibility = lookup(kVisibilities, args.visibility_name);
    options.threads = args.threads;
    if (args.error_threshold_option->count()) options.error_threshold = args.error_threshold;
    if (args.local_error_threshold_option->count()) options.local_error_threshold = args.local_error_threshold;
    if (args.min_area_option->count()) options.min_element_area = args.min_area;
    if (args.tolerance_option->count()) options.iteration_tolerance = args.tolerance;
    if (args.max_iterations_option->count()) options.max_iterations = args.max_iterations;
    options.clustering = !args.no_clustering;
    return options;
}

int threadsUsed(int requested) {
    if (requested > 0) return requested;
    const unsigned cores = std::thread::hardware_concurrency();
    return cores > 0 ? static_cast<int>(cores) : 1;
}

// Diagnostics go to stderr; notes only when the run is interactive (not quiet, a terminal).
void routeDiagnostics(Diagnostics& diagnostics, Progress& progress) {
    diagnostics.sink = [&progress](const Diagnostic& d) {
        if (d.severity == Severity::Note && !progress.shown()) return;
        progress.printLine(formatDiagnostic(d));
    };
}

// Each probe writes its own slot, so probes.csv does not depend on the thread count.
std::vector<DVec3> evaluateProbes(const Solution& solution, const std::vector<Probe>& probes, float unit_scale,
                                  Progress& progress) {
    std::vector<DVec3> irradiance(probes.size());
    std::atomic<size_t> done{0};
    ParallelRunner runner(solution.options.threads, solution.options.pin_threads);
    runner.forEach(probes.size(), 4, [&](size_t i) {
        irradiance[i] = probeIrradiance(solution, probes[i].position * static_cast<double>(unit_scale), probes[i].normal);
        progress.update(static_cast<double>(++done) / static_cast<double>(probes.size()));
    });
    return irradiance;
}

// What an EXR header records of the bake: enough to tell which scene and settings made it.
// Nothing here depends on the thread count or the clock, so outputs stay byte-identical.
std::vector<std::pair<std::string, std::string>> provenance(const BakeArgs& args, const LightmapArgs& lightmaps,
                                                            const SolverOptions& options,
                                                            const std::string& scene_sha256) {
    const double texel_density = lightmaps.texels_per_metre * static_cast<double>(args.import.unit_scale);
    char knobs[512];
    std::snprintf(knobs, sizeof knobs,
                  "quality=%s visibility=%s error_threshold=%g local_error_threshold=%g min_area=%g tolerance=%g max_iterations=%d "
                  "unit_scale=%g emission_scale=%g texel_density=%g atlas_size=%d padding=%d texel_tolerance=%g",
                  toString(options.quality), toString(options.visibility), options.error_threshold,
                  options.local_error_threshold, options.min_element_area, options.iteration_tolerance, options.max_iterations,
                  static_cast<double>(args.import.unit_scale), static_cast<double>(args.import.emission_scale),
                  texel_density, lightmaps.atlas_size, lightmaps.padding, lightmaps.texel_tolerance);
    // Named only when off, so default bakes keep their provenance string.
    if (!options.clustering) std::strncat(knobs, " clustering=off", sizeof knobs - std::strlen(knobs) - 1);
    return {{"radbake:version", kGenerator},
            {"radbake:scene", std::filesystem::path(args.scene).filename().string()},
            {"radbake:scene_sha256", scene_sha256},
            {"radbake:options", knobs}};
}

// Everything after the import; false after reporting. Outputs are only staged here.
bool bakeAndStage(const BakeArgs& args, const Scene& scene, const std::vector<Probe>& probes,
                  OutputTransaction& transaction, Progress& progress, Diagnostics& diagnostics,
                  BakeReport& report) {
    report.options = solverOptions(args);
    LightmapArgs lightmap_args = args.lightmaps;
    if (!args.texel_tolerance_option->count()) lightmap_args.texel_tolerance = texelToleranceFor(report.options.quality);
    // Before the solve: a lightmap budget error should not cost a solve first.
    if (!lightmap_args.skip && !chooseTexelDensity(scene, lightmap_args, args.import.unit_scale, diagnostics))
        return false;

    progress.beginPhase("parts");
    const PartSet parts = buildParts(scene, PartOptions{}, diagnostics);
    if (diagnostics.hasErrors()) return false;

    progress.endPhase();  // the solver names its own phases (elements, links, solve, ...)
    std::optional<Solution> solution = solveRadiosity(scene, parts, report.options, progress, diagnostics);
    if (!solution || diagnostics.hasErrors()) return false;
    report.solve = solution->stats;

    progress.beginPhase("vertices");
    const VertexBake bake = bakeVertices(scene, *solution);

    BakedLightmaps baked;
    if (!args.lightmaps.skip) {
        progress.beginPhase("lightmaps");
        if (!bakeSceneLightmaps(scene, *solution, lightmap_args, args.import.unit_scale, baked, report.lightmaps,
                                diagnostics))
            return false;
    }
    const LightmapFiles* lightmap_files = args.lightmaps.skip ? nullptr : &baked.files;

    std::vector<DVec3> irradiance;
    if (!args.probes.empty()) {
        progress.beginPhase("probes");
        irradiance = evaluateProbes(*solution, probes, args.import.unit_scale, progress);
    }

    progress.beginPhase("write");
    GltfOptions gltf;
    gltf.generator = kGenerator;
    gltf.lightmaps = lightmap_files;
    if (!writeGlb(transaction.stage(scene.name + ".glb"), scene, bake, gltf, diagnostics)) return false;
    PlyOptions ply;
    ply.generator = kGenerator;
    ply.lightmaps = lightmap_files;
    if (!writePly(transaction.stage(scene.name + ".ply"), scene, bake, ply, diagnostics)) return false;
    // Older lightmaps and previews would not match this bake: whatever this run does not
    // write under those folders is removed on commit.
    transaction.retireUnstagedIn("lightmaps");
    transaction.retireUnstagedIn("preview");
    if (!args.lightmaps.skip) {
        const std::optional<std::string> scene_hash = sha256File(args.scene, diagnostics);
        if (!scene_hash) return false;
        if (!stageLightmapExrs(transaction, baked, provenance(args, lightmap_args, report.options, *scene_hash),
                               args.lightmaps.exr_float, diagnostics))
            return false;
    }
    if (args.preview) {
        progress.beginPhase("preview");
        if (!stagePreviews(transaction, scene, bake, args.lightmaps.skip ? nullptr : &baked, diagnostics)) return false;
    }
    if (args.probes.empty()) {
        transaction.retire("probes.csv");  // an older one would not match this bake
    } else if (!writeProbesCsv(transaction.stage("probes.csv"), probes, irradiance, diagnostics)) {
        return false;
    }
    progress.endPhase();

    // stats.json last, so that its wall time covers every other output.
    report.phases = progress.phaseSeconds();
    report.seconds = progress.totalSeconds();
    report.peak_rss_mb = peakRssMegabytes();
    report.warnings = diagnostics.warningCount();
    if (!writeStatsJson(transaction.stage("stats.json"), report, diagnostics)) return false;
    // The manifest last: the size and SHA-256 of every other output.
    const std::vector<std::string> outputs = transaction.staged();
    return writeManifest(transaction.stage("manifest.json"), transaction.stagingDir(), outputs, kGenerator, diagnostics);
}

int runBake(const BakeArgs& args) {
    // One limit for every parallel phase (solver, vertices, probes): --threads N means N.
    const int threads = threadsUsed(args.threads);
    tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));

    Progress progress(!args.quiet && isatty(STDERR_FILENO));
    Diagnostics diagnostics;
    routeDiagnostics(diagnostics, progress);

    progress.beginPhase("import");
    std::optional<Scene> scene = importScene(args.scene, args.import, diagnostics);
    if (!scene) return kExitInputError;
    if (std::none_of(scene->meshes.begin(), scene->meshes.end(), [](const Mesh& m) { return !m.triangles.empty(); })) {
        diagnostics.error({args.scene, 0, 0}, "nothing to bake: the scene has no surfaces");
        return kExitInputError;
    }
    const bool emits = std::any_of(scene->meshes.begin(), scene->meshes.end(), [&](const Mesh& m) {
        return !m.triangles.empty() && m.material < scene->materials.size() && scene->materials[m.material].isEmitter();
    });
    if (!emits && scene->lights.empty())
        diagnostics.warning({args.scene, 0, 0},
                            "the scene has no emissive surface and no light: every baked value will be 0 "
                            "(VRML's headlight is not baked)");
    std::vector<Probe> probes;
    if (!args.probes.empty()) {
        std::optional<std::vector<Probe>> read = readProbes(args.probes, diagnostics);
        if (!read) return kExitInputError;
        probes = std::move(*read);
        if (probes.empty()) diagnostics.warning({args.probes, 0, 0}, "probe file holds no probes");
    }

    const std::filesystem::path out_dir =
        args.out_dir.empty() ? std::filesystem::path("baked") / scene->name : std::filesystem::path(args.out_dir);
    OutputTransaction transaction(out_dir);
    if (!transaction.begin(diagnostics)) return kExitInputError;
    cleanUpStagingOnSignals();

    BakeReport report;
    report.generator = kGenerator;
    report.scene = args.scene;
    report.threads = threads;
    report.meshes = scene->meshes.size();
    for (const Mesh& mesh : scene->meshes) {
        report.vertices += mesh.positions.size();
        report.triangles += mesh.triangles.size();
    }
    report.probes = probes.size();

    if (!bakeAndStage(args, *scene, probes, transaction, progress, diagnostics, report) || diagnostics.hasErrors())
        return kExitInputError;  // the transaction's destructor removes the staged files
    if (!transaction.commit(diagnostics)) return kExitInputError;

    const SolveStats& s = report.solve;
    std::string lightmaps;
    if (report.lightmaps.baked) {
        char buffer[128];
        std::snprintf(buffer, sizeof buffer, ", %zu lightmap%s (%.0f%% occupied)", report.lightmaps.atlases,
                      report.lightmaps.atlases == 1 ? "" : "s", 100.0 * report.lightmaps.occupancy);
        lightmaps = buffer;
    }
    std::printf("radbake: baked %s in %.2f s: %zu elements, %zu links (%zu occluded), %d iterations%s%s, "
                "%d warning%s -> %s\n",
                args.scene.c_str(), report.seconds, s.elements, s.links, s.occluded_links, s.iterations,
                s.converged ? "" : " (not converged)", lightmaps.c_str(), diagnostics.warningCount(),
                diagnostics.warningCount() == 1 ? "" : "s", transaction.outDir().string().c_str());
    return kExitOk;
}

// "draft 0.1, medium 0.01, ...": the preset values of one knob, for --help.
template <typename Field>
std::string presetValues(Field field) {
    std::string out;
    for (Quality q : {Quality::Draft, Quality::Medium, Quality::High, Quality::Reference}) {
        const SolverOptions preset = SolverOptions::forQuality(q);
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%s%s %g", out.empty() ? "" : ", ", toString(q),
                      static_cast<double>(preset.*field));
        out += buffer;
    }
    return "default: from --quality (" + out + ")";
}

}  // namespace

void addBakeCommand(CLI::App& app, int& result) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* cmd = app.add_subcommand("bake", "Solve a scene's light and write baked meshes, probes and stats");
    cmd->add_option("scene", args->scene, "Scene file (VRML97, VRML 1.0, or any format Assimp reads)")->required();
    cmd->add_option("-o,--output", args->out_dir, "Output directory")->default_str("baked/<scene name>/");

    cmd->add_option("--quality", args->quality_name, "Preset for the knobs below")
        ->check(CLI::IsMember(namesOf(kQualities)))
        ->capture_default_str();
    cmd->add_option("--visibility", args->visibility_name,
                    "Occlusion handling: rays (no shafts), aabb (shaft culling), obb (OBB occlusion test), "
                    "exact (conservative occlusion test)")
        ->check(CLI::IsMember(namesOf(kVisibilities)))
        ->capture_default_str();
    cmd->add_option("--threads", args->threads, "Worker threads for every phase; 0: all cores")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--probes", args->probes,
                    "Probe file: one 'x y z nx ny nz' a line (scene units); writes probes.csv with H in W/m^2");
    cmd->add_option("--unit-scale", args->import.unit_scale, "Metres per scene unit")->capture_default_str();
    cmd->add_option("--emission-scale", args->import.emission_scale, "Multiplies every emitted radiance")
        ->capture_default_str();

    args->error_threshold_option =
        cmd->add_option("--error-threshold", args->error_threshold,
                        "Refine a link while the power it may misplace exceeds this fraction of the emitted power; " +
                            presetValues(&SolverOptions::error_threshold))
            ->check(CLI::PositiveNumber);
    args->local_error_threshold_option =
        cmd->add_option("--local-error-threshold", args->local_error_threshold,
                        "Also split the source of a link to an element at the --min-area floor while its form "
                        "factor may vary by more than this fraction of what the element receives (0: off); " +
                            presetValues(&SolverOptions::local_error_threshold))
            ->check(CLI::NonNegativeNumber);
    args->min_area_option =
        cmd->add_option("--min-area", args->min_area,
                        "Smallest element area, relative to the scene's total area; " +
                            presetValues(&SolverOptions::min_element_area))
            ->check(CLI::PositiveNumber);
    args->tolerance_option =
        cmd->add_option("--tolerance", args->tolerance,
                        "Stop iterating when the residual, relative to the emitted light, is below this; " +
                            presetValues(&SolverOptions::iteration_tolerance))
            ->check(CLI::PositiveNumber);
    args->max_iterations_option =
        cmd->add_option("--max-iterations", args->max_iterations,
                        "Iterations per solve before stopping with a warning; " + presetValues(&SolverOptions::max_iterations))
            ->check(CLI::PositiveNumber);

    cmd->add_flag("--no-clustering", args->no_clustering,
                  "Link every facing pair of polygons instead of starting links between clusters of them "
                  "(quadratic in the polygon count: for comparisons)");
    cmd->add_flag("--no-lightmaps", args->lightmaps.skip, "Bake per-vertex light only: no lightmaps/ EXRs, no TEXCOORD_1");
    cmd->add_option("--texel-density", args->lightmaps.texel_density, "Lightmap texels per scene unit")
        ->check(CLI::PositiveNumber)
        ->default_str("16 per metre, from --unit-scale");
    cmd->add_option("--atlas-size", args->lightmaps.atlas_size, "Largest lightmap atlas side, in texels")
        ->check(CLI::Range(16, 16384))
        ->capture_default_str();
    cmd->add_option("--padding", args->lightmaps.padding,
                    "Texels around every chart, filled by dilation, so bilinear filtering never reads a neighbour")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    args->texel_tolerance_option =
        cmd->add_option("--texel-tolerance", args->lightmaps.texel_tolerance,
                        "Interpolate a block of lightmap texels when the texels evaluated in it agree within this "
                        "fraction (0: evaluate every texel); default: from --quality (draft 0.05, medium 0.02, "
                        "high 0.01, reference 0)")
            ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--max-texels", args->lightmaps.max_texels,
                    "Most lightmap texels (charts, padding excluded) a bake may evaluate; over it the default "
                    "density is lowered with a warning, a given --texel-density is an error")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_flag("--exr-float", args->lightmaps.exr_float, "Write lightmaps as 32-bit float instead of half");
    cmd->add_flag("--preview", args->preview,
                  "Also write preview/: a tone-mapped PNG of each atlas and a view of the baked scene");
    cmd->add_flag("--strict", args->import.strict, "Unknown VRML nodes and fields are errors");
    cmd->add_flag("-q,--quiet", args->quiet, "Print only warnings, errors and a one-line summary");
    cmd->callback([args, &result] {
        // The program's outer boundary: nothing escapes main; unwinding abandons the outputs.
        try {
            result = runBake(*args);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "error: %s\n", e.what());
            result = kExitInputError;
        }
    });
}

}  // namespace radbake::cli
