#pragma once
// A spline model: everything a spline surface on a mesh needs, as saved in a .msp file
// (io/spline_model_file.h): the surface it lives on, the domain triangulation with its flat
// metric (which determines the charts, spline_domain.h), the knots, the degree and the control
// points.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "spline/spline_domain.h"
#include "spline/tmesh.h"

namespace mspline::spline {

enum class SplineKind {
  /// Manifold triangular B-spline (DMS spline on the domain triangulation).
  TriangularBSpline = 1,
  /// Manifold cubic T-spline on a T-mesh (tspline.h).
  TSpline = 2,
};

/// The knots of one domain face in its home frame: knots[corner][b] = t_{corner,b}, b = 0 .. n,
/// with knots[corner][0] the corner itself.
using FaceKnots = std::array<std::vector<Eigen::Vector2d>, 3>;

struct SplineModel {
  SplineKind kind = SplineKind::TriangularBSpline;
  /// The surface mesh (positions and counter-clockwise triangles) the spline was built on.
  Eigen::MatrixX3d surfaceVertices;
  std::vector<std::array<int, 3>> surfaceFaces;
  /// Triangular B-splines only (empty for T-splines): where each surface vertex lies in the
  /// domain, the domain triangulation and, per domain vertex, the surface vertex it is.
  std::vector<DomainPoint> surfaceVertexLocations;
  SplineDomain domain;
  std::vector<int> domainVertexSource;
  /// Polynomial degree n (3 for T-splines).
  int degree = 3;
  /// Knots of every domain face (n + 1 per corner).
  std::vector<FaceKnots> knots;
  /// One row per basis function. Triangular B-splines: face by face, row f * (n + 1)(n + 2) / 2 + k
  /// is the control point of the k-th basis function of face f, beta in the order (n,0,0),
  /// (n-1,1,0), (n-1,0,1), (n-2,2,0), ... (beta_0 descending, then beta_1 descending).
  Eigen::MatrixXd controlPoints;

  /// T-splines only: the T-mesh (degree 3), where each surface vertex lies on it, and one weight
  /// per blending function. controlPoints then has one row per blending function, in the order of
  /// TSplineSpace(tmesh).anchors().
  TMesh tmesh;
  std::vector<TMeshPoint> surfaceVertexTMeshPoints;
  Eigen::VectorXd weights;
};

}  // namespace mspline::spline
