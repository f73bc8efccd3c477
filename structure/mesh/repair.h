#pragma once
// Opt-in repairs for scanned meshes. Each repair is reported so nothing changes silently.
#include <cstddef>
#include <string>
#include <vector>

#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::structure {

struct RepairOptions {
  /// Merge vertices with bit-identical coordinates (before anything else).
  bool mergeDuplicateVertices = false;
  /// Remove faces with repeated vertices, fewer than 3 vertices or (almost) zero area
  /// (isDegenerateFace with degenerateTolerance).
  bool removeDegenerateFaces = false;
  /// Remove faces that use the same vertex set as an earlier face.
  bool removeDuplicateFaces = false;
  /// Split edges shared by 3 or more faces so that each consistently oriented pair of faces keeps
  /// a copy of its own and every other face is detached there (splitNonManifoldEdges).
  bool splitNonManifoldEdges = false;
  /// Split vertices whose faces form several fans (bow-ties) into one vertex per fan.
  bool splitNonManifoldVertices = false;
  /// Flip faces so that each patch of faces connected through manifold edges agrees with its
  /// first face; non-orientable patches are left as they are (the action's message says so).
  bool orientConsistently = false;
  /// Keep only the component (faces sharing vertices) with the most faces, the first on ties.
  bool keepLargestComponent = false;
  /// Drop vertices that no face references (runs last, after the other repairs).
  bool dropUnreferencedVertices = false;
  /// Tolerance for removeDegenerateFaces, as in ValidationOptions.
  double degenerateTolerance = 1e-12;
};

/// What one repair changed.
struct RepairAction {
  /// The RepairOptions field's name in snake_case, e.g. "merge_duplicate_vertices".
  std::string repair;
  /// How many elements it changed (vertices merged, faces removed, vertices split, ...).
  std::size_t count = 0;
  /// One line for the user.
  std::string message;
};

struct RepairResult {
  /// The repaired soup (vertex and face indices are renumbered where elements were removed).
  PolygonSoup soup;
  /// One entry per requested repair, in the order they ran, also when it changed nothing.
  std::vector<RepairAction> actions;
};

/// Runs the requested repairs in the order of RepairOptions' fields, keeping cornerUVs parallel.
/// Throws InputError when a face uses an out-of-range vertex index (no repair can guess it).
RepairResult repair(PolygonSoup soup, const RepairOptions& options);

}  // namespace mspline::structure
