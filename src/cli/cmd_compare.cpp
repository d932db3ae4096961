// `radbake compare A B`: golden-file comparison of two bakes (or two files of one kind).
// Exit 0 within tolerance, 1 beyond it (the worst place is named), 2 not comparable.
#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "export/compare.h"

namespace radbake::cli {
namespace {

struct CompareArgs {
    std::string a, b;
    CompareOptions options;
    bool quiet = false;
};

int runCompare(const CompareArgs& args) {
    const CompareResult result = comparePaths(args.a, args.b, args.options);
    const int code = result.exitCode();
    if (!args.quiet || code != 0) std::fputs(formatCompareResult(result).c_str(), stdout);
    return code;
}

}  // namespace

void addCompareCommand(CLI::App& app, int& result) {
    auto args = std::make_shared<CompareArgs>();
    CLI::App* cmd = app.add_subcommand(
        "compare",
        "Compare two bake directories (or two .exr/.glb/.ply/probes.csv files); exit 0 within tolerance, 1 beyond, "
        "2 not comparable");
    cmd->add_option("a", args->a, "Reference bake directory or file")->required();
    cmd->add_option("b", args->b, "Bake directory or file to check")->required();
    cmd->add_option("--rel-tol", args->options.rel_tol, "Relative tolerance: |a-b| <= T * max(|a|,|b|) passes")
        ->check(nonNegativeReal())
        ->capture_default_str();
    cmd->add_option("--abs-tol", args->options.abs_tol, "Absolute tolerance: |a-b| <= T passes")
        ->check(nonNegativeReal())
        ->capture_default_str();
    cmd->add_flag("--quiet", args->quiet, "Print nothing when within tolerance");
    cmd->callback([args, &result] { result = runCompare(*args); });
}

}  // namespace radbake::cli
