#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_adaptive_fit.h"
#include "mspline/structure/core/constants.h"
#include "support/test_tmeshes.h"

using namespace mspline;

TEST_CASE("tspline_adaptive_fit: refines where a bump is and reaches the tolerance", "[spline]") {
  // A periodic 12 x 12 grid over the flat torus [0,12)^2 as a height field with a narrow bump
  // at (6, 6) that the coarse cells cannot follow.
  const int n = 12;
  const spline::TMesh mesh = spline::gridTMesh(test::unitKnots(n), test::unitKnots(n), true, true);
  const auto height = [](double x, double y) {
    const double r2 = (x - 6.0) * (x - 6.0) + (y - 6.0) * (y - 6.0);
    return 0.8 * std::exp(-r2 / 0.15);
  };
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::FacePoint> parameters;
  Eigen::MatrixX3d targets(40 * n * n, 3);
  for (Eigen::Index k = 0; k < targets.rows(); ++k) {
    const double x = n * unit(random), y = n * unit(random);
    const int i = std::min(n - 1, int(x)), j = std::min(n - 1, int(y));
    parameters.push_back({j * n + i, Eigen::Vector2d(x - i, y - j)});
    // Periodic in x and y: a torus-like embedding keeps the surface closed.
    const double a = 2.0 * kPi * x / n, b = 2.0 * kPi * y / n;
    const double lift = height(x, y);
    targets.row(k) << (4.0 + std::cos(b)) * std::cos(a), (4.0 + std::cos(b)) * std::sin(a),
        std::sin(b) + lift;
  }
  spline::TSplineAdaptiveFitOptions options;
  options.tolerance = 4e-3;
  options.maxControlPoints = 600;
  options.maxRefinements = 5;
  const spline::TSplineAdaptiveFitResult result =
      spline::fitTSplineAdaptively(mesh, parameters, targets, options);
  REQUIRE(result.rounds.size() >= 2);
  INFO("first rms " << result.rounds.front().rmsError << " max " << result.rounds.front().maxError
                    << ", last rms " << result.rounds.back().rmsError << " max "
                    << result.rounds.back().maxError << " with "
                    << result.rounds.back().controlPoints << " control points");
  CHECK(result.rounds.front().maxError > options.maxErrorFactor * options.tolerance);
  CHECK(result.rounds.back().maxError < 0.5 * result.rounds.front().maxError);
  CHECK(result.reachedTolerance);
  CHECK(result.rounds.back().controlPoints <= options.maxControlPoints);
  // Refinement is local: new faces only near the bump (cells within three of (6, 6)).
  CHECK(result.mesh.numTJunctions() > 0);
  CHECK(result.mesh.numFaces() < 2 * n * n);
  // The parameters stay on the refined mesh's faces.
  for (const auto& p : result.parameters) {
    REQUIRE(p.face >= 0);
    REQUIRE(p.face < result.mesh.numFaces());
    const auto& face = result.mesh.faces[std::size_t(p.face)];
    CHECK(p.position.x() >= -1e-12);
    CHECK(p.position.x() <= face.width + 1e-12);
  }
}
