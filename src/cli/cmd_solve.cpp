// `radbake solve SCENE --solution FILE`: the solve alone, the first step of a bake split into a
// solve and read-out shards. It takes every bake option (the same parser as `bake`), so a build
// farm passes one command line to each step; those of the read-out and the lightmaps change
// nothing here. A FILE that already holds this scene's solution for these solver settings is
// kept as it is (its time too), so Make and Ninja see it up to date.
#include <cstdio>
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

int runSolve(const BakeArgs& args) {
    const Ranks& ranks = stepRanks("solve", true);
    Progress progress(progressStyleOf(args.quiet || !ranks.lead()));
    Diagnostics diagnostics;
    routeRankDiagnostics(ranks, diagnostics, progress);
    if (ranks.lead() && !depfileWritable(args, diagnostics)) return kExitInputError;
    BakeOptions options = bakeOptions(args, ranks);
    const SolveOnly solved = solveOnly(args.scene, options, progress, diagnostics);
    if (!solved.ok()) return kExitInputError;
    if (!ranks.lead()) return kExitOk;  // the lead alone writes
    if (!args.depfile.empty() &&
        !writeDepfile(args.depfile, {args.solution_file}, solved.input_files, diagnostics))
        return kExitInputError;
    if (solved.kept) {
        std::printf("radbake: kept %s: it holds the solution of %s for these solver settings\n",
                    args.solution_file.c_str(), args.scene.c_str());
        return kExitOk;
    }
    const SolveStats& s = solved.stats;
    std::printf("radbake: solved %s in %.2f s: %zu elements, %zu links (%zu occluded), %d iterations%s, %d warning%s "
                "-> %s\n",
                args.scene.c_str(), solved.seconds, s.elements, s.links, s.occluded_links, s.iterations,
                s.converged ? "" : " (not converged)", diagnostics.warningCount(),
                diagnostics.warningCount() == 1 ? "" : "s", args.solution_file.c_str());
    return kExitOk;
}

}  // namespace

void addSolveCommand(CLI::App& app, int& result) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* cmd = app.add_subcommand(
        "solve", "Solve a scene's light into a solution file only (the first step of a bake split over machines)");
    cmd->add_option("scene", args->scene, "Scene file (VRML97, VRML 1.0, or any format Assimp reads)")->required();
    addBakeOptions(*cmd, *args);
    cmd->get_option("--solution")->required();
    cmd->callback([args, &result] { runGuarded(args->scene, "solving", result, [&] { return runSolve(*args); }); });
}

}  // namespace radbake::cli
