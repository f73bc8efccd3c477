#include "mspline/io/error_map.h"

#include <algorithm>
#include <cmath>

#include "mspline/structure/core/errors.h"

namespace mspline::io {

std::array<std::uint8_t, 3> errorColor(double t) {
  t = std::clamp(t, 0.0, 1.0);
  const auto c = [](double x) { return std::uint8_t(std::lround(255.0 * x)); };
  if (t < 0.5) return {c(2.0 * t), c(2.0 * t), 255};
  return {255, c(2.0 - 2.0 * t), c(2.0 - 2.0 * t)};
}

ErrorMap errorMap(const Eigen::MatrixX3d& points, const structure::TriangleMeshDistance& surface) {
  MSPLINE_ASSERT(points.rows() > 0, "an error map needs points");
  ErrorMap out;
  double squares = 0.0;
  for (const structure::ClosestPoint& hit : surface.queryAll(points)) {
    out.distances.push_back(hit.distance);
    squares += hit.distance * hit.distance;
    out.max = std::max(out.max, hit.distance);
  }
  out.rms = std::sqrt(squares / double(out.distances.size()));
  std::vector<double> sorted = out.distances;
  const std::size_t rank = std::min(sorted.size() - 1, std::size_t(0.99 * double(sorted.size())));
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(rank), sorted.end());
  out.scale = sorted[rank] > 0.0 ? sorted[rank] : (out.max > 0.0 ? out.max : 1.0);
  for (double d : out.distances) out.colors.push_back(errorColor(d / out.scale));
  return out;
}

}  // namespace mspline::io
