#pragma once
// A spline model: everything a spline surface on a mesh needs, as saved in a .msp file
// (io/spline_model_file.h): the surface it lives on, the domain triangulation with its flat
// metric (which determines the charts, spline_domain.h), the knots, the degree and the control
// points.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tribspline/spline_domain.h"
#include "mspline/spline/tspline/tmesh.h"

namespace mspline::spline {

enum class SplineKind {
  /// Manifold triangular B-spline (DMS spline on the domain triangulation).
  TriangularBSpline = 1,
  /// Manifold cubic T-spline on a T-mesh (tspline.h).
  TSpline = 2,
  /// Catmull-Clark limit surface (subd_fit_space.h) of the net of a T-mesh without T-junctions:
  /// the baseline T-spline fits are compared with.
  Subdivision = 3,
};

/// The knots of one domain face in its home frame: knots[corner][b] = t_{corner,b}, b = 0 .. n,
/// with knots[corner][0] the corner itself.
using FaceKnots = std::array<std::vector<Eigen::Vector2d>, 3>;

struct SplineModel {
  SplineKind kind = SplineKind::TriangularBSpline;
  /// The surface mesh (positions and counter-clockwise triangles) the spline was built on.
  Eigen::MatrixX3d surfaceVertices;
  std::vector<std::array<int, 3>> surfaceFaces;
  /// Per surface face, 1 when it fills a hole of the scan (structure/mesh/cap_holes.h): the spline
  /// there is fairing, not data, and export trims it away. Empty: no filled faces.
  std::vector<char> surfaceFaceFilled;
  /// Triangular B-splines only (empty for T-splines): where each surface vertex lies in the
  /// domain, the domain triangulation and, per domain vertex, the surface vertex it is.
  std::vector<SurfacePoint> surfaceVertexLocations;
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

  /// T-splines and subdivision surfaces: the T-mesh (degree 3; without T-junctions for a
  /// subdivision surface) and where each surface vertex lies on it. controlPoints then has one
  /// row per T-spline blending function, in the order of TSplineSpace(tmesh).anchors(), or for a
  /// subdivision surface one row per T-mesh vertex (the net's points).
  TMesh tmesh;
  std::vector<FacePoint> surfaceVertexTMeshPoints;
  /// T-splines only: one weight per blending function (empty for subdivision surfaces).
  Eigen::VectorXd weights;
};

}  // namespace mspline::spline
