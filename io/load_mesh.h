#pragma once
// The one way commands turn a file into a mesh: read, optionally repair, validate, build.
#include <optional>
#include <string>
#include <vector>

#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/mesh/repair.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/mesh/validate.h"

namespace mspline::io {

struct LoadOptions {
  /// Repairs to run before validation (all off by default: input is never changed silently).
  structure::RepairOptions repair;
  /// Throw InputError (with the validation summary) when validation finds any problem.
  bool requireValid = true;
};

struct LoadedMesh {
  /// The soup after the requested repairs.
  structure::PolygonSoup soup;
  /// Reader warnings (e.g. triangulated polygons).
  std::vector<std::string> warnings;
  /// What each requested repair changed.
  std::vector<structure::RepairAction> repairs;
  /// Validation of the repaired soup.
  structure::ValidationReport validation;
  /// The manifold mesh, present when the soup's structure allows building one (always when
  /// validation passed).
  std::optional<structure::TriMesh> mesh;
};

LoadedMesh loadMesh(const std::string& path, const LoadOptions& options = {});

}  // namespace mspline::io
