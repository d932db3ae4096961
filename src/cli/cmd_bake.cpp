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
    return runBakeInto(args, stepRanks("bake", true), [&](const BakeOptions& options, Progress& progress, Diagnostics& diagnostics) {
        return bake(args.scene, options, progress, diagnostics);
    });
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
