// mspline check: a spline model evaluated at random surface points in every chart holding each,
// with its partition of unity and denominators.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include "cli/command.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/spline/tspline/tspline_check.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"

namespace mspline::cli {

namespace {

using namespace structure;

struct CheckArguments {
  std::string model;
  int samples = 10000;
  int knotSamples = 500;
  unsigned seed = 1;
};

// Face areas of the domain, for sampling points uniformly on the surface.
std::vector<double> faceAreas(const spline::SplineDomain& domain) {
  std::vector<double> areas;
  for (int f = 0; f < domain.faceCount(); ++f) {
    const auto c = spline::canonicalCorners(domain, f);
    areas.push_back(0.5 * std::abs((c[1] - c[0]).x() * (c[2] - c[0]).y() -
                                   (c[1] - c[0]).y() * (c[2] - c[0]).x()));
  }
  return areas;
}

// T-spline models: the same figures through spline::checkTSpline.
int checkTSplineModel(const CheckArguments& a, const spline::SplineModel& model, Command& command) {
  Stopwatch clock;
  const spline::TSplineSpace space(model.tmesh);
  spline::TSplineCheckOptions options;
  options.samples = a.samples;
  options.seed = a.seed;
  const spline::TSplineCheck check =
      spline::checkTSpline(space, model.controlPoints, model.weights, options);
  const double seconds = clock.lap();
  const double discrepancy =
      std::max({check.chartDiscrepancy, check.knotRouteDiscrepancy, check.bezierDiscrepancy});
  // A closed T-mesh without T-junctions is a partition of unity away from the vertices without
  // function (around extraordinary points); elsewhere the rational normalization is reported.
  const bool noTJunctions = !model.tmesh.hasBoundary() && model.tmesh.numTJunctions() == 0;
  const bool passed =
      discrepancy <= 1e-12 && (!noTJunctions || check.partitionOfUnityErrorAway <= 1e-12);
  Json report{{"file", a.model},
              {"kind", "tspline"},
              {"samples", check.samples},
              {"max_chart_discrepancy", discrepancy},
              {"edge_chart_discrepancy", check.chartDiscrepancy},
              {"edge_samples", check.edgeSamples},
              {"knot_route_discrepancy", check.knotRouteDiscrepancy},
              {"bezier_discrepancy", check.bezierDiscrepancy},
              {"bezier_derivative_discrepancy", check.bezierDerivativeDiscrepancy},
              {"partition_of_unity_error", check.partitionOfUnityError},
              {"normalized_samples", check.normalizedSamples},
              {"partition_of_unity_error_away_from_holes", check.partitionOfUnityErrorAway},
              {"samples_away_from_holes", check.awaySamples},
              {"partition_of_unity_required", noTJunctions},
              {"hole_samples", check.holeSamples},
              {"min_denominator", check.minDenominator},
              {"control_points", space.numBasis()},
              {"missing_anchors", space.missingAnchors().size()},
              {"degree", 3},
              {"passed", passed},
              {"seconds", seconds}};
  if (command.json) {
    printJson(report);
  } else {
    std::cout << check.samples << " samples: chart discrepancy " << discrepancy
              << " of the diagonal, partition of unity " << check.partitionOfUnityError << " ("
              << check.normalizedSamples << " samples normalized, " << check.holeSamples
              << " in holes)" << (passed ? "" : "  FAILED") << std::endl;
  }
  return passed ? int(kExitSuccess) : int(kExitComputationFailed);
}

}  // namespace

void addCheckCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<CheckArguments>();
  auto* sub = app.add_subcommand(
      "check",
      "Checks a spline model: at random surface points (uniform by area), evaluates the spline "
      "in every chart that holds the point (the point mapped through the chart's transitions; "
      "on the first --knot-samples samples also the knots mapped into the chart and every "
      "simplex spline evaluated afresh), and measures the partition of unity (the raw basis' sum "
      "away from cones, "
      "where it is 1 up to rounding: the DMS edge terms of two neighbouring faces cancel, each "
      "evaluated in its own chart, which leaves about 1e-12). Exits 3 when a figure fails its "
      "bound (chart discrepancy 1e-12 of the diagonal, partition of unity 1e-11).");
  sub->add_option("MODEL", arguments->model, "Model file (.msp)")->required();
  sub->add_option("--samples", arguments->samples, "Random surface points (default 10000)")
      ->check(CLI::Range(1, 100000000));
  sub->add_option("--knot-samples", arguments->knotSamples,
                  "Of the samples, how many are also evaluated with the knots moved into each "
                  "chart (slow; default 500)")
      ->check(CLI::Range(0, 100000000));
  sub->add_option("--seed", arguments->seed, "Seed of the random points (default 1)");
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "check";
    command.run = [&command, arguments] {
      const CheckArguments& a = *arguments;
      Stopwatch clock;
      const spline::SplineModel model = io::readSplineModel(a.model);
      if (model.kind == spline::SplineKind::TSpline) return checkTSplineModel(a, model, command);
      // Its evaluation is OpenSubdiv's, checked by the test suite: no chart figures to report.
      if (model.kind == spline::SplineKind::Subdivision)
        throw InputError(a.model +
                         ": check knows triangular B-splines and T-splines; this is a subdivision "
                         "surface (Catmull-Clark), which has no charts to compare (use export)");
      const spline::TriBSplineSpace space(model.domain, model.knots);
      if (model.controlPoints.rows() != space.numBasis())
        throw InputError(a.model + ": " + std::to_string(model.controlPoints.rows()) +
                         " control points for " + std::to_string(space.numBasis()) +
                         " basis functions");
      const double loadSeconds = clock.lap();
      const double diagonal =
          (model.surfaceVertices.colwise().maxCoeff() - model.surfaceVertices.colwise().minCoeff())
              .norm();
      const std::vector<double> areas = faceAreas(model.domain);
      std::mt19937_64 random(a.seed);
      std::discrete_distribution<int> pickFace(areas.begin(), areas.end());
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      // Faces where no cone's functions reach: there the DMS identity holds unnormalized.
      std::vector<char> awayFromCones(std::size_t(model.domain.faceCount()), 1);
      for (int f = 0; f < model.domain.faceCount(); ++f)
        for (int k : space.chartsHolding(f))
          for (int v : model.domain.faces[std::size_t(k)])
            if (model.domain.cone[std::size_t(v)]) awayFromCones[std::size_t(f)] = 0;

      double discrepancy = 0.0, knotDiscrepancy = 0.0, unity = 0.0, rawUnity = 0.0;
      double minDenominator = std::numeric_limits<double>::infinity();
      long charts = 0, rawSamples = 0;
      spline::BasisValues basis;
      for (int s = 0; s < a.samples; ++s) {
        // Uniform in the triangle: reflect the unit square's upper half.
        double u = unit(random), v = unit(random);
        if (u + v > 1.0) {
          u = 1.0 - u;
          v = 1.0 - v;
        }
        const spline::DomainPoint point{pickFace(random), Eigen::Vector3d(1.0 - u - v, u, v)};
        double denominator = 0.0;
        space.basisAt(point, basis, 0, &denominator);
        minDenominator = std::min(minDenominator, denominator);
        double sum = 0.0;
        Eigen::Vector3d value = Eigen::Vector3d::Zero();
        for (std::size_t k = 0; k < basis.index.size(); ++k) {
          sum += basis.value[k];
          value += basis.value[k] * model.controlPoints.row(basis.index[k]).transpose();
        }
        unity = std::max(unity, std::abs(sum - 1.0));
        if (awayFromCones[std::size_t(point.face)]) {
          rawUnity = std::max(rawUnity, std::abs(denominator - 1.0));
          ++rawSamples;
        }
        const int holders = int(space.chartsHolding(point.face).size());
        for (int chart = 0; chart < holders; ++chart) {
          const Eigen::VectorXd other = space.evaluateInChart(
              model.controlPoints, point, chart, spline::TriBSplineSpace::ChartRoute::MovePoint);
          discrepancy = std::max(discrepancy, (other - value).norm() / diagonal);
          ++charts;
          // Moving the knots instead re-evaluates every simplex spline from scratch: slow, so on
          // the first samples only.
          if (s < a.knotSamples) {
            const Eigen::VectorXd moved = space.evaluateInChart(
                model.controlPoints, point, chart, spline::TriBSplineSpace::ChartRoute::MoveKnots);
            knotDiscrepancy = std::max(knotDiscrepancy, (moved - value).norm() / diagonal);
          }
        }
      }
      const double checkSeconds = clock.lap();
      const bool passed =
          std::max(discrepancy, knotDiscrepancy) <= 1e-12 && unity <= 1e-12 && rawUnity <= 1e-11;
      Json report{{"file", a.model},
                  {"samples", a.samples},
                  {"charts_per_sample", double(charts) / a.samples},
                  {"max_chart_discrepancy", std::max(discrepancy, knotDiscrepancy)},
                  {"point_route_discrepancy", discrepancy},
                  {"knot_route_discrepancy", knotDiscrepancy},
                  {"knot_route_samples", std::min(a.samples, a.knotSamples)},
                  {"partition_of_unity_error", rawUnity},
                  {"partition_of_unity_samples", rawSamples},
                  {"normalized_partition_of_unity_error", unity},
                  {"min_denominator", minDenominator},
                  {"control_points", space.numBasis()},
                  {"degree", space.degree()},
                  {"passed", passed},
                  {"seconds", loadSeconds + checkSeconds}};
      if (command.json) {
        printJson(report);
      } else {
        std::cout << a.samples << " samples, " << double(charts) / a.samples
                  << " charts each: chart discrepancy " << discrepancy
                  << " of the diagonal, partition of unity " << rawUnity << " (" << rawSamples
                  << " samples away from cones), min denominator " << minDenominator
                  << (passed ? "" : "  FAILED") << std::endl;
      }
      return passed ? int(kExitSuccess) : int(kExitComputationFailed);
    };
  });
}

}  // namespace mspline::cli
