#pragma once
// Closes every boundary loop of a surface with a triangulated disk (a cap), so that algorithms
// that need a closed surface (flattening with quantized cones, splines) can run on scans with
// holes; the cap flags let a caller fit only to the scan's own data and trim the caps off later.
#include <cstddef>
#include <vector>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct CapOptions {
  /// Target edge length of the cap triangles relative to the mean edge length of the loop they
  /// close: the spacing of the cap's rings and of the vertices on each ring.
  double edgeLengthFactor = 1.0;
  /// 2: the cap minimizes the umbrella bi-Laplacian energy with the scan fixed, so it continues
  /// the surface's tangent plane across the loop and bulges smoothly; 1: the umbrella Laplacian
  /// (a membrane spanning the loop, no bulge). A cap whose only vertex is its centre (a loop of
  /// up to 9 edges at factor 1) and whose angle sum order 2 leaves below pi (a spike) takes the
  /// mean of its loop.
  int fairingOrder = 2;
};

struct CappedSurface {
  /// The closed surface: the input's vertices and faces with their indices (0..n-1, 0..F-1),
  /// then the cap vertices and the cap faces, cap by cap.
  TriMesh mesh;
  /// Per vertex of `mesh`: 1 when it was created by a cap (the loop vertices are the input's, 0).
  std::vector<char> capVertex;
  /// Per face of `mesh`: 1 when it belongs to a cap.
  std::vector<char> capFace;
  /// Number of caps: the input's boundary loops.
  std::size_t caps = 0;
  /// Per cap: the number of edges of the boundary loop it closes.
  std::vector<std::size_t> loopLengths;
};

/// Caps every boundary loop of `mesh`. A loop of n edges, of length L, is closed by concentric
/// rings shrinking to a centre vertex, as many as make cap edges of about edgeLengthFactor * L / n,
/// zipped together into triangles with the input's orientation; the cap vertices are then faired
/// (see CapOptions::fairingOrder). A closed mesh is returned unchanged with zero caps. Throws
/// InputError for options out of range and TopologyError for a loop that cannot be capped: one
/// with fewer than 3 edges, or a boundary vertex on two loops (or twice on one), named by index.
CappedSurface capHoles(const TriMesh& mesh, const CapOptions& options = {});

/// The capped surface split at its edge midpoints (subdivideMidpoint, structure/mesh/subdivide.h):
/// a face is a cap face when its parent is, a midpoint is a cap vertex when both faces at its edge
/// are cap faces, and every loop has twice as many edges.
CappedSurface subdivideMidpoint(const CappedSurface& capped);

}  // namespace mspline::structure
