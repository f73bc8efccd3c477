#pragma once
// Distances from points (a scan's vertices) to a surface's triangles, as colors: blue (0) through
// white (half the scale) to red (the scale and above). Used by `mspline export --error-map` and
// the viewer.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/closest_point.h"

namespace mspline::io {

struct ErrorMap {
  /// Per point: its distance to the surface.
  std::vector<double> distances;
  /// The color scale: the distances' 99th percentile (robust to a few stray scan points), or the
  /// largest distance when that is 0, or 1 when every distance is 0.
  double scale = 1.0;
  /// Root mean square and largest distance.
  double rms = 0.0, max = 0.0;
  /// Per point: errorColor(distance / scale).
  std::vector<std::array<std::uint8_t, 3>> colors;
};

/// Colors t in [0, 1] (clamped) from blue through white to red.
std::array<std::uint8_t, 3> errorColor(double t);

/// The error map of `points` (rows) against `surface`; `points` must not be empty.
ErrorMap errorMap(const Eigen::MatrixX3d& points, const structure::TriangleMeshDistance& surface);

}  // namespace mspline::io
