#pragma once
// Checks a polygon soup for every defect that stops it from being a clean manifold triangle mesh.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "structure/polygon_soup.h"

namespace mspline::structure {

/// One kind of defect found in the input, with the offending elements.
struct MeshProblem {
  /// Stable identifier, snake_case: face_index_out_of_range, too_few_face_vertices,
  /// non_finite_coordinate, non_manifold_edge, non_manifold_vertex, degenerate_face,
  /// duplicate_face, inconsistent_orientation, unreferenced_vertex, multiple_components,
  /// empty_mesh.
  std::string kind;
  /// How many elements have this defect.
  std::size_t count = 0;
  /// Indices of the first offending elements (faces or vertices, as `kind` says), at most
  /// ValidationOptions::maxListed of them.
  std::vector<std::int64_t> elements;
  /// One line naming the source, the defect, the count and the first element indices.
  std::string message;
};

struct ValidationOptions {
  /// A face is degenerate when twice its area is at most this times its longest edge squared,
  /// i.e. when the sine of its largest angle is (almost) zero.
  double degenerateTolerance = 1e-12;
  /// How many element indices a problem lists.
  std::size_t maxListed = 10;
};

struct ValidationReport {
  /// Every defect found, one entry per kind, in a fixed order; empty for a clean mesh.
  std::vector<MeshProblem> problems;
  /// Counts on the soup as given (edges are distinct unordered vertex pairs of valid faces).
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t edges = 0;
  /// Connected components of faces sharing vertices (unreferenced vertices not counted).
  std::size_t components = 0;
  /// Whether the faces can be oriented consistently (meaningful when edges are manifold).
  bool orientable = true;

  bool ok() const { return problems.empty(); }
  /// The first problem's message followed by the other kinds, for a one-line error.
  std::string summary() const;
};

/// Runs every check; never throws on bad content (that is what the report is for).
ValidationReport validate(const PolygonSoup& soup, const ValidationOptions& options = {});

}  // namespace mspline::structure
