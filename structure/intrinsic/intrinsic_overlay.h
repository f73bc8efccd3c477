#pragma once
// The common subdivision of the input mesh and an intrinsic triangulation reached from it by
// Ptolemy flips (ricci_flips.h): the mesh whose faces are the cells cut out of every input face by
// the intrinsic edges. Each cell is a convex polygon both in its input face and in its intrinsic
// triangle, so the overlay carries the input's 3D positions and the flat metric at once, and every
// point of every input face gets a position in the flat metric.
//
// The correspondence is the one of Gillespie, Springborn and Crane 2021: Euclidean triangles map
// to ideal hyperbolic triangles by projective maps that keep their circumcircles (Klein model),
// a flip re-triangulates an ideal quadrilateral of one hyperbolic surface, and scaling by u moves
// a point with barycentric coordinates b to the one with coordinates proportional to exp(-u) b.
// Input edges and intrinsic edges are hyperbolic geodesics, hence straight in every triangle's
// Klein picture. The flips are replayed one by one on the input, each computed in a picture of its
// quadrilateral inscribed in the unit circle, so no triangle inequality is needed along the way.
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/intrinsic/intrinsic_triangulation.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct IntrinsicOverlay {
  /// The common subdivision, cells split into triangles. Vertices 0 .. n-1 are the input's, in
  /// order, then one vertex per crossing of an input edge with an intrinsic edge, placed on the
  /// input edge.
  TriMesh mesh;
  /// Length of every overlay edge (by edge idx()) in the flat metric of the intrinsic
  /// triangulation at u.
  Eigen::VectorXd edgeLengths;
  /// For every overlay face, the input face and the intrinsic face it lies in.
  std::vector<int> inputFace;
  std::vector<int> intrinsicFace;
  /// For every crossing vertex (overlay vertex n + c), the input edge it lies on.
  std::vector<int> crossingInputEdge;
  /// Number of flips replayed.
  long flips = 0;
  /// max over overlay edges on an intrinsic edge of the difference between the two lengths the
  /// triangles on its sides give, relative to the edge: zero up to rounding when the replayed
  /// correspondence is consistent.
  double maxLengthMismatch = 0.0;
  /// Overlay faces of zero or negative area in the flat metric: crossings that rounding put at one
  /// point of an intrinsic edge (or at its end), after tens of thousands of flips of slivers. The
  /// subdivision is still combinatorially sound, but such a metric cannot be laid out.
  int degenerateCells = 0;
};

/// Replays `flips` (IntrinsicTriangulation::flippedEdges of a triangulation built from `input`) and
/// builds the overlay with the flat metric `lengths` of that triangulation (by its edge index):
/// its lengths at scale factors `u` (Delaunay at a converged u satisfies the triangle
/// inequality), or a metric moved from them on the same triangles (holonomy_quantization.h). The
/// points of an intrinsic edge keep their place along it (set by u), and the cells of an intrinsic
/// triangle follow it by the affine map between its two shapes, so they stay convex. Which cell
/// is where is decided combinatorially (input edges do not cross one another), so rounding moves
/// points but cannot tangle the subdivision; see degenerateCells. Throws InputError on sizes that
/// do not match.
IntrinsicOverlay intrinsicOverlay(const TriMesh& input, const std::vector<int>& flips,
                                  const Eigen::VectorXd& u, const Eigen::VectorXd& lengths);

/// Points of `input`'s faces as points of the overlay faces (pieces of the input face) holding
/// them: the piece where the point's smallest barycentric coordinate is largest, the coordinates
/// clamped to it (a point on a piece's edge may round outside it).
std::vector<SurfacePoint> pointsOnOverlay(const TriMesh& input, const IntrinsicOverlay& overlay,
                                          const std::vector<SurfacePoint>& points);

}  // namespace mspline::structure
