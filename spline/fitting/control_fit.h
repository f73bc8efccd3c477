#pragma once
// Control points of a spline from samples of the surface it should follow: least squares with a
// light pull towards a quasi-interpolant, so that basis functions with little data under them
// still get sensible control points. This initializes a model from its mesh; fitting proper
// (smoothing, parameter correction, refinement) builds on it.
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tribspline/tri_bspline.h"

namespace mspline::spline {

struct ControlFitOptions {
  /// Weight of the pull towards the quasi-interpolant (each control point the average of the
  /// samples weighted by its basis function), relative to the mean diagonal of the normal
  /// equations. Small: the samples decide wherever they determine the control points.
  double regularization = 1e-4;
};

struct ControlFitResult {
  /// One row per basis function, as many columns as the targets.
  Eigen::MatrixXd controlPoints;
  /// Distance between the spline and the target at the sites used: root mean square and maximum.
  double rmsError = 0.0;
  double maxError = 0.0;
  /// Basis functions that no site lies under (their control point is the mean of their face's).
  int basisWithoutSamples = 0;
  /// Sites left out because they are cone points, where the spline is undefined.
  int sitesAtCones = 0;
};

/// Fits control points so that the spline at `sites` comes close to the rows of `targets`.
/// Throws InputError when the counts differ or there are no sites.
ControlFitResult fitControlPoints(const TriBSplineSpace& space,
                                  const std::vector<DomainPoint>& sites,
                                  const Eigen::MatrixXd& targets,
                                  const ControlFitOptions& options = {});

}  // namespace mspline::spline
