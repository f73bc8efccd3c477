#pragma once
// What every subcommand shares: exit codes, the chosen subcommand, and JSON output.
#include <CLI/CLI.hpp>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "mspline/structure/core/progress.h"

namespace mspline::cli {

using Json = nlohmann::ordered_json;

/// The command's exit codes (documented in `mspline --help`).
enum ExitCode : int {
  kExitSuccess = 0,
  kExitUsage = 1,
  kExitInvalidInput = 2,
  kExitComputationFailed = 3,
};

/// The subcommand selected on the command line: set by its CLI11 callback, run by main.
struct Command {
  std::string name;
  /// True when the user asked for --json: results (and errors) go to stdout as one JSON object.
  bool json = false;
  /// Runs the command and returns its exit code; throws mspline errors for main to report.
  std::function<int()> run;
  /// With --json: what a failing command had found before it failed; main adds "error" to it.
  Json partialResult;
};

void addInfoCommand(CLI::App& app, Command& command);
void addRepairCommand(CLI::App& app, Command& command);
void addCutCommand(CLI::App& app, Command& command);
void addFlattenCommand(CLI::App& app, Command& command);
void addVoronoiCommand(CLI::App& app, Command& command);
void addAtlasCommand(CLI::App& app, Command& command);
void addPictureCommand(CLI::App& app, Command& command);
void addSplineCommand(CLI::App& app, Command& command);
void addCheckCommand(CLI::App& app, Command& command);
void addExportCommand(CLI::App& app, Command& command);
void addCompareOsdCommand(CLI::App& app, Command& command);
void addFitCommand(CLI::App& app, Command& command);
void addViewCommand(CLI::App& app, Command& command);

/// Prints one JSON object on stdout.
void printJson(const Json& object);

/// Progress as lines "<command>: <message>" on stderr, one per message (a stage reported at
/// fraction 1); nothing when `quiet`.
structure::Progress progressLines(const std::string& command, bool quiet);

}  // namespace mspline::cli
