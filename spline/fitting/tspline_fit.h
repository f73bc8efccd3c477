#pragma once
// Control points of a T-spline (unit weights) from samples of the surface it should follow: least
// squares with a light pull towards the quasi-interpolant, as control_fit.h does for triangular
// B-splines. Initializes a model from its mesh.
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tspline.h"

namespace mspline::spline {

struct TSplineFitOptions {
  /// Weight of the pull towards the quasi-interpolant (each control point the mean of the samples
  /// weighted by its blending function), relative to the mean diagonal of the normal equations.
  double regularization = 1e-4;
};

struct TSplineFitResult {
  /// One row per blending function, as many columns as the targets.
  Eigen::MatrixXd controlPoints;
  /// Distance between the spline and the targets at the sites used: root mean square and maximum.
  double rmsError = 0.0;
  double maxError = 0.0;
  /// Blending functions with no site under them (their control point is the targets' mean).
  int basisWithoutSamples = 0;
  /// Sites left out because they lie in a hole (no blending function there).
  int sitesInHoles = 0;
};

/// Fits control points so that the T-spline with unit weights comes close to `targets` (one row
/// per site). Throws InputError when the counts differ or there are no sites.
TSplineFitResult fitTSplineControlPoints(const TSplineSpace& space,
                                         const std::vector<TMeshPoint>& sites,
                                         const Eigen::MatrixXd& targets,
                                         const TSplineFitOptions& options = {});

}  // namespace mspline::spline
