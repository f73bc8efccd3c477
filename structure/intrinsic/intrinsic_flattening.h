#pragma once
// Vertex scaling with intrinsic Delaunay flips (ricci_flips.h), delivered as a mesh: the common
// subdivision of the input and the final intrinsic triangulation with its flat edge lengths,
// ready for layoutFlatMetric.
//
// Boundary edges cannot flip, so a surface with boundary is solved on its double (two copies
// glued along the boundary, the second mirrored), as Gillespie, Springborn and Crane do: there the
// intrinsic triangulation may cross the boundary, and by symmetry the boundary stays a geodesic.
// The overlay of the double is then cut back to the input's half.
#include "mspline/structure/intrinsic/intrinsic_overlay.h"
#include "mspline/structure/intrinsic/ricci_flips.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"

namespace mspline::structure {

struct IntrinsicFlattening {
  /// The solve: on the double for a surface with boundary. `solve.ricci.u` is the double's; the
  /// input's scale factors are `u`.
  RicciFlipsResult solve;
  /// Scale factors of the input's vertices.
  Eigen::VectorXd u;
  /// The common subdivision of the input and the final intrinsic triangulation with its flat
  /// lengths (IntrinsicOverlay; with a boundary, inputFace refers to the input after the splits
  /// below, and crossingInputEdge to the double's edges). Empty unless solve.ricci.converged.
  IntrinsicOverlay overlay;
  /// Whether the surface was doubled.
  bool doubled = false;
  /// Interior edges joining two boundary vertices, split at their midpoints before doubling (the
  /// double would join those vertices twice). Their midpoints follow the input's vertices in the
  /// overlay.
  int splitEdges = 0;
};

/// Same contract as solveVertexScalingWithFlips, for meshes with or without boundary.
IntrinsicFlattening flattenWithFlips(const TriMesh& mesh, const CurvatureTarget& target,
                                     const RicciNewtonOptions& options = {});

}  // namespace mspline::structure
