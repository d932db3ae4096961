#pragma once
// Each subcommand registers itself on the app and returns the exit code through `result`.
#include <CLI/CLI.hpp>

#include "core/diagnostics.h"

namespace radbake::cli {

// Exit statuses shared by every command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitInputError = 1;  // unreadable or invalid input (also: compare found differences)
inline constexpr int kExitUsage = 2;       // bad command line

// Prints every diagnostic to stderr as it is reported.
void printDiagnosticsToStderr(Diagnostics& diagnostics);

void addInfoCommand(CLI::App& app, int& result);
void addBakeCommand(CLI::App& app, int& result);
void addSolveCommand(CLI::App& app, int& result);
void addShardCommands(CLI::App& app, int& result);  // gather, merge
void addCompareCommand(CLI::App& app, int& result);

}  // namespace radbake::cli
