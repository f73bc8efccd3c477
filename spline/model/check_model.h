#pragma once
// `mspline check` as a library call: a spline model evaluated at random surface points in every
// chart holding each, with its partition of unity and denominators. Triangular B-splines are
// checked here (every chart and both chart routes of TriBSplineSpace), T-splines through
// spline/tspline/tspline_check.h; a subdivision surface has no charts to compare.
#include <string>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/tspline/tspline_check.h"

namespace mspline::spline {

struct CheckOptions {
  /// Random surface points, uniform by area.
  int samples = 10000;
  /// Triangular B-splines: of the samples, how many are also evaluated with the knots moved into
  /// each chart (every simplex spline evaluated afresh: slow).
  int knotSamples = 500;
  /// Seed of the random points; equal seeds give equal points.
  unsigned seed = 1;
};

/// The figures of a triangular B-spline model. Discrepancies are relative to the bounding-box
/// diagonal of the model's surface vertices.
struct TriBSplineCheck {
  /// Samples, and the charts each lies in on average (every chart holding its face).
  int samples = 0;
  double chartsPerSample = 0.0;
  /// Largest difference between the value in the sample's own face and in another chart holding
  /// it, the point moved into that chart (ChartRoute::MovePoint).
  double pointRouteDiscrepancy = 0.0;
  /// The same with the knots moved into the chart instead (ChartRoute::MoveKnots), over the first
  /// `knotRouteSamples` samples.
  double knotRouteDiscrepancy = 0.0;
  int knotRouteSamples = 0;
  /// max |sum of the raw basis - 1| (the denominator) over the samples on faces no cone's
  /// functions reach, where the DMS identity holds unnormalized; and how many samples those were.
  double partitionOfUnityError = 0.0;
  long partitionOfUnitySamples = 0;
  /// max |sum of the normalized basis - 1| over every sample.
  double normalizedPartitionOfUnityError = 0.0;
  /// The smallest denominator met.
  double minDenominator = 0.0;
};

struct CheckResult {
  SplineKind kind = SplineKind::TriangularBSpline;
  /// Basis functions (control points) and polynomial degree.
  int controlPoints = 0;
  int degree = 0;
  /// The largest chart discrepancy of any route, relative to the diagonal.
  double maxChartDiscrepancy = 0.0;
  /// Every figure within its bound: chart discrepancies 1e-12; for a triangular B-spline the
  /// normalized partition of unity 1e-12 and the raw one 1e-11; for a T-spline the partition of
  /// unity away from holes 1e-12 where it is required (partitionOfUnityRequired).
  bool passed = false;
  /// Triangular B-splines only: their figures.
  TriBSplineCheck triBSpline;
  /// T-splines only: their figures (tspline_check.h), the T-mesh vertices without a blending
  /// function, and whether the partition of unity is required (a closed T-mesh without
  /// T-junctions is one away from the vertices without function; elsewhere the rational
  /// normalization is reported, not judged).
  TSplineCheck tspline;
  int missingAnchors = 0;
  bool partitionOfUnityRequired = false;
};

/// Checks `model` (`name` names it in messages). Throws InputError for a subdivision model or a
/// model whose control points do not fit its space, and as the spaces' constructors do.
CheckResult checkModel(const SplineModel& model, const std::string& name,
                       const CheckOptions& options = {});

}  // namespace mspline::spline
