#include <catch2/catch.hpp>

#include <random>
#include <vector>

#include "mspline/spline/fitting/tspline_fit.h"
#include "mspline/structure/core/errors.h"

using namespace mspline;

TEST_CASE("tspline_fit: samples of a T-spline give back its control points", "[spline]") {
  std::vector<double> xs, ys;
  for (int i = 0; i <= 12; ++i) xs.push_back(i);
  for (int j = 0; j <= 9; ++j) ys.push_back(0.5 * j * j);
  const spline::TSplineSpace space(spline::gridTMesh(xs, ys, true, false));
  std::mt19937 random(1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
  std::vector<spline::TMeshPoint> sites;
  for (int s = 0; s < 20 * space.numBasis(); ++s) {
    const int f = int(random() % std::size_t(space.mesh().numFaces()));
    const auto& face = space.mesh().faces[std::size_t(f)];
    sites.push_back({f, Eigen::Vector2d(unit(random) * face.width, unit(random) * face.height)});
  }
  Eigen::MatrixXd targets(Eigen::Index(sites.size()), 3);
  for (std::size_t s = 0; s < sites.size(); ++s)
    targets.row(Eigen::Index(s)) =
        space.evaluate(control, {}, sites[s].face, sites[s].position, 0).position.transpose();
  spline::TSplineFitOptions options;
  options.regularization = 1e-12;
  const auto fit = spline::fitTSplineControlPoints(space, sites, targets, options);
  CHECK(fit.basisWithoutSamples == 0);
  CHECK(fit.sitesInHoles == 0);
  CHECK(fit.maxError < 1e-9);
  CHECK((fit.controlPoints - control).cwiseAbs().maxCoeff() < 1e-7);
}

TEST_CASE("tspline_fit: mismatched or misplaced sites are refused", "[spline]") {
  std::vector<double> knots{0, 1, 2, 3, 4, 5};
  const spline::TSplineSpace space(spline::gridTMesh(knots, knots));
  CHECK_THROWS_AS(spline::fitTSplineControlPoints(space, {}, Eigen::MatrixXd(0, 3)),
                  structure::InputError);
  CHECK_THROWS_AS(spline::fitTSplineControlPoints(space, {{0, Eigen::Vector2d(0.5, 0.5)}},
                                                  Eigen::MatrixXd::Zero(2, 3)),
                  structure::InputError);
  CHECK_THROWS_AS(spline::fitTSplineControlPoints(space, {{99, Eigen::Vector2d(0.5, 0.5)}},
                                                  Eigen::MatrixXd::Zero(1, 3)),
                  structure::InputError);
}
