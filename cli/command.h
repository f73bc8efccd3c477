#pragma once
// What every subcommand shares: exit codes, the chosen subcommand, and JSON output.
#include <CLI/CLI.hpp>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mspline/structure/core/progress.h"

namespace mspline::cli {

using Json = nlohmann::ordered_json;

/// The command's exit codes (documented in `mspline --help` and the README): main decides them
/// from the kind of error alone.
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
  /// The files named on the command line, the main input first (set by the subcommand's
  /// callback): main prefixes an error message that names none of them with the first.
  std::vector<std::string> files;
  /// Runs the command and returns its exit code; throws mspline errors for main to report.
  std::function<int()> run;
  /// With --json: what a failing command had found before it failed; main adds "error" to it.
  Json partialResult;
  /// Whether the command's output files are named together when it succeeds (io::OutputBatch);
  /// false for the interactive viewer, whose saves and autosaves must land when they are made.
  bool outputsTogether = true;
  /// The stage running (the last progress message, quiet or not): named when memory runs out.
  std::string stage;
  /// Warnings and repair notes for stderr, printed by main after the command's outcome so that
  /// the first stderr line of a failed run is its error.
  std::vector<std::string> notes;
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

/// Prints one JSON object on stdout. Bytes that are not UTF-8 (from file names or file contents)
/// become U+FFFD: the output stays valid JSON.
void printJson(const Json& object);

/// `--smoothing` and `--rounds`: the fitting engine's fairing weight (default: hold-out
/// validation) and parameter correction rounds (default 3), shared by `fit` and `spline`.
void addFairingOptions(CLI::App& sub, double& smoothing, int& correctionRounds);

/// Progress as lines "<command>: <message>" on stderr, one per message (a stage reported at
/// fraction 1); nothing when `quiet`. Every message becomes command.stage.
structure::Progress progressLines(Command& command, bool quiet);

}  // namespace mspline::cli
