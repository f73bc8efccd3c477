#pragma once
// JSON and text renderings of validation problems and repairs, shared by the mesh commands.
#include <vector>

#include "cli/command.h"
#include "mspline/structure/mesh/repair.h"
#include "mspline/structure/mesh/validate.h"

namespace mspline::cli {

Json problemsJson(const structure::ValidationReport& report);
Json repairsJson(const std::vector<structure::RepairAction>& actions);

/// Adds warnings and repair actions to the notes main prints on stderr (information, not results).
void addNotes(Command& command, const std::vector<std::string>& warnings,
              const std::vector<structure::RepairAction>& actions);

/// Adds the repair flags (--merge-duplicate-vertices, ..., --all) to a subcommand.
void addRepairFlags(CLI::App& sub, structure::RepairOptions& options);

}  // namespace mspline::cli
