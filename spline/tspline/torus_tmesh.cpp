#include "mspline/spline/tspline/torus_tmesh.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <Eigen/LU>
#include <Eigen/SVD>

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;
using structure::SolverError;

namespace {

// Lagrange-Gauss reduction: the shortest lattice vector, then the shortest one independent of it.
void reduceBasis(Eigen::Vector2d& a, Eigen::Vector2d& b) {
  if (a.squaredNorm() > b.squaredNorm()) std::swap(a, b);
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double m = std::round(a.dot(b) / a.squaredNorm());
    b -= m * a;
    if (b.squaredNorm() >= a.squaredNorm()) return;
    std::swap(a, b);
  }
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

}  // namespace

FacePoint gridPoint(const TorusTMesh& torus, const Eigen::Vector2d& grid) {
  const int n = torus.cellsAlongFirst, m = torus.cellsAlongSecond;
  double x = std::fmod(grid.x(), double(n)), y = std::fmod(grid.y(), double(m));
  if (x < 0.0) x += n;
  if (y < 0.0) y += m;
  const int i = std::min(n - 1, static_cast<int>(std::floor(x)));
  const int j = std::min(m - 1, static_cast<int>(std::floor(y)));
  return {j * n + i, Eigen::Vector2d(x - i, y - j)};
}

TorusTMesh torusTMesh(const structure::FlatLayout& layout, const TorusTMeshOptions& options) {
  if (!layout.hasPeriods)
    throw InputError("torus T-mesh: the layout has no periods (not a flat torus without cones)");
  TorusTMesh torus;
  Eigen::Vector2d a = layout.periods[0], b = layout.periods[1];
  const double area = std::abs(cross(a, b));
  // The sine of the angle between the periods, free of the layout's unit.
  if (!(area > 1e-12 * a.norm() * b.norm()) || !std::isfinite(area))
    throw SolverError("torus T-mesh: the periods are degenerate");
  reduceBasis(a, b);
  if (cross(a, b) < 0.0) b = -b;  // keep the orientation, so the grid's faces face outward
  const double cell = std::sqrt(area / std::max(16, options.targetCells));
  const int n = std::max(4, static_cast<int>(std::lround(a.norm() / cell)));
  const int m = std::max(4, static_cast<int>(std::lround(area / a.norm() / cell)));
  Eigen::Matrix2d periods;
  periods << a, b;
  torus.firstPeriod = a;
  torus.secondPeriod = b;
  torus.cellsAlongFirst = n;
  torus.cellsAlongSecond = m;
  torus.layoutToGrid = Eigen::Vector2d(n, m).asDiagonal() * periods.inverse();
  const Eigen::Vector2d singular =
      Eigen::JacobiSVD<Eigen::Matrix2d>(torus.layoutToGrid).singularValues();
  torus.anisotropy = singular[0] / singular[1];
  std::vector<double> xs(static_cast<std::size_t>(n) + 1), ys(static_cast<std::size_t>(m) + 1);
  for (int i = 0; i <= n; ++i) xs[i] = i;
  for (int j = 0; j <= m; ++j) ys[j] = j;
  torus.mesh = gridTMesh(xs, ys, true, true);
  torus.cornerPoints.reserve(static_cast<std::size_t>(layout.cornerUV.rows()));
  for (Eigen::Index c = 0; c < layout.cornerUV.rows(); ++c)
    torus.cornerPoints.push_back(
        gridPoint(torus, torus.layoutToGrid * layout.cornerUV.row(c).transpose()));
  return torus;
}

}  // namespace mspline::spline
