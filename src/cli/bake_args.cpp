#include "cli/bake_args.h"

#include <unistd.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <new>
#include <optional>
#include <vector>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "core/memory.h"
#include "core/regular_file.h"
#include "export/output_transaction.h"

namespace radbake::cli {
namespace {

// Upper bounds of the numeric options: far above any real use, well below what breaks
// (ten million threads crash TBB); the lightmap options' bounds live with them (option_checks.cpp).
constexpr long long kMaxThreads = 1024;
constexpr long long kMaxIterations = 1000000;

const std::vector<std::pair<std::string, Quality>> kQualities = {
    {"draft", Quality::Draft}, {"medium", Quality::Medium}, {"high", Quality::High}, {"reference", Quality::Reference}};
const std::vector<std::pair<std::string, LinkVisibility>> kVisibilities = {
    {"rays", LinkVisibility::Rays}, {"aabb", LinkVisibility::Aabb}, {"obb", LinkVisibility::Obb},
    {"exact", LinkVisibility::Exact}};

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

// "draft 0.1, medium 0.01, ...": the preset values of one knob, for --help, read from the
// presets themselves (BakeOptions::forQuality) so the help never repeats them.
template <typename Read>
std::string presetValuesOf(Read read) {
    std::string out;
    for (Quality q : {Quality::Draft, Quality::Medium, Quality::High, Quality::Reference}) {
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%s%s %g", out.empty() ? "" : ", ", toString(q),
                      static_cast<double>(read(BakeOptions::forQuality(q))));
        out += buffer;
    }
    return "default: from --quality (" + out + ")";
}

template <typename Field>
std::string presetValues(Field field) {
    return presetValuesOf([field](const BakeOptions& preset) { return preset.solver.*field; });
}

}  // namespace

BakeOptions bakeOptions(const BakeArgs& args, const Ranks& ranks) {
    BakeOptions options = BakeOptions::forQuality(lookup(kQualities, args.quality_name));
    SolverOptions& solver = options.solver;
    solver.visibility = lookup(kVisibilities, args.visibility_name);
    if (args.error_threshold_option->count()) solver.error_threshold = args.error_threshold;
    if (args.local_error_threshold_option->count()) solver.local_error_threshold = args.local_error_threshold;
    if (args.min_area_option->count()) solver.min_element_area = args.min_area;
    if (args.tolerance_option->count()) solver.iteration_tolerance = args.tolerance;
    if (args.max_iterations_option->count()) solver.max_iterations = args.max_iterations;
    solver.max_memory_mb = args.max_memory_mb;  // bake() reads the scene under it too
    solver.clustering = !args.no_clustering;
    if (!args.edge_correction.empty())
        options.readout.edge_correction = args.edge_correction == "on"       ? EdgeCorrection::On
                                          : args.edge_correction == "shared" ? EdgeCorrection::Shared
                                                                             : EdgeCorrection::Off;
    const double texel_tolerance = options.lightmaps.texel_tolerance;
    options.lightmaps = args.lightmaps;
    options.lightmaps.enabled = !args.no_lightmaps;
    options.lightmaps.quantity =
        args.lightmap_quantity == "radiance" ? LightmapQuantity::Radiance : LightmapQuantity::Irradiance;
    if (!args.texel_tolerance_option->count()) options.lightmaps.texel_tolerance = texel_tolerance;
    options.import = args.import;
    options.preview = args.preview;
    options.export_lights = args.export_lights;
    options.solution_file = args.solution_file;
    // A program that owns its process pins its workers (unpinned ones were seen sharing one
    // core on the 2-core build machines); the library does not unless asked.
    options.threading = Threading{.threads = args.threads, .pin = !args.no_pin_threads, .ranks = &ranks};
    return options;
}


bool readBakeSideFiles(const BakeArgs& args, BakeOptions& options, Diagnostics& diagnostics) {
    if (!args.probes.empty()) {
        std::optional<std::vector<Probe>> read = readProbes(args.probes, diagnostics);
        if (!read) return false;
        if (read->empty()) diagnostics.warning({args.probes, 0, 0}, "probe file holds no probes");
        options.probes = std::move(*read);
    }
    if (!args.lightmap_scales.empty()) {
        std::optional<std::vector<LightmapScaleRule>> rules = readLightmapScales(args.lightmap_scales, diagnostics);
        if (!rules) return false;
        options.lightmaps.scales = std::move(*rules);
    }
    if (!args.realtime_lights.empty()) {
        std::optional<std::vector<RealtimeLightName>> names = readRealtimeLights(args.realtime_lights, diagnostics);
        if (!names) return false;
        options.realtime_lights = std::move(*names);
    }
    return true;
}

bool depfileWritable(const BakeArgs& args, Diagnostics& diagnostics) {
    const std::string why = args.depfile.empty() ? "" : whyNotReplaceable(args.depfile);
    if (why.empty()) return true;
    diagnostics.error({args.depfile, 0, 0}, "cannot write the depfile: " + why);
    return false;
}

ProgressStyle progressStyleOf(bool quiet) {
    return quiet ? ProgressStyle::Hidden : isatty(STDERR_FILENO) ? ProgressStyle::Terminal : ProgressStyle::Lines;
}

void routeDiagnostics(Diagnostics& diagnostics, Progress& progress) {
    diagnostics.sink = [&progress](const Diagnostic& d) {
        if (d.severity == Severity::Note && !progress.shown()) return;
        progress.printLine(formatDiagnostic(d));
    };
}

void runGuarded(const std::string& scene, const char* doing, int& result, const std::function<int()>& run) {
    try {
        result = run();
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "%s\n", formatDiagnostic({Severity::Error, {scene, 0, 0}, outOfMemoryMessage(doing)}).c_str());
        result = kExitInputError;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: error: %s\n", scene.c_str(), e.what());
        result = kExitInputError;
    }
}

const Ranks& stepRanks(const char* step, bool shares) {
    const Ranks& world = Ranks::world();
    if (world.size() > 1 && !shares)
        throw std::runtime_error(std::string("radbake ") + step + " runs as one process: mpirun started " +
                                 std::to_string(world.size()) + " (only bake and solve share their work between ranks)");
    return shares ? world : Ranks::one();
}

void routeRankDiagnostics(const Ranks& ranks, Diagnostics& diagnostics, Progress& progress) {
    if (ranks.lead()) return routeDiagnostics(diagnostics, progress);
    const std::string mark = "rank " + std::to_string(ranks.rank()) + ": ";
    diagnostics.sink = [mark](const Diagnostic& d) {
        if (d.severity == Severity::Error) std::fprintf(stderr, "%s%s\n", mark.c_str(), formatDiagnostic(d).c_str());
    };
}

int runBakeInto(const BakeArgs& args, const Ranks& ranks, const MakeBake& make,
                const std::vector<std::string>& extra_inputs) {
    Progress progress(progressStyleOf(args.quiet || !ranks.lead()));
    Diagnostics diagnostics;
    routeRankDiagnostics(ranks, diagnostics, progress);
    if (!ranks.lead()) {  // the lead alone writes
        BakeOptions options = bakeOptions(args, ranks);
        if (!readBakeSideFiles(args, options, diagnostics)) return kExitInputError;
        return make(options, progress, diagnostics).ok() ? kExitOk : kExitInputError;
    }
    // An interrupted content build leaves no temporary directory behind.
    cleanUpStagingOnSignals();

    // Refused before the bake, which would otherwise write every other output first.
    if (!depfileWritable(args, diagnostics)) return kExitInputError;
    // The folder is locked (and checked to be this scene's) before any work: a second bake
    // into it is refused at once, not after its solve.
    const std::filesystem::path out_dir = args.out_dir.empty()
                                              ? std::filesystem::path("baked") / sceneNameOf(args.scene)
                                              : std::filesystem::path(args.out_dir);
    OutputTransaction transaction(out_dir);
    if (!transaction.begin(diagnostics) || !claimOutputFolder(transaction, sceneNameOf(args.scene), diagnostics))
        return kExitInputError;
    BakeOptions options = bakeOptions(args, ranks);
    if (!readBakeSideFiles(args, options, diagnostics)) return kExitInputError;
    const Bake result = make(options, progress, diagnostics);
    if (!result.ok()) return kExitInputError;
    WrittenBake written;
    if (!commitBake(result, transaction, diagnostics, &written) || diagnostics.hasErrors()) return kExitInputError;
    if (!args.depfile.empty()) {
        std::vector<std::string> targets, inputs = result.scene->input_files;
        inputs.insert(inputs.end(), extra_inputs.begin(), extra_inputs.end());
        for (const std::string& file : written.files) targets.push_back((out_dir / file).lexically_normal().string());
        if (!args.probes.empty()) inputs.push_back(args.probes);
        if (!args.lightmap_scales.empty()) inputs.push_back(args.lightmap_scales);
        if (!args.realtime_lights.empty()) inputs.push_back(args.realtime_lights);
        if (!writeDepfile(args.depfile, targets, inputs, diagnostics)) return kExitInputError;
    }

    const SolveStats& s = result.report.solve;
    std::string lightmaps;
    if (result.report.lightmaps.baked) {
        char buffer[128];
        std::snprintf(buffer, sizeof buffer, ", %zu lightmap%s (%.0f%% occupied)", result.report.lightmaps.atlases,
                      result.report.lightmaps.atlases == 1 ? "" : "s", 100.0 * result.report.lightmaps.occupancy);
        lightmaps = buffer;
    }
    std::printf("radbake: baked %s in %.2f s: %zu elements, %zu links (%zu occluded), %d iterations%s%s, "
                "%d warning%s -> %s (%zu of %zu files changed)\n",
                args.scene.c_str(), progress.totalSeconds(), s.elements, s.links, s.occluded_links, s.iterations,
                s.converged ? "" : " (not converged)", lightmaps.c_str(), diagnostics.warningCount(),
                diagnostics.warningCount() == 1 ? "" : "s", out_dir.lexically_normal().string().c_str(), written.changed,
                written.files.size());
    return kExitOk;
}


void addBakeOptions(CLI::App& cmd, BakeArgs& args) {
    cmd.add_option("--quality", args.quality_name, "Preset for the knobs below")
        ->check(CLI::IsMember(namesOf(kQualities)))
        ->capture_default_str();
    cmd.add_option("--visibility", args.visibility_name,
                    "Occlusion handling: rays (no shafts), aabb (shaft culling), obb (OBB occlusion test), "
                    "exact (conservative occlusion test)")
        ->check(CLI::IsMember(namesOf(kVisibilities)))
        ->capture_default_str();
    cmd.add_option("--threads", args.threads, "Worker threads for every phase; 0: all cores")
        ->transform(wholeIn(0, kMaxThreads))
        ->capture_default_str();
    cmd.add_flag("--no-pin-threads", args.no_pin_threads,
                  "Leave worker threads unpinned (by default each is bound to a core of its own)");
    cmd.add_option("--probes", args.probes,
                    "Probe file: one 'x y z nx ny nz' a line (scene units); writes probes.csv with H in W/m^2")
        ->check(nonEmptyPath());
    cmd.add_option("--depfile", args.depfile,
                    "Also write a Make-syntax depfile (for Ninja's depfile =, make's include): every output, "
                    "then every file the bake read or looked for (the scene, Inline'd and EXTERNPROTO files, MTL files, "
                    "textures, probes)")
        ->check(nonEmptyPath());
    addSceneScaleOptions(cmd, args.import);
    addDaylightOptions(cmd, args.import.daylight);
    addReadRootOption(cmd, args.import);

    args.error_threshold_option =
        cmd.add_option("--error-threshold", args.error_threshold,
                        "Refine a link while the power it may misplace exceeds this fraction of the emitted power; " +
                            presetValues(&SolverOptions::error_threshold))
            ->check(positiveReal(1.0));
    args.local_error_threshold_option =
        cmd.add_option("--local-error-threshold", args.local_error_threshold,
                        "Also split the source of a link to an element at the --min-area floor while its form "
                        "factor may vary by more than this fraction of what the element receives (0: off); " +
                            presetValues(&SolverOptions::local_error_threshold))
            ->check(nonNegativeReal(1.0));
    args.min_area_option =
        cmd.add_option("--min-area", args.min_area,
                        "Smallest element area, relative to the scene's total area; " +
                            presetValues(&SolverOptions::min_element_area))
            ->check(positiveReal(1.0));
    args.tolerance_option =
        cmd.add_option("--tolerance", args.tolerance,
                        "Stop iterating when the residual, relative to the emitted light, is below this; " +
                            presetValues(&SolverOptions::iteration_tolerance))
            ->check(positiveReal(1.0));
    args.max_iterations_option =
        cmd.add_option("--max-iterations", args.max_iterations,
                        "Iterations per solve before stopping with a warning; " + presetValues(&SolverOptions::max_iterations))
            ->transform(wholeIn(1, kMaxIterations));

    addMaxMemoryOption(cmd, args.max_memory_mb);
    cmd.add_flag("--no-clustering", args.no_clustering,
                  "Link every facing pair of polygons instead of starting links between clusters of them "
                  "(quadratic in the polygon count: for comparisons)");
    cmd.add_option("--edge-correction", args.edge_correction,
                    "Correct points on concave edges and corners for the darkening of the face beside them: "
                    "on (medium, high, reference): every such point, vertices, texels and probes; shared: "
                    "texels, and output vertices only where the faces beside have vertices too (a room's "
                    "edges, not a block's foot), 0.4 x on's vertex time (draft); off")
        ->check(CLI::IsMember({"off", "shared", "on"}));
    cmd.add_option("--solution", args.solution_file,
                    "Reuse the radiosity solution saved in this file when the scene and solver settings are the "
                    "same (iterating on lightmap, vertex or probe settings), else solve and save it there")
        ->check(nonEmptyPath());
    cmd.add_flag("--no-lightmaps", args.no_lightmaps, "Bake per-vertex light only: no lightmaps/ EXRs, no TEXCOORD_1");
    addLightmapLayoutOptions(cmd, args.lightmaps, args.lightmap_scales);
    args.texel_tolerance_option =
        cmd.add_option("--texel-tolerance", args.lightmaps.texel_tolerance,
                        "Interpolate a block of lightmap texels when the texels evaluated in it agree within this "
                        "fraction (0: evaluate every texel); " +
                            presetValuesOf([](const BakeOptions& preset) { return preset.lightmaps.texel_tolerance; }))
            ->check(nonNegativeReal(1.0));
    cmd.add_flag("--exr-float", args.lightmaps.exr_float, "Write lightmaps as 32-bit float instead of half");
    cmd.add_flag("--directional", args.lightmaps.directional,
                  "Directional lightmaps: also lightmaps/<name>_<k>_direction.exr, how each texel's light changes "
                  "with the normal (for normal maps: E(n) = lightmap x max(0, 1 + g . (n - n0))); nine reads a texel");
    cmd.add_option("--realtime-lights", args.realtime_lights,
                    "Mixed lighting: a file of names of lights and emissive meshes, one a line, whose direct light "
                    "the engine draws; "
                    "their light still bounces, but no vertex, texel or probe holds their direct light, and "
                    "each atlas gets a shadowmask of their visibility")
        ->check(nonEmptyPath());
    cmd.add_option("--lightmap-quantity", args.lightmap_quantity,
                    "What a lightmap texel holds: irradiance (H/pi; an engine multiplies it by the albedo) or "
                    "radiance (reflectance x H/pi, for unlit pipelines); emission is in neither")
        ->check(CLI::IsMember({"irradiance", "radiance"}))
        ->capture_default_str();
    cmd.add_flag("--preview", args.preview,
                  "Also write preview/: a tone-mapped PNG of each atlas and a view of the baked scene");
    cmd.add_flag("--export-lights", args.export_lights,
                  "Also write the scene's lights into the glb (KHR_lights_punctual, marked as baked in extras); "
                  "off by default, as their light is baked already and an engine would add it again");
    cmd.add_flag("--strict", args.import.strict, "Unknown VRML nodes and fields are errors");
    cmd.add_flag("-q,--quiet", args.quiet, "Print only warnings, errors and a one-line summary");
}

}  // namespace radbake::cli
