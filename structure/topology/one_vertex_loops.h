#pragma once
// A one-vertex system of loops on a closed surface of genus g >= 1: 2g loops meeting only at one
// common vertex, whose complement is one disk (a 4g-gon once the surface is cut along them). The
// loops are routed across the cut graph of a homotopy basis, splitting edges where needed.
#include <vector>

#include "mspline/structure/topology/growing_surface.h"
#include "mspline/structure/topology/homotopy_basis.h"

namespace mspline::structure {

/// 2g loops at one vertex `center`, pairwise disjoint elsewhere, whose complement is a disk.
struct LoopSystem {
  /// The surface vertex every loop starts and ends at.
  int center = -1;
  /// Closed vertex sequences of the surface, front() == back() == center; consecutive vertices
  /// share an edge.
  std::vector<std::vector<int>> loops;
};

/// Builds 2g loops delta_i at one vertex, delta_i crossing the cut graph once, on an edge only
/// basis loop i runs along (once); so delta_i . loop_j = [i == j] and the delta_i are independent
/// in homology, disjoint except at their common vertex: cutting along them leaves one disk.
/// `basis` is the homotopy basis of `work`'s surface as it is on entry (genus >= 1, no boundary).
/// Splits edges and, when the loops do not fit, refines; throws TopologyError past the budget.
LoopSystem buildOneVertexLoops(GrowingSurface& work, const HomotopyBasis& basis);

}  // namespace mspline::structure
