#pragma once
// Exact closest points on a triangle mesh (a soup is enough: no connectivity is used).
//
// K-d trees (nanoflann) hold the triangles' centroids, one tree per level of reach (a triangle's
// largest centroid-to-corner distance; levels halve, so that a few long triangles do not widen
// the search among the many small ones), and one tree holds them all. A query takes the nearest
// centroid's triangle: its exact distance d bounds the answer from above. Every triangle
// within d of the point has its centroid within d + R of it (R: the largest reach of its level),
// so one radius search per level with d + R finds all candidates, each checked exactly by the
// closest point on a triangle (Ericson, Real-Time Collision Detection, 5.1.5). The result equals
// brute force to rounding, whatever the triangles' sizes; only the speed depends on them.
#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace mspline::structure {

struct ClosestPoint {
  /// Euclidean distance from the query point to the mesh.
  double distance = 0.0;
  /// The triangle the closest point lies on (the first one found among equally near ones).
  int face = -1;
  /// The closest point's barycentric coordinates in that triangle (corners in triangle order).
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();
  /// The closest point itself.
  Eigen::Vector3d closest = Eigen::Vector3d::Zero();
};

/// The closest point to p on segment [a, b], as the parameter t in [0, 1] of a + t (b - a) (0 when
/// a = b).
double segmentParameter(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b);

/// The closest point to p on triangle (a, b, c), degenerate triangles included.
ClosestPoint closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// Distance queries against a fixed triangle mesh. Immutable after construction; queries from
/// several threads at once are safe.
class TriangleMeshDistance {
 public:
  /// Throws InputError for no triangles, a corner index out of range or a non-finite position.
  TriangleMeshDistance(Eigen::MatrixX3d positions, std::vector<std::array<int, 3>> triangles);
  ~TriangleMeshDistance();
  TriangleMeshDistance(TriangleMeshDistance&&) noexcept;
  TriangleMeshDistance& operator=(TriangleMeshDistance&&) noexcept;

  /// The exact closest point of the mesh to p.
  ClosestPoint query(const Eigen::Vector3d& p) const;
  /// query() for every point (rows of a matrix, or a list), in parallel (TBB), in their order.
  std::vector<ClosestPoint> queryAll(const Eigen::MatrixX3d& points) const;
  std::vector<ClosestPoint> queryAll(const std::vector<Eigen::Vector3d>& points) const;

  const Eigen::MatrixX3d& positions() const { return positions_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

 private:
  struct Level;
  Eigen::MatrixX3d positions_;
  std::vector<std::array<int, 3>> triangles_;
  // The trees hold the centroids times centroidScale_, a power of two (exact) that keeps their
  // squared distances finite and normal at any unit.
  double centroidScale_ = 1.0;
  std::vector<std::unique_ptr<Level>> levels_;
  std::unique_ptr<Level> all_;
};

}  // namespace mspline::structure
