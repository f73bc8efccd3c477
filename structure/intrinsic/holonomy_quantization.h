#pragma once
// Flat metrics whose rotation along every loop is a quarter turn (seamless metrics).
//
// Ricci flow with cones quantized to multiples of pi/2 fixes the rotation around each cone, but on
// a closed surface of genus g >= 1 the rotation along the 2g handle loops is set by the conformal
// structure and is arbitrary (eight.off: about 0.3 rad off). No conformal factor can change it, so
// the metric leaves the conformal class: the log edge lengths take least-norm Newton steps that
// keep every vertex's curvature and bring each handle loop's rotation to the nearest multiple of
// the quantum, weighted so that skinny triangles hardly move. A loop's rotation is a sum of corner
// angles along a dual loop, so the constraints stay angle sums (Campen, Shen, Zhou and Zorin 2019
// prescribe holonomy the same way).
//
// Everything works on an intrinsic triangulation (intrinsic_triangulation.h) with a metric of its
// own: the input's connectivity when the flow needed no flips, otherwise the flip solver's
// Delaunay triangulation, whose triangles are far from degenerate where the common subdivision
// with the input (intrinsic_overlay.h) is full of slivers that block the steps.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/intrinsic/intrinsic_triangulation.h"
#include "mspline/structure/ricci/curvature_target.h"

namespace mspline::structure {

/// A closed path of faces of an intrinsic triangulation: halfedges[i] is the halfedge by which the
/// path leaves its i-th face; its twin lies in the next face, and the last one's twin in the
/// first.
struct DualLoop {
  std::vector<int> halfedges;
};

/// 2g dual loops whose classes form a basis of the first homology of a closed surface (tree-cotree:
/// a breadth-first vertex tree, a dual tree of the remaining edges, one loop per edge left over).
/// Throws TopologyError when the surface has a boundary or several components.
std::vector<DualLoop> homologyDualLoops(const IntrinsicTriangulation& tri);

/// The rotation of parallel transport once along each loop (radians, counter-clockwise positive),
/// summed from the corner angles of the triangulation's own metric (its logLengths0()) without
/// reduction mod 2 pi.
Eigen::VectorXd loopRotations(const IntrinsicTriangulation& tri,
                              const std::vector<DualLoop>& loops);

/// What quantizeHolonomy solves for: one equation per vertex but `droppedVertex` (its curvature
/// follows from Gauss-Bonnet) and one per loop.
struct HolonomyProblem {
  std::vector<DualLoop> loops;
  /// Target curvature of every vertex.
  Eigen::VectorXd targetCurvature;
  /// Target rotation of every loop.
  Eigen::VectorXd targetRotation;
  int droppedVertex = 0;
};

/// The residuals: curvature - target for the vertices (in index order, the dropped one skipped),
/// then rotation - target for the loops.
Eigen::VectorXd holonomyResiduals(const IntrinsicTriangulation& tri,
                                  const HolonomyProblem& problem);

/// Jacobian of holonomyResiduals with respect to the log edge lengths (one column per edge).
Eigen::SparseMatrix<double> holonomyJacobian(const IntrinsicTriangulation& tri,
                                             const HolonomyProblem& problem);

struct HolonomyQuantizationOptions {
  /// Loop rotations are moved to the nearest multiple of this (radians); pi/2 suits quad layouts
  /// and T-spline knot grids.
  double quantum = kPi / 2;
  /// Converged when every residual is at most this (radians); the atlas judges quarter turns to
  /// 1e-9.
  double tolerance = 1e-11;
  /// Newton steps at most, and one more for every four loops: the steps are cut short while the
  /// metric moves far, and more loops start farther (cheese.off, 266 loops and about 400 cones,
  /// needs 35; with 60 steps for all, joint.off's first cone set converged in 39, and its fit
  /// folded ten times as much as with the cone set tried next).
  int maxIterations = 30;
  /// Steps may flip the triangulation (off: a step that would degenerate a triangle is shortened
  /// instead, and the metric stays on the given triangles).
  bool flips = true;
  /// Without flips, give up after this many steps in a row that triangles about to degenerate cut
  /// to 1/64 of Newton's or less: they block the way, and flips are needed (cheese.off crawled so
  /// for 30 steps; where steps grew back to whole ones, as on anchor.off, they were never cut
  /// below 1/32). 0: never give up so.
  int maxBlockedSteps = 3;
};

struct HolonomyQuantizationResult {
  /// The triangulation of the new metric: the one given, or, where steps would have degenerated
  /// its triangles, that one further changed by Ptolemy flips (its flippedEdges() continue the
  /// given one's, so intrinsicOverlay maps the input onto it).
  IntrinsicTriangulation triangulation;
  /// Flips made here.
  long flips = 0;
  /// The new flat metric, by edge index of `triangulation` (the input lengths when nothing had to
  /// move).
  Eigen::VectorXd edgeLengths;
  /// The handle loops in `triangulation` and their rotations before and after (targets: multiples
  /// of the quantum).
  std::vector<DualLoop> loops;
  Eigen::VectorXd initialRotation;
  Eigen::VectorXd targetRotation;
  /// Every residual within the tolerance.
  bool converged = false;
  /// Newton steps taken.
  int iterations = 0;
  /// Largest residual at the end (radians).
  double maxResidual = 0.0;
  /// max |log(new length / old length)| over the edges not flipped here: how far the metric moved.
  double maxLogLengthChange = 0.0;
  /// Why the iteration stopped.
  std::string message;
};

/// Moves the flat metric of `tri` (its own logLengths0(); cone curvatures `cones`, flat
/// elsewhere) of a closed surface to one with the same cones whose
/// handle loops rotate by multiples of the quantum: Newton steps on the log lengths, with Ptolemy
/// flips to the Delaunay triangulation of a trial metric whose triangles would degenerate. Throws
/// TopologyError for surfaces with boundary, InputError for a cone vertex out of range. Non-
/// convergence is reported in the result, not thrown.
HolonomyQuantizationResult quantizeHolonomy(const IntrinsicTriangulation& tri,
                                            const std::vector<Cone>& cones,
                                            const HolonomyQuantizationOptions& options = {});

}  // namespace mspline::structure
