#pragma once
// Greedy shortest homotopy basis (Erickson & Whittlesey 2005) by tree-cotree decomposition.
// Boundary loops are treated as capped by one virtual face each, so that a surface of genus g with
// b boundaries yields 2g loops; the boundaries are reported separately.
#include <cstddef>
#include <vector>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct HomotopyBasisOptions {
  /// Vertex all loops pass through; -1 chooses one: the lowest-index boundary vertex of a bounded
  /// surface (so a disk needs no cut at all), vertex 0 of a closed one.
  int baseVertex = -1;
};

struct HomotopyBasis {
  /// The base vertex every loop starts and ends at.
  int baseVertex = -1;
  /// Genus of the surface (number of loops / 2).
  int genus = 0;
  /// 2g closed vertex sequences, front() == back() == baseVertex; consecutive vertices share an
  /// edge. A loop may run out and back along a shared tree prefix (a "stick") near the base.
  std::vector<std::vector<int>> loops;
  /// Length of each loop (sum of its edge lengths, sticks counted twice).
  std::vector<double> lengths;
  /// For each loop the edge (index) outside both spanning trees that closes it.
  std::vector<int> leftoverEdges;
  /// Shortest-path tree: parent vertex of each vertex (-1 for the base) and distance from the base.
  /// On a surface with boundary, entering a boundary vertex adds a penalty (the total edge length)
  /// to the distance, so that paths and loops avoid the boundary where they can.
  std::vector<int> parent;
  std::vector<double> distance;
  /// Boundary loops as cyclic vertex sequences in the direction of the boundary halfedges.
  std::vector<std::vector<int>> boundaryLoops;
  /// For each boundary loop, its vertex closest to the base (where the cut graph reaches it).
  std::vector<int> boundaryAnchors;
};

/// Throws TopologyError when the mesh is empty, has several components, isolated vertices or
/// non-manifold vertices.
void requireConnectedManifold(const TriMesh& mesh);

/// Computes the greedy homotopy basis. Throws TopologyError as requireConnectedManifold does,
/// InputError for a base vertex out of range.
HomotopyBasis computeHomotopyBasis(const TriMesh& mesh, const HomotopyBasisOptions& options = {});

/// Vertices from the base to `v` along the shortest-path tree (front() is the base).
std::vector<int> treePath(const HomotopyBasis& basis, int v);

}  // namespace mspline::structure
