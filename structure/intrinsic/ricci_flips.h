#pragma once
// Newton's method for vertex scaling with intrinsic Delaunay (Ptolemy) flips, after Gillespie,
// Springborn and Crane 2021: every trial point u is evaluated on the ideal Delaunay triangulation
// of the metric at u (intrinsic_triangulation.h), where the Ricci energy is convex and C^1 on all
// of R^n, so no triangle can block the line search. The result is a flat metric on an intrinsic
// triangulation of the input's vertices; the input's edges need not be edges of it.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/intrinsic/intrinsic_triangulation.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"

namespace mspline::structure {

struct RicciFlipsResult {
  /// Status, message, iterations, curvature error, log, seconds and u as from solveVertexScaling.
  /// Here edgeLengths are indexed by the edges of `triangulation` (NOT the input's edges) and
  /// degenerateFaces lists faces of `triangulation` violating the triangle inequality at u (empty
  /// on success). Status DegenerateTriangles means an input edge of length 0, or a solution
  /// with triangles on the boundary that violate the triangle inequality (boundary edges cannot
  /// flip; solve on the doubled surface then, see intrinsic_flattening.h).
  RicciResult ricci;
  /// The final triangulation, Delaunay at ricci.u (lengths: triangulation.lengths(ricci.u)).
  IntrinsicTriangulation triangulation;
  /// Its faces as vertex triples (input vertex indices).
  std::vector<std::array<int, 3>> faces;
  /// Flips that took the input to `triangulation` (along the accepted iterates).
  long flips = 0;
  /// Flips made in all line-search trials, rejected ones included (a measure of the work).
  long trialFlips = 0;
  /// Edge indices flipped at least once: those input edges are, in general, no longer edges.
  int inputEdgesFlipped = 0;
};

/// Same contract as solveVertexScaling (Gauss-Bonnet checked before solving, InputError
/// otherwise; TopologyError for several components or no faces; gauge u = 0 at vertex 0 when
/// nothing is fixed), but the triangulation follows the metric by Ptolemy flips, so the only
/// numerical failures left are MaxIterations, LineSearchFailed and SolverFailed.
/// `options.maxUStep` and the other Newton options mean what they mean there.
RicciFlipsResult solveVertexScalingWithFlips(const TriMesh& mesh, const CurvatureTarget& target,
                                             const RicciNewtonOptions& options = {});

}  // namespace mspline::structure
