#pragma once
// Topological invariants of a manifold triangle mesh.
#include <cstddef>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct TopologyReport {
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t faces = 0;
  /// Connected components.
  std::size_t components = 0;
  /// Boundary loops (cycles of boundary halfedges).
  std::size_t boundaryLoops = 0;
  /// V - E + F.
  long euler = 0;
  /// Sum of the components' genera: (2 * components - euler - boundaryLoops) / 2.
  long genus = 0;
  /// No boundary loops.
  bool closed = true;
  /// Always true for a TriMesh (OpenMesh stores one consistent orientation per component).
  bool orientable = true;
};

TopologyReport analyzeTopology(const TriMesh& mesh);

}  // namespace mspline::structure
