#include "mspline/spline/model/check_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/bounding_box.h"

namespace mspline::spline {

namespace {

// Face areas of the domain, for sampling points uniformly on the surface.
std::vector<double> faceAreas(const SplineDomain& domain) {
  std::vector<double> areas;
  for (int f = 0; f < domain.faceCount(); ++f) {
    const auto c = canonicalCorners(domain, f);
    areas.push_back(0.5 * std::abs((c[1] - c[0]).x() * (c[2] - c[0]).y() -
                                   (c[1] - c[0]).y() * (c[2] - c[0]).x()));
  }
  return areas;
}

TriBSplineCheck checkTriBSpline(const TriBSplineSpace& space, const SplineModel& model,
                                const CheckOptions& options) {
  const double diagonal = structure::boundingBoxDiagonal(model.surfaceVertices);
  const std::vector<double> areas = faceAreas(model.domain);
  std::mt19937_64 random(options.seed);
  std::discrete_distribution<int> pickFace(areas.begin(), areas.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Faces where no cone's functions reach: there the DMS identity holds unnormalized.
  std::vector<char> awayFromCones(std::size_t(model.domain.faceCount()), 1);
  for (int f = 0; f < model.domain.faceCount(); ++f)
    for (int k : space.chartsHolding(f))
      for (int v : model.domain.faces[std::size_t(k)])
        if (model.domain.cone[std::size_t(v)]) awayFromCones[std::size_t(f)] = 0;

  TriBSplineCheck check;
  check.samples = options.samples;
  check.knotRouteSamples = std::min(options.samples, options.knotSamples);
  check.minDenominator = std::numeric_limits<double>::infinity();
  long charts = 0;
  BasisValues basis;
  for (int s = 0; s < options.samples; ++s) {
    // Uniform in the triangle: reflect the unit square's upper half.
    double u = unit(random), v = unit(random);
    if (u + v > 1.0) {
      u = 1.0 - u;
      v = 1.0 - v;
    }
    const SurfacePoint point{pickFace(random), Eigen::Vector3d(1.0 - u - v, u, v)};
    double denominator = 0.0;
    space.basisAt(point, basis, 0, &denominator);
    check.minDenominator = std::min(check.minDenominator, denominator);
    double sum = 0.0;
    Eigen::Vector3d value = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < basis.index.size(); ++k) {
      sum += basis.value[k];
      value += basis.value[k] * model.controlPoints.row(basis.index[k]).transpose();
    }
    check.normalizedPartitionOfUnityError =
        std::max(check.normalizedPartitionOfUnityError, std::abs(sum - 1.0));
    if (awayFromCones[std::size_t(point.face)]) {
      check.partitionOfUnityError =
          std::max(check.partitionOfUnityError, std::abs(denominator - 1.0));
      ++check.partitionOfUnitySamples;
    }
    const int holders = int(space.chartsHolding(point.face).size());
    for (int chart = 0; chart < holders; ++chart) {
      const Eigen::VectorXd other = space.evaluateInChart(model.controlPoints, point, chart,
                                                          TriBSplineSpace::ChartRoute::MovePoint);
      check.pointRouteDiscrepancy =
          std::max(check.pointRouteDiscrepancy, (other - value).norm() / diagonal);
      ++charts;
      // Moving the knots instead re-evaluates every simplex spline from scratch: slow, so on the
      // first samples only.
      if (s < options.knotSamples) {
        const Eigen::VectorXd moved = space.evaluateInChart(model.controlPoints, point, chart,
                                                            TriBSplineSpace::ChartRoute::MoveKnots);
        check.knotRouteDiscrepancy =
            std::max(check.knotRouteDiscrepancy, (moved - value).norm() / diagonal);
      }
    }
  }
  check.chartsPerSample = double(charts) / options.samples;
  return check;
}

}  // namespace

CheckResult checkModel(const SplineModel& model, const std::string& name,
                       const CheckOptions& options) {
  if (options.samples < 1 || options.knotSamples < 0)
    throw structure::InputError(name + ": check needs at least one sample");
  CheckResult result;
  result.kind = model.kind;
  if (model.kind == SplineKind::TSpline) {
    const TSplineSpace space(model.tmesh);
    TSplineCheckOptions tsplineOptions;
    tsplineOptions.samples = options.samples;
    tsplineOptions.seed = options.seed;
    const TSplineCheck& check = result.tspline =
        checkTSpline(space, model.controlPoints, model.weights, tsplineOptions);
    result.controlPoints = space.numBasis();
    result.degree = 3;
    result.missingAnchors = int(space.missingAnchors().size());
    result.maxChartDiscrepancy =
        std::max({check.chartDiscrepancy, check.knotRouteDiscrepancy, check.bezierDiscrepancy});
    result.partitionOfUnityRequired =
        !model.tmesh.hasBoundary() && model.tmesh.numTJunctions() == 0;
    result.passed = result.maxChartDiscrepancy <= 1e-12 &&
                    (!result.partitionOfUnityRequired || check.partitionOfUnityErrorAway <= 1e-12);
    return result;
  }
  // Its evaluation is OpenSubdiv's, checked by the test suite: no chart figures to report.
  if (model.kind == SplineKind::Subdivision)
    throw structure::InputError(
        name +
        ": check knows triangular B-splines and T-splines; this is a subdivision surface "
        "(Catmull-Clark), which has no charts to compare (use export)");
  const TriBSplineSpace space(model.domain, model.knots);
  if (model.controlPoints.rows() != space.numBasis())
    throw structure::InputError(name + ": " + std::to_string(model.controlPoints.rows()) +
                                " control points for " + std::to_string(space.numBasis()) +
                                " basis functions");
  const TriBSplineCheck& check = result.triBSpline = checkTriBSpline(space, model, options);
  result.controlPoints = space.numBasis();
  result.degree = space.degree();
  result.maxChartDiscrepancy = std::max(check.pointRouteDiscrepancy, check.knotRouteDiscrepancy);
  result.passed = result.maxChartDiscrepancy <= 1e-12 &&
                  check.normalizedPartitionOfUnityError <= 1e-12 &&
                  check.partitionOfUnityError <= 1e-11;
  return result;
}

}  // namespace mspline::spline
