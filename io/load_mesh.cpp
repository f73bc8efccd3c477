#include "mspline/io/load_mesh.h"

#include <algorithm>

#include "mspline/io/read_mesh.h"
#include "mspline/structure/core/errors.h"

namespace mspline::io {

namespace {

bool anyRepairRequested(const structure::RepairOptions& r) {
  return r.mergeDuplicateVertices || r.removeDegenerateFaces || r.removeDuplicateFaces ||
         r.splitNonManifoldEdges || r.splitNonManifoldVertices || r.orientConsistently ||
         r.keepLargestComponent || r.dropUnreferencedVertices;
}

// OpenMesh can hold the faces unless a problem prevents a manifold mesh; the others (several
// components, unreferenced vertices, thin faces) leave a mesh whose geometry can be reported.
bool structureAllowsMesh(const structure::ValidationReport& report) {
  return std::none_of(report.problems.begin(), report.problems.end(), [](const auto& problem) {
    return structure::preventsManifoldMesh(problem.kind);
  });
}

}  // namespace

LoadedMesh loadMesh(const std::string& path, const LoadOptions& options) {
  MeshReadResult read = readMesh(path);
  LoadedMesh loaded;
  loaded.warnings = std::move(read.warnings);
  if (anyRepairRequested(options.repair)) {
    structure::RepairResult repaired = structure::repair(std::move(read.soup), options.repair);
    loaded.soup = std::move(repaired.soup);
    loaded.repairs = std::move(repaired.actions);
  } else {
    loaded.soup = std::move(read.soup);
  }
  loaded.validation = structure::validate(loaded.soup);
  if (options.requireValid && !loaded.validation.ok())
    throw structure::InputError(loaded.validation.summary());
  if (structureAllowsMesh(loaded.validation)) {
    try {
      loaded.mesh = structure::toTriMesh(loaded.soup);
    } catch (const structure::TopologyError&) {
      // Validation already names the defect; the caller reports it.
      if (loaded.validation.ok()) throw;
    }
  }
  return loaded;
}

}  // namespace mspline::io
