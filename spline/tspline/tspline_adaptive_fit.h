#pragma once
// Adaptive T-spline fitting: fit (surface_fit.h), then where samples are farther from the surface
// than the tolerance, split their T-mesh faces into four (local refinement: the cuts end in
// T-junctions), fit again, until the RMS distance is within the tolerance, the maximum within
// maxErrorFactor times it, or the control point budget is spent.
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/fitting/surface_fit.h"
#include "mspline/spline/tspline/tmesh.h"

namespace mspline::spline {

struct TSplineAdaptiveFitOptions {
  /// Wanted RMS distance of the samples to the surface (absolute units).
  double tolerance = 1e-3;
  /// The maximum distance wanted is maxErrorFactor * tolerance.
  double maxErrorFactor = 10.0;
  /// Refinement stops before the blending functions would exceed this.
  int maxControlPoints = 8000;
  /// At most this many refinement rounds.
  int maxRefinements = 6;
  SurfaceFitOptions fit;
};

/// One fit of the refinement sequence.
struct TSplineFitRound {
  int controlPoints = 0;
  int faces = 0;
  double rmsError = 0.0;
  double maxError = 0.0;
  /// Faces split after this round (0 for the last).
  int splitFaces = 0;
  double seconds = 0.0;
};

struct TSplineAdaptiveFitResult {
  /// The final T-mesh (input faces keep their ids; split faces' parts follow) and its fit.
  TMesh mesh;
  SurfaceFitResult fit;
  /// The samples' parameters on `mesh` (after parameter correction).
  std::vector<FacePoint> parameters;
  std::vector<TSplineFitRound> rounds;
  /// RMS <= tolerance and max <= maxErrorFactor * tolerance.
  bool reachedTolerance = false;
};

/// Fits a T-spline with unit weights on `mesh` (refined as described) to `targets` (one row per
/// sample) from the samples' initial `parameters`. With sample weights (options.fit), faces are
/// refined by sqrt(weight) * distance.
TSplineAdaptiveFitResult fitTSplineAdaptively(const TMesh& mesh,
                                              const std::vector<FacePoint>& parameters,
                                              const Eigen::MatrixX3d& targets,
                                              const TSplineAdaptiveFitOptions& options = {},
                                              const FitProgress& progress = {});

}  // namespace mspline::spline
