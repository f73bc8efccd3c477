#pragma once
// A spline model: everything a spline surface on a mesh needs, as saved in a .msp file
// (io/spline_model_file.h): the surface it lives on, the domain triangulation with its flat
// metric (which determines the charts, spline_domain.h), the knots, the degree and the control
// points.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "spline/spline_domain.h"

namespace mspline::spline {

enum class SplineKind {
  /// Manifold triangular B-spline (DMS spline on the domain triangulation).
  TriangularBSpline = 1,
};

/// The knots of one domain face in its home frame: knots[corner][b] = t_{corner,b}, b = 0 .. n,
/// with knots[corner][0] the corner itself.
using FaceKnots = std::array<std::vector<Eigen::Vector2d>, 3>;

struct SplineModel {
  SplineKind kind = SplineKind::TriangularBSpline;
  /// The surface mesh (positions and counter-clockwise triangles) the spline was built on, and
  /// where each of its vertices lies in the domain.
  Eigen::MatrixX3d surfaceVertices;
  std::vector<std::array<int, 3>> surfaceFaces;
  std::vector<DomainPoint> surfaceVertexLocations;
  /// The domain triangulation and, per domain vertex, the surface vertex it is.
  SplineDomain domain;
  std::vector<int> domainVertexSource;
  /// Polynomial degree n.
  int degree = 3;
  /// Knots of every domain face (n + 1 per corner).
  std::vector<FaceKnots> knots;
  /// One row per basis function, face by face: row f * (n + 1)(n + 2) / 2 + k is the control point
  /// of the k-th basis function of face f, beta in the order (n,0,0), (n-1,1,0), (n-1,0,1),
  /// (n-2,2,0), ... (beta_0 descending, then beta_1 descending).
  Eigen::MatrixXd controlPoints;
};

}  // namespace mspline::spline
