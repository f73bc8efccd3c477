#include <catch2/catch.hpp>

#include <random>

#include "mspline/spline/fitting/control_fit.h"
#include "mspline/structure/core/errors.h"
#include "support/test_meshes.h"

using namespace mspline;
using spline::DomainPoint;

TEST_CASE("control_fit: recovers the control points of a spline from its samples", "[spline]") {
  const auto domain = test::flatTorusDomain(5, 0.1);
  const spline::TriBSplineSpace space(
      domain, spline::placeKnotClouds(domain, spline::buildHomeCharts(domain), 3));
  std::mt19937 random(4);
  std::normal_distribution<double> gauss;
  std::uniform_int_distribution<int> face(0, domain.faceCount() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::MatrixXd truth(space.numBasis(), 3);
  for (Eigen::Index i = 0; i < truth.size(); ++i) truth.data()[i] = gauss(random);
  std::vector<DomainPoint> sites;
  Eigen::MatrixXd targets(4000, 3);
  for (int s = 0; s < 4000; ++s) {
    Eigen::Vector3d b(unit(random), unit(random), unit(random));
    sites.push_back({face(random), b / b.sum()});
    targets.row(s) = space.evaluate(truth, sites.back(), 0).position.transpose();
  }
  const auto fit = spline::fitControlPoints(space, sites, targets);
  INFO("rms " << fit.rmsError << ", max " << fit.maxError);
  CHECK(fit.basisWithoutSamples == 0);
  CHECK(fit.maxError <= 5e-3);  // the pull biases a little
  CHECK((fit.controlPoints - truth).cwiseAbs().maxCoeff() <= 5e-2);
  // Without the pull the samples alone determine the control points.
  spline::ControlFitOptions exact;
  exact.regularization = 1e-12;
  const auto sharp = spline::fitControlPoints(space, sites, targets, exact);
  CHECK(sharp.maxError <= 1e-8);
  CHECK((sharp.controlPoints - truth).cwiseAbs().maxCoeff() <= 1e-6);

  CHECK_THROWS_AS(spline::fitControlPoints(space, {}, Eigen::MatrixXd(0, 3)),
                  structure::InputError);
}
