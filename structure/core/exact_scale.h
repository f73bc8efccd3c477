#pragma once
// Scaling by a power of two: exact in floating point (no rounding, barring overflow and
// underflow), so a length, area or angle computed on scaled values and scaled back equals the
// plain computation bit for bit wherever that one neither overflows nor underflows, and stays
// right where it does (squared lengths of a mesh at 1e300 or 1e-300).
#include <algorithm>
#include <cmath>

namespace mspline {

/// The power of two s with s * magnitude in [1, 2); 1 for 0, a non-finite or subnormal
/// magnitude (which no scale mends). Multiplying by it and by 1/s is exact.
inline double exactUnitScale(double magnitude) {
  if (!std::isnormal(magnitude)) return 1.0;
  return std::ldexp(1.0, -std::ilogb(magnitude));
}

/// The Euclidean length of (x, y, z) without overflow or underflow of the squares; equal to
/// the plain sqrt(x*x + y*y + z*z) wherever that one is finite and not underflowed.
inline double exactScaledNorm(double x, double y, double z) {
  const double s = exactUnitScale(std::max({std::abs(x), std::abs(y), std::abs(z)}));
  x *= s, y *= s, z *= s;
  return std::sqrt(x * x + y * y + z * z) / s;
}

}  // namespace mspline
