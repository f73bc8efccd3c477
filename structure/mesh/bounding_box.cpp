#include "mspline/structure/mesh/bounding_box.h"

namespace mspline::structure {

double boundingBoxDiagonal(const Eigen::MatrixX3d& points) {
  if (points.rows() == 0) return 0.0;
  return (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
}

double boundingBoxDiagonal(const std::vector<std::array<double, 3>>& points) {
  Eigen::MatrixX3d rows(Eigen::Index(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    rows.row(Eigen::Index(i)) << points[i][0], points[i][1], points[i][2];
  return boundingBoxDiagonal(rows);
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
