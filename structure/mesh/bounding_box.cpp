#include "mspline/structure/mesh/bounding_box.h"

#include "mspline/structure/core/exact_scale.h"
#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::structure {

double boundingBoxDiagonal(const Eigen::MatrixX3d& points) {
  if (points.rows() == 0) return 0.0;
  const Eigen::RowVector3d extent = points.colwise().maxCoeff() - points.colwise().minCoeff();
  return exactScaledNorm(extent[0], extent[1], extent[2]);
}

double boundingBoxDiagonal(const std::vector<std::array<double, 3>>& points) {
  return boundingBoxDiagonal(pointMatrix(points));
}

double boundingBoxDiagonal(const TriMesh& mesh) {
  Eigen::MatrixX3d rows(Eigen::Index(mesh.n_vertices()), 3);
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    rows.row(v.idx()) << p[0], p[1], p[2];
  }
  return boundingBoxDiagonal(rows);
}

}  // namespace mspline::structure
