#pragma once
// Brings a one-vertex system of loops to the canonical form a1 b1 a1^-1 b1^-1 ... a_g b_g a_g^-1
// b_g^-1 by cut-and-paste, and reads the word of the polygon a loop system cuts the surface into.
#include <vector>

#include "mspline/structure/topology/growing_surface.h"
#include "mspline/structure/topology/one_vertex_loops.h"
#include "mspline/structure/topology/open_surface.h"

namespace mspline::structure {

/// Which loop each boundary segment of the surface opened along a loop system copies, and in which
/// direction.
struct LoopWord {
  /// Per segment, the index of its loop in LoopSystem::loops.
  std::vector<int> loop;
  /// Per segment, +1 when it runs along its loop's vertex sequence, -1 when against it.
  std::vector<int> sign;
};

/// The word of `opened`, the surface opened along `system`'s loops (see openSurface).
/// MSPLINE_ASSERT that every segment is a whole copy of one loop.
LoopWord readLoopWord(const LoopSystem& system, const OpenedSurface& opened);

/// Rotation r at which the word reads as consecutive canonical blocks x y x^-1 y^-1, or -1.
long canonicalRotation(const LoopWord& word);

/// Brings the one-vertex system to canonical form. For an interleaved pair x A y B x^-1 C y^-1 D
/// (read from the corner before x) two cut-and-paste moves give A D w^-1 z^-1 w z C B, which adds
/// the canonical block w^-1 z^-1 w z and keeps A..D (hence the blocks already made) intact.
/// Gives up, leaving a one-vertex but non-canonical system, should a round add no block.
/// Splits edges (rarely refines) of `work`'s surface; throws TopologyError past the budget.
void canonicalizeLoops(GrowingSurface& work, LoopSystem& system);

}  // namespace mspline::structure
