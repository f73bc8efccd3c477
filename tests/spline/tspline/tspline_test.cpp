#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_bezier.h"
#include "mspline/spline/tspline/tspline_check.h"
#include "mspline/structure/core/errors.h"
#include "support/test_tmeshes.h"

using namespace mspline;
using spline::TMesh;
using spline::TSplineSpace;
using test::faceOrigins;
using test::mergedBlock;
using test::stoppedLine;
using test::unitKnots;
using test::vertexAt;

TEST_CASE("tspline: a uniform grid has uniform knots, padded beyond its boundary", "[spline]") {
  const TSplineSpace space(spline::gridTMesh(unitKnots(8), unitKnots(8)));
  CHECK(space.numBasis() == 81);
  CHECK(space.missingAnchors().empty());
  for (const auto& anchor : space.anchors()) {
    const std::array<double, 5> uniform{-2, -1, 0, 1, 2};
    CHECK(anchor.sKnots == uniform);
    CHECK(anchor.tKnots == uniform);
  }
  // Faces one cell or more inside the boundary have all 16 functions: a partition of unity.
  std::mt19937 random(2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::TSplineBasisValue> basis;
  for (int j = 1; j < 7; ++j)
    for (int i = 1; i < 7; ++i) {
      space.basisAt(j * 8 + i, Eigen::Vector2d(unit(random), unit(random)), basis);
      double sum = 0.0;
      for (const auto& b : basis) sum += b.value;
      CHECK(basis.size() == 16);
      CHECK(sum == Approx(1.0).margin(1e-14));
    }
  space.basisAt(0, Eigen::Vector2d(0.5, 0.5), basis);
  CHECK(basis.size() == 9);
}

TEST_CASE("tspline: knots are inferred through T-junctions", "[spline]") {
  const TMesh mesh = mergedBlock();
  const TSplineSpace space(mesh);
  const auto origin = faceOrigins(mesh, {2, 2});
  CHECK(mesh.numVertices == 48);
  CHECK(space.numBasis() == 48);
  // Below the block: the vertical ray from (3, 1) meets y = 2, then nothing until y = 4.
  const auto& below = space.anchors()[space.anchorOfVertex()[vertexAt(mesh, origin, {3, 1})]];
  CHECK(below.tKnots == std::array<double, 5>{-2, -1, 0, 1, 3});
  CHECK(below.sKnots == std::array<double, 5>{-2, -1, 0, 1, 2});
  // At the T-junction (3, 2): up through the block to (3, 4), then (3, 5).
  const auto& junction = space.anchors()[space.anchorOfVertex()[vertexAt(mesh, origin, {3, 2})]];
  CHECK(junction.tKnots == std::array<double, 5>{-2, -1, 0, 2, 3});
  CHECK(junction.sKnots == std::array<double, 5>{-2, -1, 0, 1, 2});
  // Left of the block on its middle line: (1, 3) sees x = 2, then (4, 3) across the block.
  const auto& left = space.anchors()[space.anchorOfVertex()[vertexAt(mesh, origin, {1, 3})]];
  CHECK(left.sKnots == std::array<double, 5>{-2, -1, 0, 1, 3});
}

TEST_CASE("tspline: an analysis-suitable T-mesh is a partition of unity inside", "[spline]") {
  const TMesh mesh = stoppedLine();
  const TSplineSpace space(mesh);
  const auto origin = faceOrigins(mesh, {3, 4});
  CHECK(space.missingAnchors().empty());
  std::mt19937 random(4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::TSplineBasisValue> basis;
  double worst = 0.0;
  int samples = 0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const auto& face = mesh.faces[f];
    const Eigen::Vector2d lo = origin[std::size_t(f)];
    // Away from the boundary, where every function has its own knots.
    if (lo.minCoeff() < 2.0 || lo.x() + face.width > 6.0 || lo.y() + face.height > 6.0) continue;
    for (int s = 0; s < 50; ++s) {
      space.basisAt(f, Eigen::Vector2d(unit(random) * face.width, unit(random) * face.height),
                    basis);
      double sum = 0.0;
      for (const auto& b : basis) sum += b.value;
      worst = std::max(worst, std::abs(sum - 1.0));
      ++samples;
    }
  }
  CHECK(samples > 500);
  CHECK(worst <= 1e-12);
}

TEST_CASE("tspline: T-junctions facing each other need the rational normalization", "[spline]") {
  const TMesh mesh = mergedBlock();
  const TSplineSpace space(mesh);
  std::mt19937 random(5);
  Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
  spline::TSplineCheckOptions options;
  options.samples = 4000;
  const auto check = spline::checkTSpline(space, control, {}, options);
  // The block's neighbourhood sums to less (or more) than one; the rational form still evaluates.
  CHECK(check.normalizedSamples > 0);
  CHECK(check.partitionOfUnityError > 1e-6);
  CHECK(check.holeSamples == 0);
  CHECK(check.minDenominator > 0.1);
  CHECK(check.chartDiscrepancy <= 1e-14);
  CHECK(check.knotRouteDiscrepancy <= 1e-14);
  CHECK(check.bezierDiscrepancy <= 1e-12);
}

TEST_CASE("tspline: derivatives of the rational surface match finite differences", "[spline]") {
  const TMesh mesh = mergedBlock();
  const TSplineSpace space(mesh);
  std::mt19937 random(6);
  std::uniform_real_distribution<double> unit(0.05, 0.95);
  const Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
  const Eigen::VectorXd weights = test::randomWeights(space.numBasis(), random);
  const double h = 1e-5;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const auto& face = mesh.faces[f];
    const Eigen::Vector2d p(unit(random) * face.width, unit(random) * face.height);
    const auto at = [&](double dx, double dy) {
      return space.evaluate(control, weights, f, p + Eigen::Vector2d(dx, dy), 1);
    };
    const auto point = space.evaluate(control, weights, f, p, 2);
    CHECK((point.ds - (at(h, 0).position - at(-h, 0).position) / (2 * h)).norm() < 1e-7);
    CHECK((point.dt - (at(0, h).position - at(0, -h).position) / (2 * h)).norm() < 1e-7);
    CHECK((point.dss - (at(h, 0).ds - at(-h, 0).ds) / (2 * h)).norm() < 1e-6);
    CHECK((point.dst - (at(0, h).ds - at(0, -h).ds) / (2 * h)).norm() < 1e-6);
    CHECK((point.dtt - (at(0, h).dt - at(0, -h).dt) / (2 * h)).norm() < 1e-6);
    // The unit normal, perpendicular to both tangents.
    REQUIRE(point.normal.size() == 3);
    CHECK(point.normal.norm() == Approx(1.0).margin(1e-12));
    CHECK(std::abs(point.normal.dot(point.ds)) <= 1e-12 * point.ds.norm());
    CHECK(std::abs(point.normal.dot(point.dt)) <= 1e-12 * point.dt.norm());
    CHECK(Eigen::Vector3d(point.ds)
              .cross(Eigen::Vector3d(point.dt))
              .dot(Eigen::Vector3d(point.normal)) > 0.0);
  }
}

TEST_CASE("tspline: Bezier extraction reproduces the T-spline", "[spline]") {
  for (const TMesh& mesh :
       {mergedBlock(), stoppedLine(), spline::gridTMesh(unitKnots(7), unitKnots(6), true, true)}) {
    const TSplineSpace space(mesh);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
    const Eigen::VectorXd weights = test::randomWeights(space.numBasis(), random);
    const spline::TSplineBezier bezier(space, control, weights);
    CHECK(bezier.numElements() >= mesh.numFaces());
    double worst = 0.0, worstDerivative = 0.0;
    for (int s = 0; s < 2000; ++s) {
      const int f = std::uniform_int_distribution<int>(0, mesh.numFaces() - 1)(random);
      const auto& face = mesh.faces[f];
      const Eigen::Vector2d p(unit(random) * face.width, unit(random) * face.height);
      const auto direct = space.evaluate(control, weights, f, p);
      Eigen::Vector3d x, du, dv;
      bezier.evaluate(f, p, x, &du, &dv);
      worst = std::max(worst, (x - direct.position).norm());
      worstDerivative =
          std::max({worstDerivative, (du - direct.ds).norm(), (dv - direct.dt).norm()});
    }
    CHECK(worst <= 1e-12);
    CHECK(worstDerivative <= 1e-11);
  }
}

TEST_CASE("tspline: a periodic grid is a closed partition of unity, seamless", "[spline]") {
  const TSplineSpace space(spline::gridTMesh(unitKnots(9), unitKnots(5), true, true));
  CHECK(space.numBasis() == 45);
  const Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
  spline::TSplineCheckOptions options;
  options.samples = 3000;
  const auto check = spline::checkTSpline(space, control, {}, options);
  CHECK(check.partitionOfUnityError <= 1e-14);
  CHECK(check.normalizedSamples == 0);
  CHECK(check.edgeSamples > 2000);
  CHECK(check.chartDiscrepancy <= 1e-15);
  CHECK(check.bezierDiscrepancy <= 1e-14);
}

TEST_CASE("tspline: wrong control point counts are refused", "[spline]") {
  const TSplineSpace space(spline::gridTMesh(unitKnots(4), unitKnots(4)));
  CHECK_THROWS_AS(space.evaluate(Eigen::MatrixXd::Zero(3, 3), {}, 0, Eigen::Vector2d(0.5, 0.5)),
                  structure::InputError);
  CHECK_THROWS_AS(space.evaluate(Eigen::MatrixXd::Zero(25, 3), Eigen::VectorXd::Ones(2), 0,
                                 Eigen::Vector2d(0.5, 0.5)),
                  structure::InputError);
  CHECK_THROWS_AS(spline::TSplineBezier(space, Eigen::MatrixXd::Zero(25, 2)),
                  structure::InputError);
}
