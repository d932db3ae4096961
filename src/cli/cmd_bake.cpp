// `radbake bake SCENE`: parses the command line into one BakeOptions, calls the library's
// bake() and writeBake() (src/radbake.h), and prints. What belongs to a program and not to a
// library lives here: the terminal progress line, signal handlers that remove a half-written
// output, thread pinning by default.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/bake_args.h"
#include "cli/commands.h"
#include "cli/option_checks.h"
#include "core/regular_file.h"
#include "export/output_transaction.h"
#include "radbake.h"

namespace radbake::cli {
namespace {

int runBake(const BakeArgs& args) {
    Progress progress(progressStyleOf(args.quiet));
    Diagnostics diagnostics;
    routeDiagnostics(diagnostics, progress);
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
    BakeOptions options = bakeOptions(args);
    if (!readBakeSideFiles(args, options, diagnostics)) return kExitInputError;
    const Bake result = bake(args.scene, options, progress, diagnostics);
    if (!result.ok()) return kExitInputError;
    WrittenBake written;
    if (!commitBake(result, transaction, diagnostics, &written) || diagnostics.hasErrors()) return kExitInputError;
    if (!args.depfile.empty()) {
        std::vector<std::string> targets, inputs = result.scene->input_files;
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

}  // namespace

void addBakeCommand(CLI::App& app, int& result) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* cmd = app.add_subcommand("bake", "Solve a scene's light and write baked meshes, probes and stats");
    cmd->add_option("scene", args->scene, "Scene file (VRML97, VRML 1.0, or any format Assimp reads)")->required();
    cmd->add_option("-o,--output", args->out_dir, "Output directory")
        ->check(nonEmptyPath())
        ->default_str("baked/<scene name>/");
    addBakeOptions(*cmd, *args);
    cmd->callback([args, &result] { runGuarded(args->scene, "baking", result, [&] { return runBake(*args); }); });
}

}  // namespace radbake::cli
