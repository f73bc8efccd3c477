// mspline: the command-line entry point. The one place where failures become exit codes and
// messages: the README's error policy.
#include <cstring>
#include <iostream>
#include <new>
#include <optional>

#include "cli/command.h"
#include "mspline/io/atomic_file.h"
#include "mspline/structure/core/errors.h"

namespace mspline::cli {

void addFairingOptions(CLI::App& sub, double& smoothing, int& correctionRounds) {
  sub.add_option("--smoothing", smoothing,
                 "Fairing weight relative to the data term (default: chosen by hold-out "
                 "validation among 1e-1 .. 1e-7)")
      ->check(CLI::Range(0.0, 1e3));
  sub.add_option("--rounds", correctionRounds, "Parameter correction rounds per fit (default 3)")
      ->check(CLI::Range(0, 50));
}

void printJson(const Json& object) {
  std::cout << object.dump(2, ' ', false, Json::error_handler_t::replace) << std::endl;
}

structure::Progress progressLines(Command& command, bool quiet) {
  return [&command, quiet](const std::string& stage, double fraction) {
    command.stage = stage;
    if (!quiet && fraction >= 1.0) std::cerr << command.name << ": " << stage << std::endl;
  };
}

namespace {

// The message naming the file: as it is when it names a file of the command line already,
// otherwise prefixed with the main input.
std::string namingTheFile(const Command& command, const std::string& message) {
  for (const std::string& file : command.files)
    if (!file.empty() && message.find(file) != std::string::npos) return message;
  if (command.files.empty() || command.files.front().empty()) return message;
  return command.files.front() + ": " + message;
}

void printNotes(const Command& command) {
  for (const std::string& note : command.notes) std::cerr << note << "\n";
  std::cerr << std::flush;
}

int reportError(const Command& command, const char* kind, const std::string& what, int code) {
  const std::string message = namingTheFile(command, what);
  std::cerr << "mspline " << command.name << ": error: " << message << std::endl;
  printNotes(command);
  if (command.json) {
    Json result = command.partialResult.is_object() ? command.partialResult : Json::object();
    result["error"] = {{"kind", kind}, {"message", message}};
    printJson(result);
  }
  return code;
}

int runCommand(Command& command) {
  using namespace structure;
  try {
    // A command's outputs replace their targets together, once it has succeeded.
    std::optional<io::OutputBatch> outputs;
    if (command.outputsTogether) outputs.emplace();
    const int code = command.run();
    if (outputs) outputs->commit();
    printNotes(command);
    return code;
  } catch (const IoError& e) {
    return reportError(command, "io", e.what(), kExitInvalidInput);
  } catch (const TopologyError& e) {
    return reportError(command, "topology", e.what(), kExitInvalidInput);
  } catch (const InputError& e) {
    return reportError(command, "input", e.what(), kExitInvalidInput);
  } catch (const SolverError& e) {
    return reportError(command, "solver", e.what(), kExitComputationFailed);
  } catch (const std::bad_alloc&) {
    const std::string during = command.stage.empty() ? "" : " during " + command.stage;
    return reportError(command, "memory", "out of memory" + during, kExitComputationFailed);
  } catch (const std::exception& e) {
    return reportError(command, "internal", e.what(), kExitComputationFailed);
  }
}

bool jsonRequested(int argc, char** argv) {
  for (int k = 1; k < argc; ++k)
    if (std::strcmp(argv[k], "--json") == 0) return true;
  return false;
}

}  // namespace
}  // namespace mspline::cli

int main(int argc, char** argv) {
  using namespace mspline::cli;
  CLI::App app{
      "mspline: manifold spline modeling on triangle meshes.\n"
      "Exit codes: 0 success, 1 usage error, 2 input to change (the file and the problem named), "
      "3 computation failed (the stage named)."};
  app.set_version_flag("--version", "mspline " MSPLINE_VERSION);
  app.require_subcommand(1);
  Command command;
  addInfoCommand(app, command);
  addRepairCommand(app, command);
  addCutCommand(app, command);
  addFlattenCommand(app, command);
  addVoronoiCommand(app, command);
  addAtlasCommand(app, command);
  addPictureCommand(app, command);
  addSplineCommand(app, command);
  addFitCommand(app, command);
  addCheckCommand(app, command);
  addExportCommand(app, command);
  addCompareOsdCommand(app, command);
  addViewCommand(app, command);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and version on stdout, usage errors on stderr.
    if (app.exit(e) == 0) return kExitSuccess;
    if (jsonRequested(argc, argv))
      printJson({{"error", {{"kind", "usage"}, {"message", e.what()}}}});
    return kExitUsage;
  }
  return runCommand(command);
}
