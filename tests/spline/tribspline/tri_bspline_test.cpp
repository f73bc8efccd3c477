#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "support/test_meshes.h"

using namespace mspline;
using spline::SplineDomain;
using spline::SurfacePoint;
using spline::TriBSplineSpace;

namespace {

TriBSplineSpace makeSpace(const SplineDomain& domain, int degree, std::uint64_t seed = 1) {
  spline::KnotCloudOptions options;
  options.seed = seed;
  return TriBSplineSpace(
      domain, spline::placeKnotClouds(domain, spline::buildHomeCharts(domain), degree, options));
}

SurfacePoint randomPoint(const SplineDomain& domain, std::mt19937& random) {
  std::uniform_int_distribution<int> face(0, domain.faceCount() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Vector3d b(unit(random), unit(random), unit(random));
  return {face(random), b / b.sum()};
}

// The same point of side `side` of face f (parameter t from corner side to corner side+1), seen
// from f and from the face across.
std::pair<SurfacePoint, SurfacePoint> sidePoint(const SplineDomain& domain, int f, int side,
                                                double t) {
  SurfacePoint here{f, Eigen::Vector3d::Zero()};
  here.barycentric[side] = 1.0 - t;
  here.barycentric[(side + 1) % 3] = t;
  const int g = domain.neighbour[std::size_t(f)][std::size_t(side)];
  const int gs = domain.neighbourSide[std::size_t(f)][std::size_t(side)];
  SurfacePoint there{g, Eigen::Vector3d::Zero()};
  there.barycentric[gs] = t;
  there.barycentric[(gs + 1) % 3] = 1.0 - t;
  return {here, there};
}

struct Figures {
  double unity = 0.0;     // max |sum of normalized basis - 1|
  double rawUnity = 0.0;  // max |denominator - 1| over points with no cone nearby
  double minDenominator = 1e300;
  double chartDiscrepancy = 0.0;
  // Across sides: position, and first derivatives relative to their size, both times the
  // denominator (rounding is amplified by its inverse); the smallest denominator there.
  double jump = 0.0;
  double slopeJump = 0.0;
  double minSideDenominator = 1e300;
};

// Every face whose contributors have no cone corner: there the DMS identities hold exactly.
bool awayFromCones(const TriBSplineSpace& space, int face) {
  for (int k : space.chartsHolding(face))
    for (int v : space.domain().faces[std::size_t(k)])
      if (space.domain().cone[std::size_t(v)]) return false;
  return true;
}

Figures measure(const TriBSplineSpace& space, int samples) {
  const SplineDomain& domain = space.domain();
  std::mt19937 random(11);
  std::normal_distribution<double> gauss;
  Eigen::MatrixXd control(space.numBasis(), 3);
  for (Eigen::Index i = 0; i < control.size(); ++i) control.data()[i] = gauss(random);
  Figures figures;
  spline::BasisValues basis;
  for (int s = 0; s < samples; ++s) {
    const SurfacePoint p = randomPoint(domain, random);
    double denominator = 0.0;
    space.basisAt(p, basis, 0, &denominator);
    double sum = 0.0;
    for (double v : basis.value) sum += v;
    figures.unity = std::max(figures.unity, std::abs(sum - 1.0));
    figures.minDenominator = std::min(figures.minDenominator, denominator);
    if (awayFromCones(space, p.face))
      figures.rawUnity = std::max(figures.rawUnity, std::abs(denominator - 1.0));
    const Eigen::VectorXd value = space.evaluate(control, p, 0).position;
    // Moving the knots re-evaluates every simplex spline from scratch: on some samples only.
    for (int chart = 0; chart < int(space.chartsHolding(p.face).size()); ++chart)
      for (auto route :
           {TriBSplineSpace::ChartRoute::MovePoint, TriBSplineSpace::ChartRoute::MoveKnots})
        if (route == TriBSplineSpace::ChartRoute::MovePoint || s < 40)
          figures.chartDiscrepancy =
              std::max(figures.chartDiscrepancy,
                       (space.evaluateInChart(control, p, chart, route) - value).norm());
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int f = 0; f < domain.faceCount(); ++f)
    for (int side = 0; side < 3; ++side) {
      const auto [here, there] = sidePoint(domain, f, side, unit(random));
      const auto a = space.evaluate(control, here, 1);
      const auto b = space.evaluate(control, there, 1);
      // Derivatives in f's frame from those in g's frame: y = R x + t, so d/dx = R^T d/dy.
      const auto& chart = space.charts()[std::size_t(there.face)];
      const double angle = chart.placement[std::size_t(chart.find(f))].angle;
      const double c = std::cos(angle), s = std::sin(angle);
      const Eigen::VectorXd du = c * b.du + s * b.dv, dv = -s * b.du + c * b.dv;
      const double scale = 1.0 + a.du.norm() + a.dv.norm();
      // Rounding, divided by the denominator where it is small (sides at cones, near the cone).
      double denominator = 0.0;
      space.basisAt(here, basis, 0, &denominator);
      figures.minSideDenominator = std::min(figures.minSideDenominator, denominator);
      figures.jump = std::max(figures.jump, (a.position - b.position).norm() * denominator);
      figures.slopeJump = std::max({figures.slopeJump, (a.du - du).norm() / scale * denominator,
                                    (a.dv - dv).norm() / scale * denominator});
    }
  return figures;
}

}  // namespace

TEST_CASE("tri_bspline: a flat torus is a partition of unity in every chart", "[spline]") {
  for (int degree : {2, 3}) {
    const TriBSplineSpace space = makeSpace(test::flatTorusDomain(6, 0.2), degree);
    CHECK(space.numBasis() == 72 * (degree + 1) * (degree + 2) / 2);
    const Figures figures = measure(space, 300);
    INFO("degree " << degree);
    CHECK(figures.rawUnity <= 1e-13);
    CHECK(figures.unity <= 1e-13);
    CHECK(figures.chartDiscrepancy <= 1e-12);
    CHECK(figures.jump <= 1e-11);
    CHECK(figures.slopeJump <= 1e-9);
  }
}

TEST_CASE("tri_bspline: a cube's cones are closed up by the rational normalization", "[spline]") {
  const auto mesh = test::cubeSurface(2);
  const SplineDomain domain = spline::domainFromMesh(mesh, structure::edgeLengths(mesh));
  int cones = 0;
  for (char c : domain.cone) cones += c;
  REQUIRE(cones == 8);
  const TriBSplineSpace space = makeSpace(domain, 3);
  const Figures figures = measure(space, 300);
  WARN("cube: min denominator " << figures.minDenominator << ", raw unity away from cones "
                                << figures.rawUnity << ", jumps " << figures.jump << ", "
                                << figures.slopeJump << ", min denominator on sides "
                                << figures.minSideDenominator);
  CHECK(figures.minSideDenominator > 0.0);
  CHECK(figures.minDenominator > 0.05);
  CHECK(figures.rawUnity <= 1e-13);
  CHECK(figures.unity <= 1e-13);
  CHECK(figures.chartDiscrepancy <= 1e-12);
  CHECK(figures.jump <= 1e-11);
  CHECK(figures.slopeJump <= 1e-9);
}

TEST_CASE("tri_bspline: batch evaluation agrees with single points", "[spline]") {
  // The batch sums the raw functions and normalizes once per point, from the faces' polynomials
  // where only a face's own functions reach; single points normalize every function.
  const auto cube = test::cubeSurface(2);
  for (const SplineDomain& domain : {test::flatTorusDomain(5, 0.2),
                                     spline::domainFromMesh(cube, structure::edgeLengths(cube))}) {
    const TriBSplineSpace space = makeSpace(domain, 3);
    std::mt19937 random(21);
    std::vector<SurfacePoint> points;
    for (int s = 0; s < 2000; ++s) points.push_back(randomPoint(domain, random));
    // On sides and close to corners too.
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int f = 0; f < domain.faceCount(); ++f)
      for (int side = 0; side < 3; ++side) {
        points.push_back(sidePoint(domain, f, side, unit(random)).first);
        SurfacePoint corner{f, Eigen::Vector3d::Constant(0.005 + 0.01 * unit(random))};
        corner.barycentric[side] = 1.0 - corner.barycentric.sum() + corner.barycentric[side];
        points.push_back(corner);
      }
    for (int dims : {3, 2}) {
      std::normal_distribution<double> gauss;
      Eigen::MatrixXd control(space.numBasis(), dims);
      for (Eigen::Index i = 0; i < control.size(); ++i) control.data()[i] = gauss(random);
      spline::SplineSamples samples;
      for (int derivatives : {2, 1, 0}) {
        space.evaluateBatch(control, points, derivatives, samples);
        CHECK(samples.position.rows() == Eigen::Index(points.size()));
        CHECK(samples.du.size() == (derivatives >= 1 ? Eigen::Index(points.size()) * dims : 0));
        CHECK(samples.dvv.size() == (derivatives >= 2 ? Eigen::Index(points.size()) * dims : 0));
        CHECK(samples.normal.size() ==
              (derivatives >= 1 && dims == 3 ? Eigen::Index(points.size()) * 3 : 0));
        // Per order of derivative: the largest difference relative to the size of the value.
        std::array<double, 3> worst{};
        for (std::size_t k = 0; k < points.size(); ++k) {
          const spline::SplinePoint single = space.evaluate(control, points[k], derivatives);
          // Rounding grows like the inverse denominator near cones.
          double denominator = 0.0;
          spline::BasisValues basis;
          space.basisAt(points[k], basis, 0, &denominator);
          const auto error = [&](const Eigen::MatrixXd& batch, const Eigen::VectorXd& one) {
            return (batch.row(Eigen::Index(k)).transpose() - one).norm() * denominator /
                   (1.0 + one.norm());
          };
          worst[0] = std::max(worst[0], error(samples.position, single.position));
          if (derivatives >= 1) {
            worst[1] =
                std::max({worst[1], error(samples.du, single.du), error(samples.dv, single.dv)});
            // The normal's rounding also grows as du and dv become parallel.
            if (dims == 3)
              worst[1] =
                  std::max(worst[1],
                           error(samples.normal, single.normal) *
                               Eigen::Vector3d(single.du).cross(Eigen::Vector3d(single.dv)).norm() /
                               ((1.0 + single.du.norm()) * (1.0 + single.dv.norm())));
          }
          if (derivatives >= 2)
            worst[2] = std::max({worst[2], error(samples.duu, single.duu),
                                 error(samples.duv, single.duv), error(samples.dvv, single.dvv)});
        }
        INFO("faces " << domain.faceCount() << ", dimension " << dims << ", derivatives "
                      << derivatives);
        CHECK(worst[0] <= 1e-13);
        CHECK(worst[1] <= 1e-11);
        CHECK(worst[2] <= 1e-9);
      }
    }
  }
}

TEST_CASE("tri_bspline: knots that do not fit the domain are refused", "[spline]") {
  const SplineDomain domain = test::flatTorusDomain(4);
  auto knots = spline::placeKnotClouds(domain, spline::buildHomeCharts(domain), 3);
  auto missing = knots;
  missing[3][1].pop_back();
  CHECK_THROWS_AS(TriBSplineSpace(domain, missing), structure::InputError);
  auto moved = knots;
  moved[2][0][0] += Eigen::Vector2d(0.1, 0.0);
  CHECK_THROWS_WITH(TriBSplineSpace(domain, moved), Catch::Contains("is not the corner"));
  knots.pop_back();
  CHECK_THROWS_AS(TriBSplineSpace(domain, knots), structure::InputError);
}
