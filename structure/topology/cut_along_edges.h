#pragma once
// Opens a surface along a set of its edges by duplicating vertices.
#include <vector>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct CutMesh {
  /// The opened mesh. Face f of it is face f of the surface (same corners, same orientation).
  TriMesh mesh;
  /// For each vertex of `mesh` the surface vertex it copies; copies of one vertex are numbered
  /// consecutively and vertices appear in the surface's order.
  std::vector<int> sourceVertex;
};

/// Gives every surface vertex one copy per wedge of incident faces between consecutive cut or
/// boundary edges, and builds the faces on the copies. Throws InternalError if the result cannot
/// be represented (e.g. a cut edge whose ends are both cut leaves would become a double edge).
CutMesh cutAlongEdges(const TriMesh& surface, const std::vector<int>& cutEdges);

}  // namespace mspline::structure
