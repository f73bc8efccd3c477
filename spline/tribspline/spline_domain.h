#pragma once
// The domain of a manifold spline: a triangulation of a flat surface with cone singularities at
// some of its vertices (structure/layout/coarse_triangulation.h makes one from the flat metric of a
// mesh), and the charts the spline is evaluated in.
//
// Chart design: every face has a home chart, its own frame (corner 0 at the origin, corner 1 on
// the positive x axis) with its neighbourhood developed into it: the whole fan around each corner
// that is not a cone, and the faces across its sides. A flat fan develops without overlap, so the
// home chart is an isometric copy of that neighbourhood; around a cone no affine chart exists, and
// the development stops at the faces across the sides. Transitions between home charts are the
// rigid motions of the development. The basis functions of a face live in its home chart and are
// supported inside the developed neighbourhood, so a point of face G is evaluated by mapping it
// into the home chart of every face whose home chart holds G.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/atlas/affine_atlas.h"
#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/layout/coarse_triangulation.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::spline {

using structure::FacePoint;
using structure::SurfacePoint;

struct SplineDomain {
  /// Corners of every face (domain vertex indices), counter-clockwise.
  std::vector<std::array<int, 3>> faces;
  /// Flat length of side k of every face, which joins corners k and k + 1.
  std::vector<std::array<double, 3>> sideLengths;
  /// The face across side k, and the index of that side in it.
  std::vector<std::array<int, 3>> neighbour;
  std::vector<std::array<int, 3>> neighbourSide;
  /// Per domain vertex: 1 where the metric has a cone (no flat neighbourhood).
  std::vector<char> cone;

  int faceCount() const { return int(faces.size()); }
  int vertexCount() const { return int(cone.size()); }
};

/// Throws InputError when the arrays' sizes disagree, an index is out of range, the adjacency is
/// not symmetric, two sides glued together have different lengths (relative 1e-9), or a face
/// violates the strict triangle inequality.
void validateDomain(const SplineDomain& domain);

/// The domain of a closed mesh with a flat metric `lengths` (by edge idx()): face f, corner k is
/// the from-vertex of the k-th halfedge from halfedge_handle(f), side k that halfedge's edge, and
/// vertices whose curvature exceeds coneTolerance in absolute value are cones. InputError for a
/// surface with boundary or lengths that do not fit.
SplineDomain domainFromMesh(const structure::TriMesh& mesh, const Eigen::VectorXd& lengths,
                            double coneTolerance = 1e-6);

/// The domain of a coarse triangulation of a flat metric (its faces, lengths, adjacency and cones).
SplineDomain domainFromCoarse(const structure::CoarseTriangulation& coarse);

/// How far a domain's metric is from flat away from its cones, before and after polishing.
struct DomainPolish {
  /// max |curvature - target| over the vertices (radians): non-cones target 0, cones keep their
  /// curvature (plus an equal share of what the non-cones give up, for Gauss-Bonnet).
  double initialError = 0.0;
  double finalError = 0.0;
  int iterations = 0;
};

/// Rescales the side lengths (vertex scaling, Newton's method on the curvatures) until every
/// vertex that is no cone is flat to rounding. A coarse triangulation sums the rounding of the
/// fine metric and its flips into each vertex (about 1e-11 rad); left there, the knot clouds
/// carried around a vertex would not meet themselves, and the partition of unity would be off by
/// as much. The change of the lengths is of the same tiny order. InputError on an invalid domain,
/// SolverError when Newton's method does not bring the error below 1e-13.
DomainPolish polishDomainMetric(SplineDomain& domain);

/// Corner positions of a face in its own frame: corner 0 at the origin, corner 1 on the positive
/// x axis, corner 2 above it.
std::array<Eigen::Vector2d, 3> canonicalCorners(const SplineDomain& domain, int face);

/// The barycentric coordinates of the position x of a face's frame (canonicalCorners) with respect
/// to its corners; negative outside the face.
Eigen::Vector3d frameBarycentric(const SplineDomain& domain, int face, const Eigen::Vector2d& x);

/// The home chart of one face: the faces developed into its frame (the home face first, with the
/// identity) and for each the motion from its own frame into the home frame. A face may be there
/// more than once, at different places: a development that reaches it along two paths that go
/// around a cone or a handle (small domains, faces with a repeated vertex) holds two copies of
/// it, two different pieces of the neighbourhood, and a basis function of the home face counts
/// on both.
struct HomeChart {
  std::vector<int> faces;
  std::vector<structure::RigidMotion> placement;
  /// Index into `faces` of the first copy of face f, -1 when the chart does not hold it.
  int find(int face) const;
  /// Indices of all its copies.
  std::vector<int> findAll(int face) const;
};

/// Home charts of all faces. Throws InputError when a fan does not close (a vertex that is not
/// flat but not marked as a cone).
std::vector<HomeChart> buildHomeCharts(const SplineDomain& domain);

}  // namespace mspline::spline
