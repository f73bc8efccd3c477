#include <catch2/catch.hpp>

#include <string>

#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/check_model.h"
#include "mspline/structure/core/errors.h"
#include "support/test_data.h"

using namespace mspline;

TEST_CASE("check_model: a fitted triangular B-spline agrees across charts and sums to one",
          "[spline]") {
  // knot1 is a torus: no cones, every sample counts for the raw partition of unity.
  const spline::SplineModel& model = test::fittedModel("knot1.off", "tribspline", test::kSmallFit);
  spline::CheckOptions options;
  options.samples = 2000;
  options.knotSamples = 40;
  const spline::CheckResult result = spline::checkModel(model, "knot1", options);
  const spline::TriBSplineCheck& check = result.triBSpline;
  CHECK(result.kind == spline::SplineKind::TriangularBSpline);
  CHECK(result.passed);
  CHECK(result.controlPoints == model.controlPoints.rows());
  CHECK(result.degree == model.degree);
  CHECK(check.samples == options.samples);
  CHECK(check.knotRouteSamples == options.knotSamples);
  // Every point lies in its own face's chart at least; most in the charts of its corners too.
  CHECK(check.chartsPerSample > 1.0);
  CHECK(result.maxChartDiscrepancy <= 1e-12);
  CHECK(check.pointRouteDiscrepancy <= 1e-12);
  CHECK(check.knotRouteDiscrepancy <= 1e-12);
  CHECK(check.partitionOfUnityError <= 1e-11);
  CHECK(check.partitionOfUnitySamples == options.samples);
  CHECK(check.normalizedPartitionOfUnityError <= 1e-12);
  CHECK(check.minDenominator > 0.0);
  // The same seed gives the same points.
  const spline::CheckResult again = spline::checkModel(model, "knot1", options);
  CHECK(again.triBSpline.minDenominator == check.minDenominator);
  CHECK(again.triBSpline.pointRouteDiscrepancy == check.pointRouteDiscrepancy);
}

TEST_CASE("check_model: near cones the raw partition of unity is not counted", "[spline]") {
  const spline::SplineModel& model = test::headModel("tribspline");
  spline::CheckOptions options;
  options.samples = 2000;
  options.knotSamples = 0;
  const spline::TriBSplineCheck check = spline::checkModel(model, "head", options).triBSpline;
  CHECK(check.partitionOfUnitySamples > 0);
  CHECK(check.partitionOfUnitySamples < options.samples);
  CHECK(check.partitionOfUnityError <= 1e-11);
  CHECK(check.normalizedPartitionOfUnityError <= 1e-12);
  CHECK(check.knotRouteSamples == 0);
  CHECK(check.knotRouteDiscrepancy == 0.0);
}

TEST_CASE("check_model: a fitted T-spline agrees across faces, with caps at its cones",
          "[spline]") {
  const spline::SplineModel& model = test::headModel("tspline");
  spline::CheckOptions options;
  options.samples = 2000;
  const spline::CheckResult result = spline::checkModel(model, "head", options);
  CHECK(result.kind == spline::SplineKind::TSpline);
  CHECK(result.passed);
  CHECK(result.controlPoints == model.controlPoints.rows());
  CHECK(result.degree == 3);
  CHECK(result.maxChartDiscrepancy <= 1e-12);
  CHECK(result.tspline.samples == options.samples);
  // The cones are extraordinary vertices with caps: every vertex anchors a blending function.
  CHECK(result.missingAnchors == 0);
}

TEST_CASE("check_model: subdivision models and wrong control points are refused", "[spline]") {
  spline::SplineModel model = test::headModel("tribspline");
  model.controlPoints.conservativeResize(model.controlPoints.rows() - 1, 3);
  CHECK_THROWS_AS(spline::checkModel(model, "m.msp"), structure::InputError);
  CHECK_THROWS_WITH(spline::checkModel(model, "m.msp"),
                    Catch::StartsWith("m.msp: ") && Catch::Contains("basis functions"));
  model = test::headModel("tspline");
  model.kind = spline::SplineKind::Subdivision;
  CHECK_THROWS_WITH(spline::checkModel(model, "m.msp"),
                    Catch::StartsWith("m.msp: ") && Catch::Contains("subdivision"));
}
