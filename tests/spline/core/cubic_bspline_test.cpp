#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "mspline/spline/core/cubic_bspline.h"
#include "mspline/spline/core/uniform_bspline.h"

using mspline::spline::cubicBSpline;

TEST_CASE("cubic_bspline: uniform knots give the uniform basis pieces", "[spline]") {
  const double knots[5] = {-2.0, -1.0, 0.0, 1.0, 2.0};
  for (double t : {0.0, 0.1, 0.5, 0.9}) {
    double uniform[4], d1[4], d2[4];
    mspline::spline::uniformCubicBasis(t, uniform, d1, d2);
    // On [0,1] this B-spline is the piece of basis function 1 (its knots start two intervals left).
    double derivative = 0.0, second = 0.0;
    CHECK(cubicBSpline(knots, t, &derivative, &second) == Approx(uniform[1]).margin(1e-15));
    CHECK(derivative == Approx(d1[1]).margin(1e-14));
    CHECK(second == Approx(d2[1]).margin(1e-13));
    CHECK(cubicBSpline(knots, t - 1.0) == Approx(uniform[2]).margin(1e-15));
  }
  CHECK(cubicBSpline(knots, 2.0) == 0.0);
  CHECK(cubicBSpline(knots, -2.0) == 0.0);
}

TEST_CASE("cubic_bspline: derivatives match finite differences on uneven knots", "[spline]") {
  const double knots[5] = {-1.5, -0.25, 0.0, 2.0, 2.75};
  std::mt19937 random(3);
  std::uniform_real_distribution<double> x(-1.45, 2.7);
  const double h = 1e-6;
  for (int s = 0; s < 200; ++s) {
    const double t = x(random);
    double d1 = 0.0, d2 = 0.0, d1Plus = 0.0, d1Minus = 0.0;
    cubicBSpline(knots, t, &d1, &d2);
    const double fd = (cubicBSpline(knots, t + h) - cubicBSpline(knots, t - h)) / (2 * h);
    cubicBSpline(knots, t + h, &d1Plus);
    cubicBSpline(knots, t - h, &d1Minus);
    CHECK(d1 == Approx(fd).margin(1e-8));
    CHECK(d2 == Approx((d1Plus - d1Minus) / (2 * h)).margin(1e-6));
  }
}

TEST_CASE("cubic_bspline: B-splines on shared knots sum to one", "[spline]") {
  const double line[9] = {0.0, 0.5, 1.75, 2.0, 3.5, 4.0, 4.25, 6.0, 7.0};
  // On [2, 3.5] exactly four consecutive B-splines are non-zero.
  for (double t = 2.0; t < 3.5; t += 0.01) {
    double sum = 0.0;
    for (int first = 0; first + 4 < 9; ++first) sum += cubicBSpline(line + first, t);
    CHECK(sum == Approx(1.0).margin(1e-14));
  }
  // Repeated knots (zero spans) are allowed.
  const double repeated[5] = {0.0, 0.0, 0.0, 1.0, 2.0};
  CHECK(std::isfinite(cubicBSpline(repeated, 0.5)));
  CHECK(cubicBSpline(repeated, 0.5) > 0.0);
}
