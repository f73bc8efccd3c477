#pragma once
// What `spline` and `fit` share: from a flattened surface to a spline space on it (the T-mesh of
// a seamless quad grid, or the domain triangulation with knot clouds of a triangular B-spline),
// the surface copied into the model, and the samples (the surface's vertices, optionally points
// inside its faces) with their parameters.
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cli/command.h"
#include "mspline/spline/core/spline_model.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/flatten/flatten_surface.h"

namespace mspline::cli {

struct SplineSetupSettings {
  /// "tribspline" or "tspline" ("subd" sets up as "tspline": the same quad net).
  std::string kind = "tribspline";
  int degree = 3;
  /// Control points wanted, about.
  int control = 6000;
  /// Triangular B-splines: knot cloud radius fraction and seed.
  double cloudRadius = 0.3;
  unsigned seed = 1;
  /// T-splines: cell side as a fraction of sqrt(flat area); 0: from `control`.
  double grid = 0.0;
  /// Wanted samples per control point: points inside the surface's faces are added where the
  /// vertices alone give fewer (0: vertices only).
  double samplesPerControlPoint = 3.0;
  /// Triangular B-splines: per surface vertex, how densely the domain should sample it (empty:
  /// uniformly in the flat metric; structure::CoarseningOptions::density).
  Eigen::VectorXd density;
};

struct SplineSetup {
  /// The model without control points: kind, surface, and the T-mesh with the surface vertices'
  /// T-mesh points, or the domain, knots and the surface vertices' domain points.
  spline::SplineModel model;
  /// Samples: the parameters (T-mesh points or domain points by kind) and the 3D points; sample
  /// k < V is surface vertex k, points inside faces follow.
  std::vector<spline::TMeshPoint> tmeshSites;
  std::vector<spline::DomainPoint> domainSites;
  Eigen::MatrixX3d targets;
  /// Per sample after the vertices, the surface face it lies in.
  std::vector<int> sampleFaces;
  /// Kind-specific figures for JSON (grid or domain).
  Json report;
};

/// Builds the space of `settings.kind` on the flattened surface; adds "grid"/"basis"/"locate" or
/// "coarsen"/"basis"/"locate" stage seconds to `stages`.
SplineSetup setUpSpline(const SplineSetupSettings& settings,
                        const structure::Flattening& flattening, int genus, Json& stages,
                        structure::Stopwatch& clock,
                        const std::function<void(const std::string&)>& progress);

/// The diagonal of the points' bounding box.
double boxDiagonal(const Eigen::MatrixX3d& points);

}  // namespace mspline::cli
