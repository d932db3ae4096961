// radbake: the command-line program. Subcommands live in cmd_<name>.cpp.
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "core/ranks.h"

namespace radbake::cli {

void printDiagnosticsToStderr(Diagnostics& diagnostics) {
    diagnostics.sink = [](const Diagnostic& d) { std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str()); };
}

}  // namespace radbake::cli

int main(int argc, char** argv) {
    using namespace radbake::cli;
    CLI::App app{"radbake " RADBAKE_VERSION ": offline hierarchical-radiosity lighting baker"};
    app.set_version_flag("--version", std::string("radbake ") + RADBAKE_VERSION);
    app.require_subcommand(1);
    app.get_formatter()->column_width(40);

    int result = kExitOk;
    addInfoCommand(app, result);
    addBakeCommand(app, result);
    addSolveCommand(app, result);
    addShardCommands(app, result);
    addCompareCommand(app, result);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return kExitUsage;
    }
    // A rank that failed ends the others, which may be waiting for it in an exchange.
    if (result != kExitOk && radbake::Ranks::launchedByMpi()) {
        try {
            radbake::Ranks::world().abortAll(result);
        } catch (const std::exception&) {
        }
    }
    return result;
}
