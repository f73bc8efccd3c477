#include "mspline/spline/subd/triangle_quad_split.h"

#include <string>

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

TriangleQuadSplit splitTrianglesIntoQuads(const structure::TriMesh& mesh) {
  const int nv = static_cast<int>(mesh.n_vertices());
  const int ne = static_cast<int>(mesh.n_edges());
  TriangleQuadSplit split;
  split.points.resize(nv + ne + static_cast<int>(mesh.n_faces()), 3);
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    split.points.row(v.idx()) << p[0], p[1], p[2];
  }
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const auto m =
        0.5 * (mesh.point(mesh.from_vertex_handle(h)) + mesh.point(mesh.to_vertex_handle(h)));
    split.points.row(nv + e.idx()) << m[0], m[1], m[2];
  }
  split.quads.reserve(3 * mesh.n_faces());
  for (auto f : mesh.faces()) {
    // Corner k is the to-vertex of the k-th halfedge from halfedge_handle(f) (the fv_range order);
    // the edge from corner k to corner k+1 is that of halfedge k+1.
    int corner[3], edge[3];
    auto h = mesh.halfedge_handle(f);
    for (int k = 0; k < 3; ++k, h = mesh.next_halfedge_handle(h)) {
      corner[k] = mesh.to_vertex_handle(h).idx();
      edge[(k + 2) % 3] = nv + mesh.edge_handle(h).idx();
    }
    const int centroid = nv + ne + f.idx();
    split.points.row(centroid) =
        (split.points.row(corner[0]) + split.points.row(corner[1]) + split.points.row(corner[2])) /
        3.0;
    for (int k = 0; k < 3; ++k)
      split.quads.push_back({corner[k], edge[k], centroid, edge[(k + 2) % 3]});
  }
  return split;
}

Eigen::Vector3d quadPointBarycentric(int corner, double u, double v) {
  if (corner < 0 || corner > 2)
    throw structure::InputError("quad corner " + std::to_string(corner) + " is not 0, 1 or 2");
  Eigen::Vector3d atCorner = Eigen::Vector3d::Zero(), toNext = atCorner, toPrevious = atCorner;
  atCorner[corner] = 1.0;
  toNext[corner] = toNext[(corner + 1) % 3] = 0.5;
  toPrevious[corner] = toPrevious[(corner + 2) % 3] = 0.5;
  const Eigen::Vector3d centroid = Eigen::Vector3d::Constant(1.0 / 3.0);
  return (1 - u) * (1 - v) * atCorner + u * (1 - v) * toNext + u * v * centroid +
         (1 - u) * v * toPrevious;
}

}  // namespace mspline::spline
