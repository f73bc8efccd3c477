#pragma once
// The uniform cubic B-spline basis on one knot interval [0,1], and its tensor product: the 16
// weights of a bicubic patch over its 4 x 4 control grid. Reference for the Catmull-Clark limit of
// regular faces (and any other uniform bicubic B-spline).
#include <cstddef>

namespace mspline::spline {

/// The four uniform cubic B-spline basis functions that are non-zero on [0,1] (knots at the
/// integers), at t: values[k] weighs control point k of the four consecutive ones, the segment
/// running between points 1 and 2. The values are non-negative and sum to 1 on [0,1]. Optional
/// first (d1) and second (d2) derivatives with respect to t, 4 entries each.
template <class Scalar>
void uniformCubicBasis(Scalar t, Scalar values[4], Scalar* d1 = nullptr, Scalar* d2 = nullptr) {
  const Scalar s = Scalar(1) - t;
  const Scalar t2 = t * t, t3 = t2 * t;
  values[0] = s * s * s / Scalar(6);
  values[1] = (Scalar(3) * t3 - Scalar(6) * t2 + Scalar(4)) / Scalar(6);
  values[2] = (-Scalar(3) * t3 + Scalar(3) * t2 + Scalar(3) * t + Scalar(1)) / Scalar(6);
  values[3] = t3 / Scalar(6);
  if (d1) {
    d1[0] = -s * s / Scalar(2);
    d1[1] = Scalar(3) * t2 / Scalar(2) - Scalar(2) * t;
    d1[2] = (-Scalar(3) * t2 + Scalar(2) * t + Scalar(1)) / Scalar(2);
    d1[3] = t2 / Scalar(2);
  }
  if (d2) {
    d2[0] = s;
    d2[1] = Scalar(3) * t - Scalar(2);
    d2[2] = Scalar(1) - Scalar(3) * t;
    d2[3] = t;
  }
}

/// Weights of the bicubic tensor-product patch over a 4 x 4 control grid at (s, t) in [0,1]^2:
/// weight 4 j + i belongs to grid point (i, j), i counting along s and j along t, so the patch
/// spans the cell of points 5, 6, 10, 9 (OpenSubdiv's regular patch ordering). Every non-null
/// output has 16 entries: first derivatives ds, dt and second derivatives dss, dst, dtt.
template <class Scalar>
void uniformBicubicBasis(Scalar s, Scalar t, Scalar weights[16], Scalar* ds = nullptr,
                         Scalar* dt = nullptr, Scalar* dss = nullptr, Scalar* dst = nullptr,
                         Scalar* dtt = nullptr) {
  Scalar bs[4], bt[4], bs1[4], bt1[4], bs2[4], bt2[4];
  uniformCubicBasis(s, bs, bs1, bs2);
  uniformCubicBasis(t, bt, bt1, bt2);
  for (std::size_t j = 0; j < 4; ++j)
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t k = 4 * j + i;
      weights[k] = bs[i] * bt[j];
      if (ds) ds[k] = bs1[i] * bt[j];
      if (dt) dt[k] = bs[i] * bt1[j];
      if (dss) dss[k] = bs2[i] * bt[j];
      if (dst) dst[k] = bs1[i] * bt1[j];
      if (dtt) dtt[k] = bs[i] * bt2[j];
    }
}

}  // namespace mspline::spline
