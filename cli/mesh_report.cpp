#include "cli/mesh_report.h"

namespace mspline::cli {

Json problemsJson(const structure::ValidationReport& report) {
  Json problems = Json::array();
  for (const auto& problem : report.problems)
    problems.push_back({{"kind", problem.kind},
                        {"count", problem.count},
                        {"message", problem.message},
                        {"elements", problem.elements}});
  return problems;
}

Json repairsJson(const std::vector<structure::RepairAction>& actions) {
  Json repairs = Json::array();
  for (const auto& action : actions)
    repairs.push_back(
        {{"repair", action.repair}, {"count", action.count}, {"message", action.message}});
  return repairs;
}

void addNotes(Command& command, const std::vector<std::string>& warnings,
              const std::vector<structure::RepairAction>& actions) {
  for (const auto& warning : warnings) command.notes.push_back("warning: " + warning);
  for (const auto& action : actions) command.notes.push_back("repair: " + action.message);
}

void addRepairFlags(CLI::App& sub, structure::RepairOptions& options) {
  auto* all = sub.add_flag_callback(
      "--all",
      [&options] {
        options.mergeDuplicateVertices = options.removeDegenerateFaces =
            options.removeDuplicateFaces = options.splitNonManifoldEdges =
                options.splitNonManifoldVertices = options.orientConsistently =
                    options.keepLargestComponent = options.dropUnreferencedVertices = true;
      },
      "Run every repair below");
  sub.add_flag("--merge-duplicate-vertices", options.mergeDuplicateVertices,
               "Merge vertices with identical coordinates");
  sub.add_flag("--remove-degenerate-faces", options.removeDegenerateFaces,
               "Remove zero-area faces and faces with repeated vertices");
  sub.add_flag("--remove-duplicate-faces", options.removeDuplicateFaces,
               "Remove faces over the same vertices as an earlier face");
  sub.add_flag("--split-non-manifold-edges", options.splitNonManifoldEdges,
               "Give each consistently oriented pair of faces at an edge shared by 3 or more "
               "faces its own copy of the edge; other faces there are detached");
  sub.add_flag("--split-non-manifold-vertices", options.splitNonManifoldVertices,
               "Give every fan of faces at a bow-tie vertex its own vertex");
  sub.add_flag("--orient", options.orientConsistently,
               "Flip faces so each component is consistently oriented");
  sub.add_flag("--keep-largest-component", options.keepLargestComponent,
               "Keep only the component with the most faces");
  sub.add_flag("--drop-unreferenced-vertices", options.dropUnreferencedVertices,
               "Remove vertices no face uses");
  all->group("Repairs");
}

}  // namespace mspline::cli
