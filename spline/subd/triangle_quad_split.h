#pragma once
// The topology of one Catmull-Clark step on a triangle mesh, with plain positions: every triangle
// becomes three quads through its edge midpoints and centroid. The result is a Catmull-Clark
// control net with extraordinary vertices everywhere (valence 3 at the centroids, the mesh's own
// valences at its vertices) over the same domain as the triangles, so a spline on the triangles can
// be compared point for point with the Catmull-Clark limit of the quads.
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::spline {

struct TriangleQuadSplit {
  /// Rows: the mesh's vertices (same indices), then the midpoint of edge e at V + e, then the
  /// centroid of face f at V + E + f (V vertices, E edges of the mesh).
  Eigen::MatrixXd points;
  /// Quad 3 f + k covers corner k of triangle f (corner k is the k-th vertex of fv_range(f)):
  /// [corner k, midpoint of edge (k, k+1), centroid, midpoint of edge (k-1, k)], oriented like
  /// the triangle.
  std::vector<std::vector<int>> quads;
};

/// Splits every triangle of `mesh` into three quads (see TriangleQuadSplit).
TriangleQuadSplit splitTrianglesIntoQuads(const structure::TriMesh& mesh);

/// Barycentric coordinates, in its triangle (corner order of fv_range), of the point (u, v) of the
/// quad at `corner` (0, 1 or 2) under the bilinear map of the quad's corners: (0,0) at the corner,
/// u towards the next corner, v towards the previous one, (1,1) at the centroid.
Eigen::Vector3d quadPointBarycentric(int corner, double u, double v);

}  // namespace mspline::spline
