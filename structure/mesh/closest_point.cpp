#include "mspline/structure/mesh/closest_point.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>

#include <tbb/parallel_for.h>
#include <nanoflann.hpp>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/exact_scale.h"

namespace mspline::structure {

namespace {

using Eigen::Vector3d;

// nanoflann's view of the centroid matrix.
struct CentroidCloud {
  const Eigen::MatrixX3d* points = nullptr;
  std::size_t kdtree_get_point_count() const { return std::size_t(points->rows()); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return (*points)(Eigen::Index(i), Eigen::Index(dim));
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using CentroidTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CentroidCloud>,
                                        CentroidCloud, 3, std::uint32_t>;

}  // namespace

double segmentParameter(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  // A ratio of products of two lengths, on vectors scaled by a power of two (exact).
  const double scale =
      exactUnitScale(std::max((b - a).cwiseAbs().maxCoeff(), (p - a).cwiseAbs().maxCoeff()));
  const Vector3d d = (b - a) * scale;
  const double length2 = d.squaredNorm();
  return length2 > 0.0 ? std::clamp(((p - a) * scale).dot(d) / length2, 0.0, 1.0) : 0.0;
}

ClosestPoint closestPointOnTriangle(const Vector3d& p, const Vector3d& a, const Vector3d& b,
                                    const Vector3d& c) {
  ClosestPoint out;
  const auto result = [&](double u, double v, double w) {
    out.barycentric = Vector3d(u, v, w);
    out.closest = u * a + v * b + w * c;
    const Vector3d offset = p - out.closest;
    out.distance = exactScaledNorm(offset.x(), offset.y(), offset.z());
    return out;
  };
  // Ericson's Voronoi region tests: the corners, then the edges, then the inside. They multiply
  // four lengths: computed on differences scaled by a power of two (exact, so the same answers),
  // they neither overflow nor underflow at any unit.
  const double scale =
      exactUnitScale(std::max({(b - a).cwiseAbs().maxCoeff(), (c - a).cwiseAbs().maxCoeff(),
                               (p - a).cwiseAbs().maxCoeff()}));
  const Vector3d ab = (b - a) * scale, ac = (c - a) * scale, ap = (p - a) * scale;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return result(1.0, 0.0, 0.0);
  const Vector3d bp = (p - b) * scale;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return result(0.0, 1.0, 0.0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return result(1.0 - v, v, 0.0);
  }
  const Vector3d cp = (p - c) * scale;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return result(0.0, 0.0, 1.0);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return result(1.0 - w, 0.0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return result(0.0, 1.0 - w, w);
  }
  const double sum = va + vb + vc;
  if (sum > 0.0) return result(va / sum, vb / sum, vc / sum);
  // A degenerate (collinear) triangle has no inside: its closest point is on one of its sides.
  ClosestPoint best;
  best.distance = std::numeric_limits<double>::infinity();
  const Vector3d* corner[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    const double t = segmentParameter(p, *corner[k], *corner[(k + 1) % 3]);
    Vector3d w = Vector3d::Zero();
    w[k] = 1.0 - t;
    w[(k + 1) % 3] = t;
    const ClosestPoint candidate = result(w[0], w[1], w[2]);
    if (candidate.distance < best.distance) best = candidate;
  }
  return best;
}

// Triangles (all of them, or those whose reach lies in (reach / 2, reach]; the last level's in
// [0, reach]), their centroids (times centroidScale_) and a k-d tree on them.
struct TriangleMeshDistance::Level {
  std::vector<int> faces;
  Eigen::MatrixX3d centroids;
  double reach = 0.0;
  CentroidCloud cloud;
  std::unique_ptr<CentroidTree> tree;
};

namespace {

// Levels of reach at most: the last one holds every triangle whose reach is below 2^-15 of the
// largest (a search in it reaches that much further than needed, about the size of its own
// triangles' neighbours).
constexpr int kReachLevels = 16;

}  // namespace

TriangleMeshDistance::TriangleMeshDistance(Eigen::MatrixX3d positions,
                                           std::vector<std::array<int, 3>> triangles)
    : positions_(std::move(positions)), triangles_(std::move(triangles)) {
  if (triangles_.empty()) throw InputError("closest points: the mesh has no triangles");
  if (!positions_.allFinite()) throw InputError("closest points: a position is not finite");
  Eigen::MatrixX3d centroids(Eigen::Index(triangles_.size()), 3);
  std::vector<double> reach(triangles_.size(), 0.0);
  double largest = 0.0;
  for (std::size_t f = 0; f < triangles_.size(); ++f) {
    Vector3d centroid = Vector3d::Zero();
    for (int v : triangles_[f]) {
      if (v < 0 || v >= positions_.rows())
        throw InputError("closest points: triangle " + std::to_string(f) + " refers to vertex " +
                         std::to_string(v) + " of " + std::to_string(positions_.rows()));
      centroid += positions_.row(v).transpose() / 3.0;
    }
    centroids.row(Eigen::Index(f)) = centroid.transpose();
    for (int v : triangles_[f]) {
      const Vector3d offset = positions_.row(v).transpose() - centroid;
      reach[f] = std::max(reach[f], exactScaledNorm(offset.x(), offset.y(), offset.z()));
    }
    largest = std::max(largest, reach[f]);
  }
  centroidScale_ = exactUnitScale(centroids.cwiseAbs().maxCoeff());
  // A few long triangles must not widen every search: triangles are grouped by their reach
  // (halving from level to level), each group searched with its own.
  std::vector<std::vector<int>> members(kReachLevels);
  for (std::size_t f = 0; f < triangles_.size(); ++f) {
    int level = kReachLevels - 1;
    for (double bound = largest; level > 0 && reach[f] <= 0.5 * bound;) bound *= 0.5, --level;
    members[std::size_t(kReachLevels - 1 - level)].push_back(int(f));
  }
  const auto makeLevel = [&](std::vector<int> faces) {
    auto level = std::make_unique<Level>();
    level->faces = std::move(faces);
    level->centroids.resize(Eigen::Index(level->faces.size()), 3);
    for (std::size_t i = 0; i < level->faces.size(); ++i) {
      const int f = level->faces[i];
      level->centroids.row(Eigen::Index(i)) = centroids.row(f) * centroidScale_;
      level->reach = std::max(level->reach, reach[std::size_t(f)]);
    }
    level->cloud.points = &level->centroids;
    level->tree = std::make_unique<CentroidTree>(3, level->cloud,
                                                 nanoflann::KDTreeSingleIndexAdaptorParams(10));
    level->tree->buildIndex();
    return level;
  };
  for (auto& faces : members)
    if (!faces.empty()) levels_.push_back(makeLevel(std::move(faces)));
  std::vector<int> all(triangles_.size());
  for (std::size_t f = 0; f < all.size(); ++f) all[f] = int(f);
  all_ = makeLevel(std::move(all));
}

TriangleMeshDistance::~TriangleMeshDistance() = default;
TriangleMeshDistance::TriangleMeshDistance(TriangleMeshDistance&&) noexcept = default;
TriangleMeshDistance& TriangleMeshDistance::operator=(TriangleMeshDistance&&) noexcept = default;

ClosestPoint TriangleMeshDistance::query(const Vector3d& p) const {
  const auto exact = [&](int f) {
    const auto& t = triangles_[std::size_t(f)];
    ClosestPoint c =
        closestPointOnTriangle(p, positions_.row(t[0]).transpose(),
                               positions_.row(t[1]).transpose(), positions_.row(t[2]).transpose());
    c.face = f;
    return c;
  };
  const Vector3d scaled = p * centroidScale_;
  // An upper bound: the nearest centroid's triangle.
  std::uint32_t nearest = 0;
  double nearestDistance2 = 0.0;
  all_->tree->knnSearch(scaled.data(), 1, &nearest, &nearestDistance2);
  ClosestPoint best = exact(int(nearest));
  std::vector<std::pair<std::uint32_t, double>> candidates;
  for (const auto& level : levels_) {
    // Rounding in the tree's squared distances must not drop a candidate at the radius.
    const double radius =
        ((best.distance + level->reach) * (1.0 + 1e-12) + 1e-300) * centroidScale_;
    candidates.clear();
    level->tree->radiusSearch(scaled.data(), radius * radius, candidates,
                              nanoflann::SearchParams(0, 0.0f, false));
    for (const auto& candidate : candidates) {
      const int f = level->faces[candidate.first];
      if (f == best.face) continue;
      // Centroid distance minus reach bounds the triangle's distance from below.
      if (std::sqrt(candidate.second) / centroidScale_ - level->reach > best.distance) continue;
      const ClosestPoint c = exact(f);
      if (c.distance < best.distance) best = c;
    }
  }
  return best;
}

std::vector<ClosestPoint> TriangleMeshDistance::queryAll(const Eigen::MatrixX3d& points) const {
  std::vector<ClosestPoint> out(std::size_t(points.rows()));
  tbb::parallel_for(Eigen::Index(0), points.rows(), [&](Eigen::Index i) {
    out[std::size_t(i)] = query(points.row(i).transpose());
  });
  return out;
}

std::vector<ClosestPoint> TriangleMeshDistance::queryAll(
    const std::vector<Eigen::Vector3d>& points) const {
  std::vector<ClosestPoint> out(points.size());
  tbb::parallel_for(std::size_t(0), points.size(),
                    [&](std::size_t i) { out[i] = query(points[i]); });
  return out;
}

}  // namespace mspline::structure
