// mspline check: a spline model evaluated at random surface points in every chart holding each,
// with its partition of unity and denominators (spline/model/check_model.h), and its quality,
// against its scan when given (spline/quality/surface_quality.h).
#include <iostream>
#include <optional>

#include "cli/command.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/quality_report.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/check_model.h"
#include "mspline/structure/core/stopwatch.h"

namespace mspline::cli {

namespace {

struct CheckArguments {
  std::string model;
  std::string scan;
  spline::QualityOptions quality;
  int samples = 10000;
  int knotSamples = 500;
  unsigned seed = 1;
};

Json tsplineReport(const std::string& file, const spline::CheckResult& result) {
  const spline::TSplineCheck& check = result.tspline;
  return {{"file", file},
          {"kind", "tspline"},
          {"samples", check.samples},
          {"max_chart_discrepancy", result.maxChartDiscrepancy},
          {"edge_chart_discrepancy", check.chartDiscrepancy},
          {"edge_samples", check.edgeSamples},
          {"knot_route_discrepancy", check.knotRouteDiscrepancy},
          {"bezier_discrepancy", check.bezierDiscrepancy},
          {"bezier_derivative_discrepancy", check.bezierDerivativeDiscrepancy},
          {"partition_of_unity_error", check.partitionOfUnityError},
          {"normalized_samples", check.normalizedSamples},
          {"partition_of_unity_error_away_from_holes", check.partitionOfUnityErrorAway},
          {"samples_away_from_holes", check.awaySamples},
          {"partition_of_unity_required", result.partitionOfUnityRequired},
          {"hole_samples", check.holeSamples},
          {"min_denominator", check.minDenominator},
          {"cones", check.cones},
          {"max_cone_normal_spread", check.maxConeNormalSpread},
          {"worst_cone", check.worstCone},
          {"cones_spread_over_1e-3", check.conesSpreadOver1e3},
          {"control_points", result.controlPoints},
          {"missing_anchors", result.missingAnchors},
          {"degree", result.degree},
          {"passed", result.passed}};
}

Json triBSplineReport(const std::string& file, const spline::CheckResult& result) {
  const spline::TriBSplineCheck& check = result.triBSpline;
  return {{"file", file},
          {"samples", check.samples},
          {"charts_per_sample", check.chartsPerSample},
          {"max_chart_discrepancy", result.maxChartDiscrepancy},
          {"point_route_discrepancy", check.pointRouteDiscrepancy},
          {"knot_route_discrepancy", check.knotRouteDiscrepancy},
          {"knot_route_samples", check.knotRouteSamples},
          {"partition_of_unity_error", check.partitionOfUnityError},
          {"partition_of_unity_samples", check.partitionOfUnitySamples},
          {"normalized_partition_of_unity_error", check.normalizedPartitionOfUnityError},
          {"min_denominator", check.minDenominator},
          {"control_points", result.controlPoints},
          {"degree", result.degree},
          {"passed", result.passed}};
}

void printSummary(const spline::CheckResult& result) {
  const char* failed = result.passed ? "" : "  FAILED";
  if (result.kind == spline::SplineKind::TSpline) {
    const spline::TSplineCheck& check = result.tspline;
    std::cout << check.samples << " samples: chart discrepancy " << result.maxChartDiscrepancy
              << " of the diagonal, partition of unity " << check.partitionOfUnityError << " ("
              << check.normalizedSamples << " samples normalized, " << check.holeSamples
              << " in holes)" << failed << "\n"
              << check.cones << " cones: normals 1e-3 cells around them spread by up to "
              << check.maxConeNormalSpread << " rad (" << check.conesSpreadOver1e3 << " over 1e-3)"
              << std::endl;
    return;
  }
  const spline::TriBSplineCheck& check = result.triBSpline;
  std::cout << check.samples << " samples, " << check.chartsPerSample
            << " charts each: chart discrepancy " << check.pointRouteDiscrepancy
            << " of the diagonal, partition of unity " << check.partitionOfUnityError << " ("
            << check.partitionOfUnitySamples << " samples away from cones), min denominator "
            << check.minDenominator << failed << std::endl;
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
      "bound (chart discrepancy 1e-12 of the diagonal, partition of unity 1e-11). Reports the "
      "surface's quality (distances to --scan both ways, folds, dihedral angles at two "
      "resolutions, regularity); a subdivision model only that.");
  sub->add_option("MODEL", arguments->model, "Model file (.msp)")->required();
  sub->add_option("--samples", arguments->samples, "Random surface points (default 10000)")
      ->check(CLI::Range(1, 100000000));
  sub->add_option("--knot-samples", arguments->knotSamples,
                  "Of the samples, how many are also evaluated with the knots moved into each "
                  "chart (slow; default 500)")
      ->check(CLI::Range(0, 100000000));
  sub->add_option("--seed", arguments->seed, "Seed of the random points (default 1)");
  sub->add_option("--scan", arguments->scan,
                  "The scan the model was fitted to: the quality also measures the distances both "
                  "ways and the folds against the scan's normals");
  sub->add_option("--quality-resolution", arguments->quality.resolution,
                  "Samples per face side of the coarser tessellation the quality measures; the "
                  "finer one has twice as many (default 3)")
      ->check(CLI::Range(1, 64));
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "check";
    command.files = {arguments->model, arguments->scan};
    command.run = [&command, arguments] {
      const CheckArguments& a = *arguments;
      structure::Stopwatch clock;
      spline::CheckOptions options;
      options.samples = a.samples;
      options.knotSamples = a.knotSamples;
      options.seed = a.seed;
      const spline::SplineModel model = io::readSplineModel(a.model);
      std::optional<io::LoadedMesh> scan;
      if (!a.scan.empty()) scan = io::loadMesh(a.scan);
      // The quality first: a scan that is not the model's fails before the chart checks.
      spline::QualityOptions qualityOptions = a.quality;
      qualityOptions.name = a.model;
      qualityOptions.scanName = a.scan;
      const spline::SurfaceQuality quality =
          spline::measureQuality(model, scan ? &*scan->mesh : nullptr, qualityOptions);
      // A subdivision surface (OpenSubdiv's evaluation) has no charts to compare: its quality only.
      const bool subd = model.kind == spline::SplineKind::Subdivision;
      spline::CheckResult result;
      result.passed = true;
      if (!subd) result = spline::checkModel(model, a.model, options);
      if (command.json) {
        Json report = subd ? Json{{"file", a.model},
                                  {"kind", "subd"},
                                  {"control_points", model.controlPoints.rows()},
                                  {"note", "a subdivision surface has no charts to compare"},
                                  {"passed", true}}
                      : result.kind == spline::SplineKind::TSpline
                          ? tsplineReport(a.model, result)
                          : triBSplineReport(a.model, result);
        if (scan) report["scan"] = a.scan;
        report["quality"] = Json::parse(io::qualityJson(quality));
        report["seconds"] = clock.lap();
        printJson(report);
      } else {
        if (!subd) printSummary(result);
        std::cout << io::qualitySummary(quality) << std::endl;
      }
      return result.passed ? int(kExitSuccess) : int(kExitComputationFailed);
    };
  });
}

}  // namespace mspline::cli
