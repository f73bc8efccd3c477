#pragma once
// Consistency figures of a T-spline surface: does a surface point give the same value whichever
// face (chart) it is evaluated from and whichever way the blending functions are moved, does the
// Bezier form reproduce it, and where do the blending functions fail to sum to one.
#include <Eigen/Core>

#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_bezier.h"

namespace mspline::spline {

struct TSplineCheckOptions {
  /// Random points, uniform by area over the faces; as many again on shared edges.
  int samples = 10000;
  unsigned seed = 1;
};

struct TSplineCheck {
  int samples = 0;
  /// Diagonal of the control points' bounding box; the discrepancies below are relative to it.
  double diagonal = 0.0;
  /// Points on edges shared by two faces, evaluated from each face (the point moved into the
  /// charts through that face's motions): max difference.
  double chartDiscrepancy = 0.0;
  int edgeSamples = 0;
  /// The blending functions' knots moved into the face frame instead of the point into their
  /// charts: max difference.
  double knotRouteDiscrepancy = 0.0;
  /// The Bezier form against direct evaluation: max difference of positions, and of first
  /// derivatives relative to the diagonal per knot unit.
  double bezierDiscrepancy = 0.0;
  double bezierDerivativeDiscrepancy = 0.0;
  /// max |sum of blending functions - 1| over the samples off holes, and how many samples needed
  /// the rational normalization (|sum - 1| > 1e-12).
  double partitionOfUnityError = 0.0;
  int normalizedSamples = 0;
  /// The same on faces away from vertices without a blending function (no vertex of the face
  /// within two edges of one), where a T-mesh without T-junctions is a partition of unity.
  double partitionOfUnityErrorAway = 0.0;
  int awaySamples = 0;
  /// Samples in a hole (no blending function) and the smallest positive denominator met.
  int holeSamples = 0;
  double minDenominator = 0.0;
  /// Surfaces in 3-space: the cones (extraordinary vertices with cap faces) and the angle between
  /// the normals 1e-3 of the cap's cell from each (tspline_cone_normals.h). With a unique normal at
  /// the cone it is the surface's own turning over 2e-3 cells, under 1e-3 where a cap cell turns
  /// the normal by less than about half a radian. The largest (radians; pi where a normal is
  /// undefined), at which cone (T-mesh vertex, -1 without cones), and how many cones exceed 1e-3.
  int cones = 0;
  double maxConeNormalSpread = 0.0;
  int worstCone = -1;
  int conesSpreadOver1e3 = 0;
};

TSplineCheck checkTSpline(const TSplineSpace& space, const Eigen::MatrixXd& control,
                          const Eigen::VectorXd& weights, const TSplineCheckOptions& options = {});

}  // namespace mspline::spline
