#pragma once
// A cut graph: a set of mesh edges along which the surface opens into one topological disk.
#include <vector>

#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/topology/homotopy_basis.h"

namespace mspline::structure {

struct CutGraph {
  /// Sorted indices of the mesh edges to cut along; empty when the surface already is a disk.
  std::vector<int> edges;
};

/// The union of the basis loops plus the tree paths from the base to each boundary anchor, with
/// dangling trees pruned (a leaf may remain only on the boundary). A closed sphere gets a slit of
/// two edges at the base, the shortest cut a simplicial disk can come from.
CutGraph computeCutGraph(const TriMesh& mesh, const HomotopyBasis& basis);

}  // namespace mspline::structure
