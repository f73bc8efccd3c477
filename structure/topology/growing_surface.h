#pragma once
// The surface a cut to a disk is routed on (see cut_to_disk.h): it grows by single edge splits and
// whole-mesh midpoint refinements within a budget. Also the edge helpers the cut stages share.
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

/// An undirected edge named by its two vertices, the smaller index first (see edgeKey).
using VertexPair = std::pair<int, int>;

/// The VertexPair of the edge joining a and b, whichever order they come in.
VertexPair edgeKey(int a, int b);

/// Index of the edge joining vertices a and b; MSPLINE_ASSERT that there is one.
int edgeBetween(const TriMesh& mesh, int a, int b);

/// Indices of the edges along vertex paths (consecutive vertices adjacent), in path order.
std::vector<int> edgesOfPaths(const TriMesh& mesh, const std::vector<std::vector<int>>& paths);

/// The surface being modified and what was done to it. The mesh lives behind a pointer so that
/// refining replaces it without assigning one OpenMesh mesh to another.
struct GrowingSurface {
  /// The current surface: the input with the splits and refinements so far.
  std::unique_ptr<TriMesh> surface;
  /// Whole-mesh refinements and single edge splits applied so far.
  int refinements = 0;
  int edgeSplits = 0;
  /// Budget: refineSurface throws past maxRefinements, checkGrowth past maxVertices.
  int maxRefinements = 0;
  std::size_t maxVertices = 0;
};

/// Splits edge (a, b) at its midpoint (both incident triangles split in two) and counts the
/// split; returns the new vertex. The geometry does not change.
int splitEdge(GrowingSurface& work, int a, int b);

/// Throws SolverError once the surface has grown past maxVertices.
void checkGrowth(const GrowingSurface& work);

/// Replaces the surface by its midpoint subdivision and rewrites `paths` (vertex paths on the old
/// surface) as the same paths on the new one. Throws SolverError past maxRefinements.
void refineSurface(GrowingSurface& work, std::vector<std::vector<int>>& paths);

}  // namespace mspline::structure
