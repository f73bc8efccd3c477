#pragma once
// One cubic B-spline with arbitrary (non-decreasing) knots: the univariate factor of a T-spline
// blending function, evaluated with Cox-de Boor's recurrence.
#include <cstddef>

namespace mspline::spline {

/// The cubic B-spline on the knots k[0] <= ... <= k[4] at x, with optional first (d1) and second
/// (d2) derivatives. Its support is the half-open [k[0], k[4]); spans of zero length contribute
/// nothing (0/0 read as 0), so repeated knots are allowed.
template <class Scalar>
Scalar cubicBSpline(const Scalar k[5], Scalar x, Scalar* d1 = nullptr, Scalar* d2 = nullptr) {
  if (d1) *d1 = Scalar(0);
  if (d2) *d2 = Scalar(0);
  if (!(x >= k[0] && x < k[4])) return Scalar(0);
  const auto ratio = [](Scalar a, Scalar b) { return b > Scalar(0) ? a / b : Scalar(0); };
  // Degree 0 .. 3, each row one entry shorter: n[p][j] is N_{j,p}.
  Scalar n0[4], n1[3], n2[2];
  for (std::size_t j = 0; j < 4; ++j) n0[j] = (x >= k[j] && x < k[j + 1]) ? Scalar(1) : Scalar(0);
  for (std::size_t j = 0; j < 3; ++j)
    n1[j] = ratio(x - k[j], k[j + 1] - k[j]) * n0[j] +
            ratio(k[j + 2] - x, k[j + 2] - k[j + 1]) * n0[j + 1];
  for (std::size_t j = 0; j < 2; ++j)
    n2[j] = ratio(x - k[j], k[j + 2] - k[j]) * n1[j] +
            ratio(k[j + 3] - x, k[j + 3] - k[j + 1]) * n1[j + 1];
  const Scalar value = ratio(x - k[0], k[3] - k[0]) * n2[0] + ratio(k[4] - x, k[4] - k[1]) * n2[1];
  if (d1) *d1 = Scalar(3) * (ratio(n2[0], k[3] - k[0]) - ratio(n2[1], k[4] - k[1]));
  if (d2) {
    // Derivatives of the two quadratics, then of the cubic.
    const Scalar q0 = Scalar(2) * (ratio(n1[0], k[2] - k[0]) - ratio(n1[1], k[3] - k[1]));
    const Scalar q1 = Scalar(2) * (ratio(n1[1], k[3] - k[1]) - ratio(n1[2], k[4] - k[2]));
    *d2 = Scalar(3) * (ratio(q0, k[3] - k[0]) - ratio(q1, k[4] - k[1]));
  }
  return value;
}

}  // namespace mspline::spline
