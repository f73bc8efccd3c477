#pragma once
// A T-mesh on a flat torus: the grid that the deck group maps to itself. A flat torus is the plane
// modulo the lattice of its two periods; one linear map takes a reduced basis of the lattice to
// (N, 0) and (0, M), after which the unit grid of N x M cells is seamless: every transition of the
// affine atlas is a translation by whole cells, no T-junctions and no extraordinary points, so
// the T-spline is a periodic uniform bicubic B-spline. The price is that the grid follows the
// lattice, not the metric: the map is a similarity only when the reduced periods are orthogonal
// with a rational length ratio, and `anisotropy` reports how far from one it is (it is at most
// 2 / sqrt(3) times the ratio of rounding, since a reduced basis is at least 60 degrees apart).
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tmesh.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::spline {

struct TorusTMeshOptions {
  /// About this many grid cells (and as many control points); at least 4 along each period.
  int targetCells = 4000;
};

struct TorusTMesh {
  /// The periodic N x M grid of unit cells (gridTMesh with both directions periodic).
  TMesh mesh;
  int cellsAlongFirst = 0;
  int cellsAlongSecond = 0;
  /// The reduced periods (layout frame) and the linear map from the layout frame to grid units
  /// that takes them to (N, 0) and (0, M).
  Eigen::Vector2d firstPeriod = Eigen::Vector2d::Zero();
  Eigen::Vector2d secondPeriod = Eigen::Vector2d::Zero();
  Eigen::Matrix2d layoutToGrid = Eigen::Matrix2d::Identity();
  /// Ratio of the map's singular values: 1 for a similarity (square cells on the surface).
  double anisotropy = 1.0;
  /// Per surface face corner (3 f + k, the layout's corner order), its point on the T-mesh.
  std::vector<FacePoint> cornerPoints;
};

/// Grid point (in grid units, any lift) as a point of the periodic grid.
FacePoint gridPoint(const TorusTMesh& torus, const Eigen::Vector2d& grid);

/// Builds the grid for a layout with periods (layoutFlatMetric on a closed genus-1 surface without
/// cones). Throws InputError when the layout has no periods or they are degenerate.
TorusTMesh torusTMesh(const structure::FlatLayout& layout, const TorusTMeshOptions& options = {});

}  // namespace mspline::spline
