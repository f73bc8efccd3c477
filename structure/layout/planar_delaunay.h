#pragma once
// The Delaunay triangulation of points in the plane (Bowyer-Watson) with exact predicates, and
// nearest-point queries by greedy descent along its edges.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace mspline::structure {

class PlanarDelaunay {
 public:
  /// Triangulates `points` (at least one). Coordinates are snapped to a grid of 2^27 steps across
  /// the points' bounding box, so that orientation and in-circle tests are exact in 128-bit
  /// integers: the result is the Delaunay triangulation of the snapped points (one of them where
  /// four points are cocircular). A point that snaps onto an earlier one is left out (see
  /// duplicates()). Throws InputError for no points or a coordinate that is not finite.
  explicit PlanarDelaunay(const std::vector<Eigen::Vector2d>& points);

  /// The triangles as counter-clockwise point indices, each with no point strictly inside its
  /// circumcircle. Along the convex hull a sliver may be missing: the triangulation is built inside
  /// an enclosing triangle whose corners, though far, take part in the empty-circle tests.
  std::vector<std::array<int, 3>> triangles() const;
  /// (left-out point, the earlier point it snapped onto), in input order.
  const std::vector<std::array<int, 2>>& duplicates() const { return duplicates_; }

  /// A point nearest to q among the snapped points (exactly; ties broken arbitrarily), found by
  /// walking from `start` to ever nearer Delaunay neighbours: a point none of whose neighbours
  /// is nearer is nearest, as its Voronoi cell is cut out by the bisectors with its neighbours.
  /// q must lie in the points' bounding box enlarged by its size on every side.
  int nearest(const Eigen::Vector2d& q, int start = 0) const;

 private:
  using GridPoint = std::array<std::int64_t, 2>;
  struct Triangle {
    std::array<int, 3> v;
    /// n[k]: the triangle across the edge opposite v[k], -1 outside the enclosing triangle.
    std::array<int, 3> n;
  };

  GridPoint snap(const Eigen::Vector2d& p) const;
  int locate(const GridPoint& p, int triangle) const;
  void insert(int point, int& hint);

  Eigen::Vector2d low_;
  double scale_ = 1.0;
  /// The input points, then the three corners of the enclosing triangle.
  std::vector<GridPoint> grid_;
  std::vector<Triangle> triangles_;
  /// Triangles removed by insertions, whose slots are reused.
  std::vector<int> free_;
  std::vector<char> removed_;
  std::vector<std::array<int, 2>> duplicates_;
  /// Per point: itself, or the earlier point it snapped onto.
  std::vector<int> representative_;
  /// Per point during an insertion: the new fan triangle whose rim edge starts there, else -1.
  std::vector<int> rimStart_;
  /// Delaunay neighbours of point p: neighbours_[offsets_[p] .. offsets_[p + 1]).
  std::vector<int> offsets_;
  std::vector<int> neighbours_;
};

}  // namespace mspline::structure
