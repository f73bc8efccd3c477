// mspline info: topology, geometry and every validation problem of a mesh file.
#include <cstdio>

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

Json infoJson(const std::string& path, const io::LoadedMesh& loaded) {
  const auto& validation = loaded.validation;
  Json info;
  info["file"] = path;
  info["valid"] = validation.ok();
  if (loaded.mesh) {
    auto topology = structure::analyzeTopology(*loaded.mesh);
    auto stats = structure::meshStatistics(*loaded.mesh);
    info["vertices"] = topology.vertices;
    info["edges"] = topology.edges;
    info["faces"] = topology.faces;
    info["components"] = topology.components;
    info["boundaries"] = topology.boundaryLoops;
    info["euler"] = topology.euler;
    info["genus"] = topology.genus;
    info["closed"] = topology.closed;
    info["orientable"] = validation.orientable;
    info["bbox_diagonal"] = stats.bboxDiagonal;
    info["min_angle_degrees"] = stats.minAngleDegrees;
    info["median_angle_degrees"] = stats.medianAngleDegrees;
  } else {
    // Without a manifold mesh only the soup's counts are meaningful.
    info["vertices"] = validation.vertices;
    info["edges"] = validation.edges;
    info["faces"] = validation.faces;
    info["components"] = validation.components;
    info["boundaries"] = nullptr;
    info["euler"] = static_cast<long>(validation.vertices) - static_cast<long>(validation.edges) +
                    static_cast<long>(validation.faces);
    info["genus"] = nullptr;
    info["closed"] = nullptr;
    info["orientable"] = validation.orientable;
  }
  info["problems"] = problemsJson(validation);
  info["warnings"] = loaded.warnings;
  if (!loaded.repairs.empty()) info["repairs"] = repairsJson(loaded.repairs);
  return info;
}

void printText(const Json& info) {
  auto line = [](const char* key, const Json& value) {
    std::string text = value.is_string() ? value.get<std::string>() : value.dump();
    if (value.is_number_float()) {
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "%.6g", value.get<double>());
      text = buffer;
    }
    std::printf("%-21s %s\n", key, value.is_null() ? "unknown (invalid mesh)" : text.c_str());
  };
  for (const char* key :
       {"file", "vertices", "edges", "faces", "components", "boundaries", "euler", "genus",
        "closed", "orientable", "bbox_diagonal", "min_angle_degrees", "median_angle_degrees"}) {
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
        command.partialResult = info;
        throw structure::InputError(loaded.validation.summary());
      }
      if (command.json) printJson(info);
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
