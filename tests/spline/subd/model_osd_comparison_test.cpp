#include <catch2/catch.hpp>

#include <cmath>

#include "mspline/spline/subd/model_osd_comparison.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "support/test_tmeshes.h"

using namespace mspline;

namespace {

// A T-spline model on a periodic 16 x 8 grid over a torus: every face regular.
spline::SplineModel torusModel() {
  const int n = 16, m = 8;
  std::vector<double> u, v;
  for (int i = 0; i <= n; ++i) u.push_back(i);
  for (int j = 0; j <= m; ++j) v.push_back(j);
  spline::SplineModel model;
  model.kind = spline::SplineKind::TSpline;
  model.tmesh = spline::gridTMesh(u, v, true, true);
  Eigen::MatrixXd vertexPoints(n * m, 3);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n, b = 2 * kPi * j / m, r = 1.0 + 0.4 * std::cos(b);
      vertexPoints.row(j * n + i) << r * std::cos(a), r * std::sin(a), 0.4 * std::sin(b);
    }
  model.controlPoints = test::anchorControl(spline::TSplineSpace(model.tmesh), vertexPoints);
  return model;
}

}  // namespace

TEST_CASE("model_osd_comparison: a torus T-spline model is OpenSubdiv's limit everywhere",
          "[spline]") {
  const spline::SplineModel model = torusModel();
  spline::OsdCompareOptions options;
  options.samples = 2000;
  const spline::ModelOsdComparison result = spline::compareWithOpenSubdiv(model, "torus", options);
  CHECK(result.tmeshFaces == 128);
  CHECK(result.controlPoints == 128);
  CHECK(result.tJunctions == 0);
  CHECK(result.extraordinaryPoints == 0);
  CHECK(result.comparison.regularFaces == 128);
  CHECK(result.comparison.samples == options.samples);
  CHECK(result.comparison.regularMaxDeviation <= 1e-12);
  // The same comparison as on the space itself.
  const spline::OsdComparison direct = spline::compareWithOpenSubdiv(
      spline::TSplineSpace(model.tmesh), model.controlPoints, model.weights, options);
  CHECK(direct.regularMaxDeviation == result.comparison.regularMaxDeviation);
}

TEST_CASE("model_osd_comparison: other kinds and T-junctions are refused, naming the model",
          "[spline]") {
  spline::SplineModel model = torusModel();
  model.kind = spline::SplineKind::TriangularBSpline;
  CHECK_THROWS_WITH(spline::compareWithOpenSubdiv(model, "m.msp"),
                    Catch::StartsWith("m.msp: ") && Catch::Contains("triangular B-spline"));
  model.kind = spline::SplineKind::TSpline;
  model.tmesh = test::stoppedLine();
  model.controlPoints = Eigen::MatrixXd::Zero(spline::TSplineSpace(model.tmesh).numBasis(), 3);
  CHECK_THROWS_AS(spline::compareWithOpenSubdiv(model, "m.msp"), structure::InputError);
  CHECK_THROWS_WITH(spline::compareWithOpenSubdiv(model, "m.msp"),
                    Catch::StartsWith("m.msp: ") && Catch::Contains("T-junctions"));
}
