#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "mspline/spline/tribspline/tri_bspline_fit_space.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "support/test_meshes.h"

using namespace mspline;
using spline::FacePoint;
using spline::FitBasisTerm;
using spline::SplineDomain;
using spline::SurfacePoint;
using spline::TriBSplineFitSpace;
using spline::TriBSplineSpace;

namespace {

TriBSplineSpace homeChartSpace(const SplineDomain& domain, int degree) {
  return TriBSplineSpace(domain,
                         spline::placeKnotClouds(domain, spline::buildHomeCharts(domain), degree));
}

// A flat torus of 32 faces without cones and a cube's surface of 48 faces with 8 cones.
std::vector<SplineDomain> domains() {
  const auto cube = test::cubeSurface(1);
  return {test::flatTorusDomain(4, 0.2),
          spline::domainFromMesh(cube, structure::edgeLengths(cube))};
}

// A random point of a random face, each barycentric coordinate at least `margin`.
FacePoint randomParameter(const TriBSplineSpace& space, std::mt19937& random, double margin) {
  const SplineDomain& domain = space.domain();
  std::uniform_int_distribution<int> face(0, domain.faceCount() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Vector3d b(unit(random), unit(random), unit(random));
  b /= b.sum();
  b = Eigen::Vector3d::Constant(margin) + (1.0 - 3.0 * margin) * b;
  return spline::toFitParameter(space, {face(random), b});
}

Eigen::MatrixXd randomControl(int count, std::mt19937& random) {
  std::normal_distribution<double> gauss;
  Eigen::MatrixXd control(count, 3);
  for (Eigen::Index i = 0; i < control.size(); ++i) control.data()[i] = gauss(random);
  return control;
}

// The surface of `control` at p (position, and d/ds, d/dt as columns 1, 2).
Eigen::Matrix3d surfaceAt(const TriBSplineFitSpace& space, const Eigen::MatrixXd& control,
                          const FacePoint& p) {
  std::vector<FitBasisTerm> terms;
  space.basisAt(p, terms, 1);
  REQUIRE(!terms.empty());
  Eigen::Matrix3d result = Eigen::Matrix3d::Zero();
  for (const FitBasisTerm& term : terms) {
    const Eigen::Vector3d c = control.row(term.index).transpose();
    result.col(0) += term.value * c;
    result.col(1) += term.ds * c;
    result.col(2) += term.dt * c;
  }
  return result;
}

std::map<int, FitBasisTerm> termsAt(const TriBSplineFitSpace& space, const FacePoint& p) {
  std::vector<FitBasisTerm> terms;
  space.basisAt(p, terms, 2);
  std::map<int, FitBasisTerm> byIndex;
  for (const FitBasisTerm& term : terms) byIndex[term.index] = term;
  return byIndex;
}

}  // namespace

TEST_CASE("tri_bspline_fit_space: domain points and fit parameters convert both ways", "[spline]") {
  const SplineDomain domain = domains()[1];
  const TriBSplineSpace tri = homeChartSpace(domain, 2);
  std::mt19937 random(3);
  for (int s = 0; s < 50; ++s) {
    const FacePoint p = randomParameter(tri, random, 0.0);
    const SurfacePoint point = spline::toDomainPoint(tri, p);
    CHECK(point.barycentric.sum() == Approx(1.0).epsilon(1e-14));
    CHECK(point.barycentric.minCoeff() >= -1e-14);
    const FacePoint back = spline::toFitParameter(tri, point);
    CHECK(back.face == p.face);
    CHECK((back.position - p.position).norm() <= 1e-14);
  }
  // The corners land on canonicalCorners.
  const auto corners = spline::canonicalCorners(domain, 5);
  for (int k = 0; k < 3; ++k) {
    const SurfacePoint point{5, Eigen::Vector3d::Unit(k)};
    CHECK((spline::toFitParameter(tri, point).position - corners[std::size_t(k)]).norm() <= 1e-15);
  }
}

TEST_CASE("tri_bspline_fit_space: a partition of unity with derivatives that match differences",
          "[spline]") {
  for (const SplineDomain& domain : domains()) {
    const TriBSplineSpace tri = homeChartSpace(domain, 3);
    const TriBSplineFitSpace space(tri);
    CHECK(space.numBasis() == tri.numBasis());
    std::mt19937 random(5);
    // Off the sides by more than h: the offset points stay in the face (walks inside a face).
    std::vector<FacePoint> points;
    for (int s = 0; s < 150; ++s) points.push_back(randomParameter(tri, random, 0.02));
    // And in every corner at a cone, inside its faces' own clouds, where the rational
    // normalization bends the functions.
    for (int f = 0; f < domain.faceCount(); ++f)
      for (int k = 0; k < 3; ++k)
        if (domain.cone[std::size_t(domain.faces[std::size_t(f)][std::size_t(k)])]) {
          Eigen::Vector3d b = Eigen::Vector3d::Constant(0.0012);
          b[(k + 1) % 3] = 0.0018;
          b[k] = 1.0 - b[(k + 1) % 3] - b[(k + 2) % 3];
          points.push_back(spline::toFitParameter(tri, {f, b}));
        }
    double unity = 0.0, slopeSum = 0.0, curvatureSum = 0.0, slopeError = 0.0, curvatureError = 0.0;
    double nearConeSlopeError = 0.0, nearConeCurvatureError = 0.0, minDenominator = 1.0;
    for (std::size_t s = 0; s < points.size(); ++s) {
      const FacePoint& p = points[s];
      const bool nearCone = s >= 150;
      // Near a cone the functions vary on the cone clouds' scale: a smaller difference step.
      const double h = nearCone ? 2e-8 : 2e-6;
      spline::BasisValues raw;
      double denominator = 0.0;
      tri.basisAt(spline::toDomainPoint(tri, p), raw, 0, &denominator);
      minDenominator = std::min(minDenominator, denominator);
      const auto terms = termsAt(space, p);
      REQUIRE(!terms.empty());
      double sum = 0.0;
      Eigen::Matrix<double, 5, 1> derivativeSum = Eigen::Matrix<double, 5, 1>::Zero();
      double slopeScale = 0.0, curvatureScale = 0.0;
      for (const auto& [index, term] : terms) {
        sum += term.value;
        derivativeSum +=
            Eigen::Matrix<double, 5, 1>(term.ds, term.dt, term.dss, term.dst, term.dtt);
        slopeScale = std::max({slopeScale, std::abs(term.ds), std::abs(term.dt)});
        curvatureScale =
            std::max({curvatureScale, std::abs(term.dss), std::abs(term.dst), std::abs(term.dtt)});
      }
      unity = std::max(unity, std::abs(sum - 1.0));
      slopeSum = std::max(slopeSum, derivativeSum.head<2>().cwiseAbs().maxCoeff() / slopeScale);
      curvatureSum =
          std::max(curvatureSum, derivativeSum.tail<3>().cwiseAbs().maxCoeff() / curvatureScale);
      for (int axis = 0; axis < 2; ++axis) {
        const Eigen::Vector2d step = h * Eigen::Vector2d::Unit(axis);
        const FacePoint plus = space.walk(p, step), minus = space.walk(p, -step);
        REQUIRE(plus.face == p.face);
        REQUIRE(minus.face == p.face);
        CHECK((plus.position - p.position - step).norm() <= 1e-15);
        const auto above = termsAt(space, plus), below = termsAt(space, minus);
        for (const auto& [index, term] : terms) {
          // By value: C++17 lambdas cannot capture a structured binding (clang refuses).
          const auto get = [&, key = index](const std::map<int, FitBasisTerm>& at) {
            const auto found = at.find(key);
            return found == at.end() ? FitBasisTerm{} : found->second;
          };
          const FitBasisTerm a = get(above), b = get(below);
          const double slope = (a.value - b.value) / (2.0 * h);
          double& slopeWorst = nearCone ? nearConeSlopeError : slopeError;
          slopeWorst =
              std::max(slopeWorst, std::abs(slope - (axis == 0 ? term.ds : term.dt)) / slopeScale);
          // d/ds and d/dt differentiated along the axis: (dss, dst) or (dst, dtt).
          const Eigen::Vector2d curvature = Eigen::Vector2d(a.ds - b.ds, a.dt - b.dt) / (2.0 * h);
          const Eigen::Vector2d exact =
              axis == 0 ? Eigen::Vector2d(term.dss, term.dst) : Eigen::Vector2d(term.dst, term.dtt);
          double& curvatureWorst = nearCone ? nearConeCurvatureError : curvatureError;
          curvatureWorst =
              std::max(curvatureWorst, (curvature - exact).cwiseAbs().maxCoeff() / curvatureScale);
        }
      }
    }
    INFO("faces " << domain.faceCount());
    CHECK(unity <= 1e-13);
    CHECK(slopeSum <= 1e-12);
    CHECK(curvatureSum <= 1e-11);
    CHECK(slopeError <= 1e-6);
    CHECK(curvatureError <= 1e-6);
    // The cube's corners: denominators well below 1 met, derivatives still right.
    if (domain.faceCount() == 48) CHECK(minDenominator < 0.5);
    CHECK(nearConeSlopeError <= 1e-6);
    CHECK(nearConeCurvatureError <= 1e-6);
  }
}

TEST_CASE("tri_bspline_fit_space: walks across sides are reversible and continuous", "[spline]") {
  for (const SplineDomain& domain : domains()) {
    const TriBSplineSpace tri = homeChartSpace(domain, 3);
    const TriBSplineFitSpace space(tri);
    std::mt19937 random(7);
    const Eigen::MatrixXd control = randomControl(space.numBasis(), random);
    std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
    int faceChanges = 0;
    double backError = 0.0, pieceError = 0.0, sideJump = 0.0;
    for (int s = 0; s < 30; ++s) {
      const FacePoint p = randomParameter(tri, random, 0.0);
      const double phi = angle(random);
      // About three cells long: several sides crossed.
      const Eigen::Vector2d step = 3.0 * Eigen::Vector2d(std::cos(phi), std::sin(phi));
      Eigen::Vector2d turned;
      const FacePoint end = space.walk(p, step, turned);
      CHECK(turned.norm() == Approx(step.norm()).epsilon(1e-12));
      const FacePoint back = space.walk(end, -turned);
      backError =
          std::max(backError,
                   (surfaceAt(space, control, back) - surfaceAt(space, control, p)).col(0).norm());
      // The same walk in 200 pieces, each turned into the frame reached: the same end, and the
      // surface continuous where a piece crosses a side.
      FacePoint at = p;
      Eigen::Vector2d piece = step / 200.0;
      Eigen::Matrix3d previous = surfaceAt(space, control, at);
      for (int k = 0; k < 200; ++k) {
        Eigen::Vector2d turnedPiece;
        const FacePoint next = space.walk(at, piece, turnedPiece);
        faceChanges += next.face != at.face;
        if (next.face != at.face) {
          // Where the piece leaves the face, by bisection: the surface just before and just
          // after is the same.
          double inside = 0.0, outside = 1.0;
          for (int b = 0; b < 50; ++b) {
            const double middle = 0.5 * (inside + outside);
            (space.walk(at, middle * piece).face == at.face ? inside : outside) = middle;
          }
          sideJump = std::max(sideJump, (surfaceAt(space, control, space.walk(at, inside * piece)) -
                                         surfaceAt(space, control, space.walk(at, outside * piece)))
                                            .col(0)
                                            .norm());
        }
        previous = surfaceAt(space, control, next);
        at = next;
        piece = turnedPiece;
      }
      pieceError =
          std::max(pieceError, (previous.col(0) - surfaceAt(space, control, end).col(0)).norm());
    }
    INFO("faces " << domain.faceCount());
    CHECK(faceChanges >= 30 * 3);
    CHECK(backError <= 1e-9);
    CHECK(pieceError <= 1e-9);
    CHECK(sideJump <= 1e-9);
  }
}

TEST_CASE("tri_bspline_fit_space: a walk into a cone stops just before it", "[spline]") {
  const SplineDomain domain = domains()[1];
  const TriBSplineSpace tri = homeChartSpace(domain, 3);
  const TriBSplineFitSpace space(tri);
  int tried = 0;
  for (int f = 0; f < domain.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) {
      if (!domain.cone[std::size_t(domain.faces[std::size_t(f)][std::size_t(k)])]) continue;
      ++tried;
      const auto corners = spline::canonicalCorners(domain, f);
      const FacePoint centre =
          spline::toFitParameter(tri, {f, Eigen::Vector3d::Constant(1.0 / 3.0)});
      // Aimed at the cone and twice as far: without the stop the walk would go past it.
      const FacePoint end = space.walk(centre, 2.0 * (corners[std::size_t(k)] - centre.position));
      CHECK(end.face == f);
      const double distance = (end.position - corners[std::size_t(k)]).norm();
      const double perimeter = domain.sideLengths[std::size_t(f)][0] +
                               domain.sideLengths[std::size_t(f)][1] +
                               domain.sideLengths[std::size_t(f)][2];
      CHECK(distance > 0.5e-6 * perimeter);
      CHECK(distance < 2e-6 * perimeter);
    }
  CHECK(tried >= 24);
}

TEST_CASE("tri_bspline_fit_space: the quadrature integrates quartics over the domain exactly",
          "[spline]") {
  for (const SplineDomain& domain : domains()) {
    const TriBSplineSpace tri = homeChartSpace(domain, 2);
    const TriBSplineFitSpace space(tri);
    std::vector<FacePoint> nodes;
    std::vector<double> weights;
    space.quadrature(nodes, weights);
    REQUIRE(nodes.size() == weights.size());
    CHECK(int(nodes.size()) == 28 * domain.faceCount());
    double total = 0.0, area = 0.0;
    for (double w : weights) total += w;
    for (const auto& l : domain.sideLengths)
      area += 0.25 * structure::fourTimesArea(l[0], l[1], l[2]);
    // The torus: 16 unit cells; the cube: six faces of area 4.
    CHECK(area == Approx(domain.faceCount() == 32 ? 16.0 : 24.0).epsilon(1e-12));
    CHECK(total == Approx(area).epsilon(1e-12));
    // A linear function L with corner values a, b, c: the integral of L^4 over a triangle of area
    // A is A / 15 sum_{i+j+k=4} a^i b^j c^k.
    const Eigen::Vector2d gradient(0.7, -0.3);
    std::vector<double> quartic(std::size_t(domain.faceCount()), 0.0);
    for (std::size_t k = 0; k < nodes.size(); ++k)
      quartic[std::size_t(nodes[k].face)] +=
          weights[k] * std::pow(1.0 + gradient.dot(nodes[k].position), 4);
    for (int f = 0; f < domain.faceCount(); ++f) {
      const auto corners = spline::canonicalCorners(domain, f);
      std::array<double, 3> value;
      for (std::size_t c = 0; c < 3; ++c) value[c] = 1.0 + gradient.dot(corners[c]);
      double sum = 0.0;
      for (int i = 0; i <= 4; ++i)
        for (int j = 0; i + j <= 4; ++j)
          sum += std::pow(value[0], i) * std::pow(value[1], j) * std::pow(value[2], 4 - i - j);
      const auto& l = domain.sideLengths[std::size_t(f)];
      CHECK(quartic[std::size_t(f)] ==
            Approx(0.25 * structure::fourTimesArea(l[0], l[1], l[2]) / 15.0 * sum).epsilon(1e-12));
    }
  }
}
