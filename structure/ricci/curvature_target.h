#pragma once
// Target curvatures for a flat metric with cone singularities, and the Gauss-Bonnet check.
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

/// A prescribed curvature at one vertex: the Gauss curvature 2 pi - (cone angle) at an interior
/// vertex, the geodesic curvature pi - (boundary angle) at a boundary vertex.
struct Cone {
  int vertex = -1;
  double curvature = 0.0;
};

enum class BoundaryCondition {
  /// u = 0 on the boundary (Dirichlet): boundary lengths are kept, boundary vertices are not
  /// unknowns, and their geodesic curvature comes out of the solve.
  FixedScale,
  /// Boundary vertices are unknowns with a prescribed geodesic curvature: the cone's value where
  /// one is given, 0 (a straight boundary) elsewhere.
  PrescribedGeodesicCurvature,
};

/// What the Ricci solver is asked to reach; vectors are indexed by vertex idx().
struct CurvatureTarget {
  /// Target Gauss curvature (interior) or geodesic curvature (boundary); unused where fixed.
  Eigen::VectorXd curvature;
  /// 1 where u stays 0 and the vertex is not an unknown.
  std::vector<char> fixed;
};

/// Flat everywhere except at `cones` (interior or, with PrescribedGeodesicCurvature, boundary
/// vertices). Throws InputError for a vertex out of range, listed twice, or on the boundary when
/// the boundary is FixedScale. Does not check Gauss-Bonnet (see checkGaussBonnet).
CurvatureTarget flatTarget(const TriMesh& mesh, const std::vector<Cone>& cones,
                           BoundaryCondition boundary = BoundaryCondition::FixedScale);

/// When no vertex is fixed, the targets must sum to 2 pi chi (Gauss-Bonnet; on bounded surfaces the
/// sum includes the geodesic curvatures); throws InputError naming both numbers when they differ by
/// more than `relativeTolerance` * max(2 pi, sum of |targets|). With a fixed vertex the fixed
/// vertices absorb any excess, so there is nothing to check.
void checkGaussBonnet(const TriMesh& mesh, const CurvatureTarget& target,
                      double relativeTolerance = 1e-9);

}  // namespace mspline::structure
