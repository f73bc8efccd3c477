#include "mspline/structure/layout/planar_delaunay.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

namespace {

__extension__ typedef __int128 Int128;

// Points snap into [0, kGrid]^2 and the enclosing triangle's corners lie in [-3, 6] kGrid, so
// coordinate differences stay below 9 * 2^27 < 2^30.2; squared lengths and cross products stay
// below 2^62, and the in-circle determinant (three of their products) below 2^126.
constexpr std::int64_t kGrid = std::int64_t(1) << 27;

using GridPoint = std::array<std::int64_t, 2>;

// > 0 when a, b, c turn counter-clockwise.
Int128 orient(const GridPoint& a, const GridPoint& b, const GridPoint& c) {
  return Int128(b[0] - a[0]) * (c[1] - a[1]) - Int128(b[1] - a[1]) * (c[0] - a[0]);
}

// > 0 when d lies strictly inside the circle through the counter-clockwise a, b, c.
Int128 inCircle(const GridPoint& a, const GridPoint& b, const GridPoint& c, const GridPoint& d) {
  const Int128 ax = a[0] - d[0], ay = a[1] - d[1], bx = b[0] - d[0], by = b[1] - d[1];
  const Int128 cx = c[0] - d[0], cy = c[1] - d[1];
  return (ax * ax + ay * ay) * (bx * cy - cx * by) + (bx * bx + by * by) * (cx * ay - ax * cy) +
         (cx * cx + cy * cy) * (ax * by - bx * ay);
}

}  // namespace

PlanarDelaunay::PlanarDelaunay(const std::vector<Eigen::Vector2d>& points) {
  if (points.empty()) throw InputError("Delaunay triangulation: no points");
  low_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d high = -low_;
  for (const Eigen::Vector2d& p : points) {
    if (!p.allFinite()) throw InputError("Delaunay triangulation: a coordinate is not finite");
    low_ = low_.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const double extent = (high - low_).maxCoeff();
  scale_ = extent > 0.0 ? double(kGrid) / extent : 1.0;
  const int n = static_cast<int>(points.size());
  for (const Eigen::Vector2d& p : points)
    grid_.push_back(
        {std::llround((p.x() - low_.x()) * scale_), std::llround((p.y() - low_.y()) * scale_)});
  grid_.push_back({-3 * kGrid, -3 * kGrid});
  grid_.push_back({6 * kGrid, -3 * kGrid});
  grid_.push_back({-3 * kGrid, 6 * kGrid});
  triangles_.push_back({{n, n + 1, n + 2}, {-1, -1, -1}});
  removed_.push_back(0);
  representative_.resize(n);
  std::iota(representative_.begin(), representative_.end(), 0);
  rimStart_.assign(n + 3, -1);

  // Rows snaking across the box: each point is located by a short walk from the previous one.
  const std::int64_t rowHeight = kGrid / std::max(1, int(std::sqrt(n / 4.0))) + 1;
  auto key = [&](int p) {
    const std::int64_t row = grid_[p][1] / rowHeight;
    return std::make_tuple(row, row % 2 ? -grid_[p][0] : grid_[p][0], grid_[p][1], p);
  };
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  int hint = 0;
  for (int p : order) insert(p, hint);
  std::sort(duplicates_.begin(), duplicates_.end());

  offsets_.assign(n + 4, 0);
  for (std::size_t t = 0; t < triangles_.size(); ++t)
    if (!removed_[t])
      for (int v : triangles_[t].v) ++offsets_[v + 1];
  std::partial_sum(offsets_.begin(), offsets_.end(), offsets_.begin());
  neighbours_.resize(offsets_.back());
  std::vector<int> cursor(offsets_.begin(), offsets_.end() - 1);
  for (std::size_t t = 0; t < triangles_.size(); ++t)
    if (!removed_[t])
      for (int k = 0; k < 3; ++k)
        neighbours_[cursor[triangles_[t].v[k]]++] = triangles_[t].v[(k + 1) % 3];
}

int PlanarDelaunay::locate(const GridPoint& p, int t) const {
  // The visibility walk: it cannot cycle in a Delaunay triangulation (Edelsbrunner 1990).
  for (;;) {
    const Triangle& triangle = triangles_[t];
    int next = -1;
    for (int k = 0; k < 3 && next < 0; ++k)
      if (orient(grid_[triangle.v[(k + 1) % 3]], grid_[triangle.v[(k + 2) % 3]], p) < 0) {
        next = triangle.n[k];
        MSPLINE_ASSERT(next >= 0, "point outside the enclosing triangle");
      }
    if (next < 0) return t;
    t = next;
  }
}

void PlanarDelaunay::insert(int point, int& hint) {
  const GridPoint& p = grid_[point];
  const int start = locate(p, hint);
  for (int v : triangles_[start].v)
    if (grid_[v] == p) {
      duplicates_.push_back({point, v});
      representative_[point] = v;
      return;
    }
  // Bowyer-Watson: the triangles whose circumcircle holds p strictly form a star around p (with
  // exact predicates), which is re-triangulated as a fan from p over its rim.
  std::vector<int> cavity{start};
  removed_[start] = 1;
  struct RimEdge {
    int a, b, outside;
  };
  std::vector<RimEdge> rim;
  for (std::size_t i = 0; i < cavity.size(); ++i) {
    const Triangle t = triangles_[cavity[i]];
    for (int k = 0; k < 3; ++k) {
      const int across = t.n[k];
      if (across >= 0 && removed_[across]) continue;
      if (across >= 0) {
        const auto& v = triangles_[across].v;
        if (inCircle(grid_[v[0]], grid_[v[1]], grid_[v[2]], p) > 0) {
          removed_[across] = 1;
          cavity.push_back(across);
          continue;
        }
      }
      rim.push_back({t.v[(k + 1) % 3], t.v[(k + 2) % 3], across});
    }
  }
  free_.insert(free_.end(), cavity.begin(), cavity.end());
  for (const RimEdge& edge : rim) {
    int t = static_cast<int>(triangles_.size());
    if (free_.empty()) {
      triangles_.emplace_back();
      removed_.push_back(0);
    } else {
      t = free_.back();
      free_.pop_back();
      removed_[t] = 0;
    }
    triangles_[t] = {{edge.a, edge.b, point}, {-1, -1, edge.outside}};
    if (edge.outside >= 0) {
      Triangle& outside = triangles_[edge.outside];
      for (int j = 0; j < 3; ++j)
        if (outside.v[j] != edge.a && outside.v[j] != edge.b) outside.n[j] = t;
    }
    rimStart_[edge.a] = t;
    hint = t;
  }
  // Fan triangle (a, b, p) meets the one starting at b across the edge b p.
  for (const RimEdge& edge : rim) {
    const int t = rimStart_[edge.a], next = rimStart_[edge.b];
    triangles_[t].n[0] = next;
    triangles_[next].n[1] = t;
  }
  for (const RimEdge& edge : rim) rimStart_[edge.a] = -1;
}

std::vector<std::array<int, 3>> PlanarDelaunay::triangles() const {
  const int n = static_cast<int>(representative_.size());
  std::vector<std::array<int, 3>> result;
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& v = triangles_[t].v;
    if (!removed_[t] && v[0] < n && v[1] < n && v[2] < n) result.push_back(v);
  }
  return result;
}

int PlanarDelaunay::nearest(const Eigen::Vector2d& q, int start) const {
  const int n = static_cast<int>(representative_.size());
  MSPLINE_ASSERT(start >= 0 && start < n, "start point out of range");
  const Eigen::Vector2d scaled = (q - low_) * scale_;
  MSPLINE_ASSERT(scaled.minCoeff() >= -double(kGrid) && scaled.maxCoeff() <= 2.0 * double(kGrid),
                 "query point outside the triangulation's range");
  const GridPoint g = {std::llround(scaled.x()), std::llround(scaled.y())};
  auto squaredDistance = [&](int v) {
    const Int128 dx = grid_[v][0] - g[0], dy = grid_[v][1] - g[1];
    return dx * dx + dy * dy;
  };
  int v = representative_[start];
  Int128 distance = squaredDistance(v);
  for (int next = v;; v = next) {
    for (int i = offsets_[v]; i < offsets_[v + 1]; ++i) {
      const Int128 d = squaredDistance(neighbours_[i]);
      if (d < distance) {
        distance = d;
        next = neighbours_[i];
      }
    }
    if (next == v) break;
  }
  // The enclosing triangle's corners are farther from the range than some point always is.
  MSPLINE_ASSERT(v < n, "nearest point is a corner of the enclosing triangle");
  return v;
}

}  // namespace mspline::structure
