#pragma once
// A surface on a T-mesh as a triangle mesh, watertight like tessellate.h's: every T-mesh vertex
// and every T-mesh edge is sampled once and its samples shared by the faces on both sides. The
// sampling is the same for any surface given as a function of (face, position in its frame)
// (tessellateTMeshSurface): T-splines (tessellateTSpline) and Catmull-Clark limit surfaces of a
// T-mesh's net (spline/subd/subd_tessellate.h).
//
// Sampling: each edge (a side of a face between two consecutive boundary vertices, identified
// with its twin across the side) gets `resolution` equal segments; each face gets the interior
// points of the grid of `resolution` x `resolution` equal cells of its rectangle. A face without
// T-junctions (4 boundary vertices) is then that grid, two triangles a cell. A face with
// T-junctions has more boundary samples than its grid has on its sides, so its grid is stitched to
// its boundary: the grid's cells between its interior points are triangulated as usual, and the
// ring between the boundary polyline and the outermost interior grid points is zipped side by
// side (along each side of the rectangle, the two chains of points are merged by their
// coordinate along the side; every triangle has an edge on one chain and its apex on the other,
// so none is inverted). At resolution 1 and 2 such a face has one interior point, its centre
// (at resolution 1 added for it), and the ring is a fan around it.
//
// T-spline positions are TSplineBezier's, except where the denominator sum_i w_i N_i is below 1e-6
// (times the largest weight): there the Bezier coefficients' rounding is no longer small against
// it, and TSplineSpace::evaluate gives the point (and tells holes, where it is exactly 0). A
// T-spline is defined at its extraordinary vertices (caps, tspline_cap.h): their samples are the
// cone points, with the caps' normal. Where a surface has a hole a sample stands for the
// mean, over the faces that hold it, of the surface evaluated a fraction `holeOffset` of the way
// from the sample towards each face's centre (ten times further, up to the centre, if that is in
// the hole too): the limit of the surface around the hole, a point it approaches to O(holeOffset).
// No NaN is written.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::spline {

/// A surface on a T-mesh: writes the point at p of `face` (its frame) and, when `normal` is
/// given, the unit normal ds x dt / |ds x dt| there (zero where that vanishes); returns false
/// where the surface is undefined (a hole).
using TMeshSurface = std::function<bool(int face, const Eigen::Vector2d& p,
                                        Eigen::Vector3d& position, Eigen::Vector3d* normal)>;

struct TMeshTessellation {
  /// The surface's triangles, counter-clockwise in the face frames.
  structure::PolygonSoup mesh;
  /// Per mesh vertex: the T-mesh point it is the surface at (for a hole sample, the point in the
  /// hole it stands for). Mesh vertex v < TMesh::numVertices is T-mesh vertex v's sample.
  std::vector<FacePoint> vertexPoints;
  /// The mesh vertices that are hole samples (ascending).
  std::vector<int> holeVertices;
  /// See the header comment.
  double holeOffset = 0.0;
  /// Edge samples taken 1% of the way towards their face's centre because the surface is one
  /// point along their whole edge, so that no triangle has zero area.
  int collapsedEdgeSamples = 0;
  /// Per mesh vertex: the unit normal ds x dt / |ds x dt| at vertexPoints (pointing to the side the
  /// triangles face); for hole samples, and where ds x dt vanishes, the normal of the triangles
  /// around the vertex (spline::vertexNormalsOfMesh).
  std::vector<std::array<double, 3>> normals;
  /// Per mesh vertex: its chart coordinates, vertexPoints' position in the frame of its T-mesh face
  /// (for a vertex shared by faces, the first face that holds it).
  std::vector<std::array<double, 2>> uvs;
  /// Where the surface was evaluated (CSR): mesh vertex v is the mean of the surface at
  /// samplePoints[sampleOffsets[v] .. sampleOffsets[v + 1]): vertexPoints[v] for every vertex but
  /// the hole samples, which have the points off the hole (one per face around it that has one).
  /// sampleOffsets has one entry more than the mesh has vertices.
  std::vector<std::int64_t> sampleOffsets;
  std::vector<FacePoint> samplePoints;
};

struct TSplineTessellation : TMeshTessellation {
  /// Smallest denominator sum_i w_i N_i at the points evaluated for the mesh (for hole samples,
  /// the points off the hole); +infinity for an empty mesh.
  double minDenominator = 0.0;
};

/// The unit normal ds x dt / |ds x dt|, zero where that vanishes.
Eigen::Vector3d unitNormal(const Eigen::Vector3d& ds, const Eigen::Vector3d& dt);

/// Samples `surface` on `mesh` `resolution` times along every T-mesh edge (resolution >= 1), as
/// the header comment says (a non-finite point counts as a hole). `what` names the result (its
/// mesh's sourceName) and starts the messages. Throws InputError for a resolution below 1 or a
/// face whose centre lies in a hole.
TMeshTessellation tessellateTMeshSurface(const TMesh& mesh, const TMeshSurface& surface,
                                         int resolution, const std::string& what);

/// Samples the surface with `control` (numBasis x 3) and `weights` (numBasis, or empty for all 1)
/// `resolution` times along every T-mesh edge (resolution >= 1). Throws InputError for a
/// resolution below 1, wrong sizes, or a face whose centre lies in a hole.
TSplineTessellation tessellateTSpline(const TSplineSpace& space, const Eigen::MatrixXd& control,
                                      const Eigen::VectorXd& weights, int resolution);

}  // namespace mspline::spline
