#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "mspline/spline/core/uniform_bspline.h"

using mspline::spline::uniformBicubicBasis;
using mspline::spline::uniformCubicBasis;

namespace {

// Parameters in [0,1], including both ends.
std::vector<double> samples() {
  std::vector<double> t;
  for (int i = 0; i <= 20; ++i) t.push_back(i / 20.0);
  t.push_back(1e-9);
  t.push_back(1.0 - 1e-9);
  return t;
}

// The curve of 4 consecutive control values at t, with derivatives.
struct CurveValue {
  double value = 0, d1 = 0, d2 = 0;
};
CurveValue segment(const double control[4], double t) {
  double b[4], b1[4], b2[4];
  uniformCubicBasis(t, b, b1, b2);
  CurveValue c;
  for (int k = 0; k < 4; ++k) {
    c.value += b[k] * control[k];
    c.d1 += b1[k] * control[k];
    c.d2 += b2[k] * control[k];
  }
  return c;
}

}  // namespace

TEST_CASE("uniform_bspline: partition of unity, non-negative, derivatives sum to zero",
          "[spline]") {
  for (double t : samples()) {
    double b[4], b1[4], b2[4];
    uniformCubicBasis(t, b, b1, b2);
    CHECK(b[0] + b[1] + b[2] + b[3] == Approx(1.0).margin(1e-15));
    CHECK(b1[0] + b1[1] + b1[2] + b1[3] == Approx(0.0).margin(1e-15));
    CHECK(b2[0] + b2[1] + b2[2] + b2[3] == Approx(0.0).margin(1e-15));
    for (double v : b) CHECK(v >= 0.0);

    double w[16], ws[16], wt[16], wss[16], wst[16], wtt[16];
    const double s = 1.0 - 0.37 * t;
    uniformBicubicBasis(s, t, w, ws, wt, wss, wst, wtt);
    double sums[6] = {0, 0, 0, 0, 0, 0};
    for (int k = 0; k < 16; ++k) {
      sums[0] += w[k];
      sums[1] += ws[k];
      sums[2] += wt[k];
      sums[3] += wss[k];
      sums[4] += wst[k];
      sums[5] += wtt[k];
      CHECK(w[k] >= 0.0);
    }
    CHECK(sums[0] == Approx(1.0).margin(1e-15));
    for (int k = 1; k < 6; ++k) CHECK(sums[k] == Approx(0.0).margin(1e-14));
  }
}

TEST_CASE("uniform_bspline: known values and linear precision", "[spline]") {
  double b[4];
  uniformCubicBasis(0.0, b);
  CHECK(b[0] == Approx(1.0 / 6.0));
  CHECK(b[1] == Approx(4.0 / 6.0));
  CHECK(b[2] == Approx(1.0 / 6.0));
  CHECK(b[3] == 0.0);
  // Control values at the knots' Greville abscissae reproduce linear functions: values k give
  // t + 1; and squares k^2 give (t + 1)^2 + 1/3.
  const double linear[4] = {0, 1, 2, 3}, square[4] = {0, 1, 4, 9};
  for (double t : samples()) {
    const CurveValue l = segment(linear, t), q = segment(square, t);
    CHECK(l.value == Approx(t + 1.0).margin(1e-15));
    CHECK(l.d1 == Approx(1.0).margin(1e-14));
    CHECK(l.d2 == Approx(0.0).margin(1e-14));
    CHECK(q.value == Approx((t + 1.0) * (t + 1.0) + 1.0 / 3.0).margin(1e-14));
    CHECK(q.d1 == Approx(2.0 * (t + 1.0)).margin(1e-14));
    CHECK(q.d2 == Approx(2.0).margin(1e-14));
  }
  // Tensor-product ordering: weight 4 j + i is B_i(s) B_j(t).
  double bs[4], bt[4], w[16];
  uniformCubicBasis(0.3, bs);
  uniformCubicBasis(0.8, bt);
  uniformBicubicBasis(0.3, 0.8, w);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) CHECK(w[4 * j + i] == Approx(bs[i] * bt[j]).margin(1e-16));
}

TEST_CASE("uniform_bspline: derivatives match finite differences", "[spline]") {
  const double h = 1e-6;
  for (double t : samples()) {
    if (t < h || t > 1.0 - h) continue;
    double b[4], b1[4], b2[4], plus[4], minus[4], plus1[4], minus1[4];
    uniformCubicBasis(t, b, b1, b2);
    uniformCubicBasis(t + h, plus, plus1);
    uniformCubicBasis(t - h, minus, minus1);
    for (int k = 0; k < 4; ++k) {
      CHECK(b1[k] == Approx((plus[k] - minus[k]) / (2 * h)).margin(1e-8));
      CHECK(b2[k] == Approx((plus1[k] - minus1[k]) / (2 * h)).margin(1e-8));
    }
  }
  const double s = 0.41, t = 0.67;
  double w[16], ws[16], wt[16], wss[16], wst[16], wtt[16];
  uniformBicubicBasis(s, t, w, ws, wt, wss, wst, wtt);
  double sp[16], sm[16], tp[16], tm[16], sps[16], sms[16], tpt[16], tmt[16], tps[16], tms[16];
  uniformBicubicBasis(s + h, t, sp, sps);
  uniformBicubicBasis(s - h, t, sm, sms);
  uniformBicubicBasis(s, t + h, tp, tps, tpt);
  uniformBicubicBasis(s, t - h, tm, tms, tmt);
  for (int k = 0; k < 16; ++k) {
    CHECK(ws[k] == Approx((sp[k] - sm[k]) / (2 * h)).margin(1e-8));
    CHECK(wt[k] == Approx((tp[k] - tm[k]) / (2 * h)).margin(1e-8));
    CHECK(wss[k] == Approx((sps[k] - sms[k]) / (2 * h)).margin(1e-8));
    CHECK(wst[k] == Approx((tps[k] - tms[k]) / (2 * h)).margin(1e-8));
    CHECK(wtt[k] == Approx((tpt[k] - tmt[k]) / (2 * h)).margin(1e-8));
  }
}

TEST_CASE("uniform_bspline: consecutive segments join with C2 continuity", "[spline]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> control(12);
  for (double& c : control) c = uniform(rng);
  for (std::size_t i = 0; i + 4 < control.size(); ++i) {
    const CurveValue left = segment(&control[i], 1.0), right = segment(&control[i + 1], 0.0);
    CHECK(left.value == Approx(right.value).margin(1e-15));
    CHECK(left.d1 == Approx(right.d1).margin(1e-14));
    CHECK(left.d2 == Approx(right.d2).margin(1e-14));
  }
  // The same in single precision (the template is also used with float).
  float b[4], b1[4], b2[4], next[4], next1[4], next2[4];
  uniformCubicBasis(1.0f, b, b1, b2);
  uniformCubicBasis(0.0f, next, next1, next2);
  CHECK(b[0] == 0.0f);
  CHECK(b1[0] == 0.0f);
  CHECK(b2[0] == 0.0f);
  CHECK(next[3] == 0.0f);
  CHECK(next1[3] == 0.0f);
  CHECK(next2[3] == 0.0f);
  for (int k = 0; k < 3; ++k) {
    CHECK(b[k + 1] == Approx(next[k]).margin(1e-7));
    CHECK(b1[k + 1] == Approx(next1[k]).margin(1e-7));
    CHECK(b2[k + 1] == Approx(next2[k]).margin(1e-7));
  }
}
