#pragma once
// The boundary loops of a mesh, walked along its boundary halfedges.
#include <vector>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

/// Each boundary loop as the vertices its boundary halfedges leave, in their direction (vertex k
/// to k + 1), which runs against the orientation of the faces beside it.
std::vector<std::vector<TriMesh::VertexHandle>> boundaryLoops(const TriMesh& mesh);

}  // namespace mspline::structure
