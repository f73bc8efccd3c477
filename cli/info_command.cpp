// mspline info: topology, geometry and every validation problem of a mesh file.
#include <cstdio>
#include <optional>

#include "cli/command.h"
#include "cli/mesh_report.h"
#include "mspline/io/load_mesh.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/mesh_statistics.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::cli {

namespace {

struct InfoArguments {
  std::string mesh;
  structure::RepairOptions repair;
};

// The kinds of the problems that make the Euler characteristic and the genus unknown.
std::vector<std::string> topologyHiddenBy(const io::LoadedMesh& loaded) {
  std::vector<std::string> kinds;
  for (const auto& problem : loaded.validation.problems)
    if (structure::hidesTopology(problem.kind)) kinds.push_back(problem.kind);
  // OpenMesh can also reject a face whose defect has a kind of its own (a degenerate face
  // repeating a vertex): then every defect is named.
  if (kinds.empty() && !loaded.mesh)
    for (const auto& problem : loaded.validation.problems) kinds.push_back(problem.kind);
  return kinds;
}

Json infoJson(const std::string& path, const io::LoadedMesh& loaded) {
  const auto& validation = loaded.validation;
  const std::vector<std::string> hiddenBy = topologyHiddenBy(loaded);
  Json info;
  info["file"] = path;
  info["valid"] = validation.ok();
  // The soup's counts; on a mesh they equal the mesh's (components: faces connected through
  // shared vertices, so that an unreferenced vertex is not a component of its own).
  info["vertices"] = validation.vertices;
  info["edges"] = validation.edges;
  info["faces"] = validation.faces;
  info["components"] = validation.components;
  // Boundary loops need a manifold mesh; V - E + F and the genus also need every vertex on it.
  std::optional<structure::TopologyReport> topology;
  if (loaded.mesh) topology = structure::analyzeTopology(*loaded.mesh);
  const bool eulerKnown = topology && hiddenBy.empty();
  info["boundaries"] = topology ? Json(topology->boundaryLoops) : Json(nullptr);
  info["euler"] = eulerKnown ? Json(topology->euler) : Json(nullptr);
  info["genus"] = eulerKnown ? Json(topology->genus) : Json(nullptr);
  info["closed"] = topology ? Json(topology->closed) : Json(nullptr);
  if (!eulerKnown) info["topology_unknown_because"] = hiddenBy;
  info["orientable"] = validation.orientable;
  if (loaded.mesh) {
    auto stats = structure::meshStatistics(*loaded.mesh);
    info["bbox_diagonal"] = stats.bboxDiagonal;
    info["min_angle_degrees"] = stats.minAngleDegrees;
    info["median_angle_degrees"] = stats.medianAngleDegrees;
    info["max_dihedral_degrees"] = stats.maxDihedralDegrees;
    info["folded_edges"] = stats.foldedEdges;
  }
  info["problems"] = problemsJson(validation);
  info["warnings"] = loaded.warnings;
  if (!loaded.repairs.empty()) info["repairs"] = repairsJson(loaded.repairs);
  return info;
}

void printText(const Json& info) {
  std::string unknown = "unknown";
  if (info.contains("topology_unknown_because")) {
    unknown += " (";
    for (const auto& kind : info["topology_unknown_because"])
      unknown += (unknown.back() == '(' ? "" : ", ") + kind.get<std::string>();
    unknown += ")";
  }
  auto line = [&unknown](const char* key, const Json& value) {
    std::string text = value.is_string() ? value.get<std::string>() : value.dump();
    if (value.is_number_float()) {
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "%.6g", value.get<double>());
      text = buffer;
    }
    std::printf("%-21s %s\n", key, value.is_null() ? unknown.c_str() : text.c_str());
  };
  for (const char* key : {"file", "vertices", "edges", "faces", "components", "boundaries", "euler",
                          "genus", "closed", "orientable", "bbox_diagonal", "min_angle_degrees",
                          "median_angle_degrees", "max_dihedral_degrees", "folded_edges"}) {
    if (info.contains(key)) line(key, info[key]);
  }
  if (info["problems"].empty()) {
    std::printf("%-21s none\n", "problems");
  } else {
    for (const auto& problem : info["problems"])
      std::printf("problem: %s\n", problem["message"].get<std::string>().c_str());
  }
}

}  // namespace

void addInfoCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<InfoArguments>();
  auto* sub = app.add_subcommand(
      "info",
      "Report vertices, edges, faces, components, boundaries, Euler characteristic, genus and "
      "every validation problem of a mesh (OBJ, OFF, PLY, STL). Exits 2 when the mesh has "
      "problems.");
  sub->add_option("MESH", arguments->mesh, "Mesh file")->required();
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  addRepairFlags(*sub, arguments->repair);
  sub->callback([&command, arguments] {
    command.name = "info";
    command.files = {arguments->mesh};
    command.run = [&command, arguments] {
      io::LoadOptions options;
      options.repair = arguments->repair;
      options.requireValid = false;
      io::LoadedMesh loaded = io::loadMesh(arguments->mesh, options);
      Json info = infoJson(arguments->mesh, loaded);
      addNotes(command, loaded.warnings, loaded.repairs);
      if (!command.json) printText(info);
      if (!loaded.validation.ok()) {
        // main prints the report with the error added under --json.
        command.partialResult = std::move(info);
        throw structure::InputError(loaded.validation.summary());
      }
      if (command.json) printJson(info);
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
