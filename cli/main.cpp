// mspline: the command-line entry point. Maps every failure to an exit code and one clear line.
#include <iostream>
#include <new>

#include "cli/command.h"
#include "mspline/io/atomic_file.h"
#include "mspline/structure/core/errors.h"

namespace mspline::cli {

void printJson(const Json& object) {
  std::cout << object.dump(2) << std::endl;
}

structure::Progress progressLines(const std::string& command, bool quiet) {
  if (quiet) return {};
  return [command](const std::string& stage, double fraction) {
    if (fraction >= 1.0) std::cerr << command << ": " << stage << std::endl;
  };
}

namespace {

int reportError(const Command& command, const char* kind, const std::string& message, int code) {
  std::cerr << "mspline " << command.name << ": error: " << message << std::endl;
  if (command.json) {
    Json result = command.partialResult.is_object() ? command.partialResult : Json::object();
    result["error"] = {{"kind", kind}, {"message", message}};
    printJson(result);
  }
  return code;
}

int runCommand(const Command& command) {
  using namespace structure;
  try {
    // A command's outputs replace their targets together, once it has succeeded.
    io::OutputBatch outputs;
    const int code = command.run();
    outputs.commit();
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
    return reportError(command, "memory", "out of memory", kExitComputationFailed);
  } catch (const std::exception& e) {
    return reportError(command, "internal", e.what(), kExitComputationFailed);
  }
}

}  // namespace
}  // namespace mspline::cli

int main(int argc, char** argv) {
  using namespace mspline::cli;
  CLI::App app{
      "mspline: manifold spline modeling on triangle meshes.\n"
      "Exit codes: 0 success, 1 usage error, 2 invalid input, 3 computation failed."};
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
    return app.exit(e) == 0 ? kExitSuccess : kExitUsage;
  }
  return runCommand(command);
}
