// mspline repair: runs the requested repairs and writes the result only if it is then valid.
#include <iostream>

#include "cli/command.h"
#include "cli/mesh_report.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/read_mesh.h"
#include "mspline/io/write_mesh.h"
#include "mspline/structure/core/errors.h"

namespace mspline::cli {

namespace {

struct RepairArguments {
  std::string mesh;
  std::string output;
  structure::RepairOptions repair;
};

}  // namespace

void addRepairCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<RepairArguments>();
  auto* sub = app.add_subcommand(
      "repair",
      "Apply the chosen repairs and write the mesh. Nothing is written unless the repaired mesh "
      "passes validation.");
  sub->add_option("MESH", arguments->mesh, "Mesh file to repair")->required();
  sub->add_option("-o,--output", arguments->output, "Output mesh (OBJ, OFF, PLY or STL)")
      ->required();
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  addRepairFlags(*sub, arguments->repair);
  sub->callback([&command, arguments] {
    command.name = "repair";
    command.files = {arguments->mesh, arguments->output};
    command.run = [&command, arguments] {
      io::meshFormatFromPath(arguments->output);  // fail before the work, not after
      io::LoadOptions options;
      options.repair = arguments->repair;
      options.requireValid = false;
      io::LoadedMesh loaded = io::loadMesh(arguments->mesh, options);
      addNotes(command, loaded.warnings, loaded.repairs);
      if (!loaded.validation.ok()) {
        // Every defect left, each with its count and first elements: what the repairs cannot mend.
        std::string left;
        for (const auto& problem : loaded.validation.problems)
          left += (left.empty() ? "" : "; ") + problem.message;
        command.partialResult = {{"file", arguments->mesh},
                                 {"repairs", repairsJson(loaded.repairs)},
                                 {"problems", problemsJson(loaded.validation)}};
        throw structure::InputError("after the requested repairs: " + left + " (nothing written)");
      }
      io::writeMesh(arguments->output, loaded.soup);
      if (command.json) {
        printJson({{"file", arguments->mesh},
                   {"output", arguments->output},
                   {"vertices", loaded.validation.vertices},
                   {"faces", loaded.validation.faces},
                   {"repairs", repairsJson(loaded.repairs)}});
      } else {
        std::cout << "wrote " << arguments->output << " (" << loaded.validation.vertices
                  << " vertices, " << loaded.validation.faces << " faces)" << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
