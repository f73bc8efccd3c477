#pragma once
// Cuts a connected orientable surface into one topological disk. Closed surfaces of genus g >= 1
// are cut along a one-vertex system of 2g loops, so the disk is a 4g-gon (a polygonal schema);
// other surfaces are cut along the general cut graph (see cut_graph.h).
#include <cstddef>
#include <string>
#include <vector>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct CutOptions {
  /// Base vertex of the homotopy basis (and so of the general cut graph); -1 chooses one (see
  /// HomotopyBasisOptions). The one-vertex schema's common vertex is chosen far from the basis.
  int baseVertex = -1;
  /// Closed surfaces of genus >= 1: cut along 2g loops meeting at one vertex (4g boundary
  /// segments). When false, every surface is cut along the general cut graph on original edges.
  bool oneVertexSchema = true;
  /// With oneVertexSchema: bring the schema to canonical form a1 b1 a1^-1 b1^-1 ... a_g b_g
  /// a_g^-1 b_g^-1 by replacing loops.
  bool canonicalSchema = true;
  /// Whole-mesh 1-to-4 midpoint refinements allowed when the loops do not fit in the mesh.
  int maxRefinements = 3;
  /// Give up (SolverError) when the surface being cut would grow past maxGrowth times the
  /// input's vertex count (at least 100000 vertices): routing 4g loops out of one vertex on a
  /// coarse mesh of high genus needs ever more edge splits.
  std::size_t maxGrowth = 64;
};

/// One stretch of the disk boundary: a copy of one cut curve or a piece of an original boundary.
struct BoundarySegment {
  /// Positions in CutResult::boundaryLoop of the first and the last vertex; the segment runs
  /// forward, cyclically, from `begin` to `end` (begin == end: the whole loop).
  std::size_t begin = 0;
  std::size_t end = 0;
  /// Index into CutResult::curves of the curve this segment copies.
  std::size_t curve = 0;
  /// +1 when the segment runs along the curve's vertex sequence, -1 when against it.
  int orientation = 1;
  /// Whether the curve lies on the surface's boundary (appears once) rather than on the cut
  /// (appears twice, once per side).
  bool boundary = false;
};

struct CutResult {
  /// Copies both meshes; the other fields start empty.
  CutResult(const TriMesh& diskMesh, const TriMesh& surfaceMesh)
      : disk(diskMesh), surface(surfaceMesh) {}

  /// The disk. Face f of the disk is face f of `surface`, with the same orientation.
  TriMesh disk;
  /// The surface that was cut: the input, possibly with edges split and/or refined. Vertices
  /// 0..V-1 are the input vertices; new ones (on input edges) follow.
  TriMesh surface;
  /// Genus of the input.
  int genus = 0;
  /// For each disk vertex, the vertex of `surface` it copies.
  std::vector<int> surfaceVertex;
  /// For each disk vertex, the input vertex it copies, or -1 for a vertex added by a split or a
  /// refinement (such vertices lie on input edges or faces, so the disk is the input surface).
  std::vector<int> inputVertex;
  /// Whole-mesh midpoint refinements and points added on edges (the one-vertex schema's loops cross
  /// edges there, its canonical form splits edges to route new loops; refinement is rare: bounded
  /// meshes where a cut path cannot avoid touching another boundary).
  int refinements = 0;
  int edgeSplits = 0;
  /// Sorted indices of the edges of `surface` that were cut.
  std::vector<int> cutEdges;
  /// The disk's boundary as a cyclic sequence of disk vertex indices, in the direction of its
  /// boundary halfedges (empty only if the disk had no boundary, which never happens).
  std::vector<int> boundaryLoop;
  /// The boundary split at copies of branch vertices (cut or boundary degree != 2), in order.
  std::vector<BoundarySegment> segments;
  /// Surface vertex sequences of the curves, each named by `curveNames`; a closed loop lists its
  /// start vertex at both ends.
  std::vector<std::vector<int>> curves;
  /// Names: a_k/b_k for a canonical schema, x_k for the loops of a non-canonical one-vertex
  /// schema, c_k for chains of a general cut graph, d_k for pieces of the original boundary.
  std::vector<std::string> curveNames;
  /// The segments' names in order from position 0, inverses marked "^-1": "a1 b1 a1^-1 b1^-1"
  /// for a torus, "c1 d1 c1^-1 ..." for a bounded surface.
  std::string word;
  /// The surface vertex all loops meet at (one-vertex schema) or the basis base vertex.
  int baseVertex = -1;
  /// Whether the cut is a one-vertex system of 2g loops (4g segments), and whether its word is
  /// the canonical a1 b1 a1^-1 b1^-1 ... (never claimed for spheres and bounded surfaces).
  bool oneVertexSchema = false;
  bool canonical = false;
  /// Empty, or why the one-vertex schema asked to be canonical is not (canonical form outgrew
  /// maxGrowth or maxRefinements; the schema is then the one built, with 4g sides).
  std::string notCanonicalBecause;
  /// Computed on `disk`: V - E + F, number of boundary loops and components (1, 1, 1 for a disk).
  long diskEuler = 0;
  std::size_t diskBoundaryLoops = 0;
  std::size_t diskComponents = 0;
};

/// Cuts the surface to a disk. Throws TopologyError for empty, non-manifold or disconnected
/// meshes, SolverError when the cut does not fit within maxRefinements refinements or maxGrowth.
/// The general cut (bounded surfaces, spheres, oneVertexSchema off) runs along input edges
/// unless a refinement was needed; the one-vertex schema always adds vertices: its loops cross
/// input faces (points on input edges, the common vertex inside a face), which bounds its size
/// by the input's times the genus, while canonical form may outgrow the budget and is then
/// given up (CutResult::notCanonicalBecause).
CutResult cutToDisk(const TriMesh& mesh, const CutOptions& options = {});

}  // namespace mspline::structure
