#pragma once
// Opens a surface along a set of edges and reads the boundary of the result as segments between
// copies of branch vertices: the step every cut to a disk (see cut_to_disk.h) ends with.
#include <cstddef>
#include <vector>

#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/topology/cut_along_edges.h"

namespace mspline::structure {

/// The surface cut along a set of edges, with its boundary read off.
struct OpenedSurface {
  /// The opened mesh and, for each of its vertices, the surface vertex it copies.
  CutMesh cut;
  /// Sorted, distinct indices of the surface edges that were cut.
  std::vector<int> cutEdges;
  /// The (first) boundary loop of the opened mesh, in the direction of its boundary halfedges,
  /// rotated to start at a segment start; empty when the opened mesh has no boundary.
  std::vector<int> boundaryLoop;
  /// Segment start positions in boundaryLoop, increasing; segment k ends where k+1 starts.
  std::vector<std::size_t> segmentBegins;
};

/// Cuts `surface` along `cutEdges` (any order, repeats allowed) and splits the (first) boundary
/// loop of the result at copies of branch vertices: those where the number of cut and boundary
/// edges is not 2.
OpenedSurface openSurface(const TriMesh& surface, std::vector<int> cutEdges);

/// The surface vertices of segment k, from its first to its last vertex (the start vertex at both
/// ends when the segment is the whole loop).
std::vector<int> segmentVertices(const OpenedSurface& opened, std::size_t k);

}  // namespace mspline::structure
