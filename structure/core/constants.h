#pragma once
// Numbers every layer uses, defined once.

namespace mspline {

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace mspline
