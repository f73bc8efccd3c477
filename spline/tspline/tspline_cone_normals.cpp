#include "mspline/spline/tspline/tspline_cone_normals.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "mspline/structure/core/constants.h"

namespace mspline::spline {

std::vector<ConeNormalSpread> coneNormalSpreads(const TSplineSpace& space,
                                                const Eigen::MatrixXd& control,
                                                const Eigen::VectorXd& weights, double offset) {
  if (control.cols() != 3) return {};
  const TMesh& mesh = space.mesh();
  std::vector<std::vector<int>> sectors(std::size_t(mesh.numVertices));
  for (const TSplineCapFace& cap : space.capFaces())
    sectors[std::size_t(cap.cone)].push_back(cap.face);
  std::vector<ConeNormalSpread> spreads;
  std::vector<Eigen::Vector3d> normals;
  for (int v = 0; v < mesh.numVertices; ++v) {
    const std::vector<int>& around = sectors[std::size_t(v)];
    if (around.empty()) continue;
    ConeNormalSpread cone;
    cone.vertex = v;
    cone.valence = int(around.size());
    const int perFace = std::max(2, (8 + cone.valence - 1) / cone.valence);
    normals.clear();
    // The faces in any order, each swept from either side: the spread is over all pairs.
    for (const int f : around) {
      const TMeshFace& face = mesh.faces[std::size_t(f)];
      const auto at = std::find(face.vertices.begin(), face.vertices.end(), v);
      const Eigen::Vector2d corner = face.positions[std::size_t(at - face.vertices.begin())];
      const double sx = corner.x() < 0.5 * face.width ? 1.0 : -1.0;
      const double sy = corner.y() < 0.5 * face.height ? 1.0 : -1.0;
      cone.cellSize = std::min(face.width, face.height);
      for (int j = 0; j < perFace; ++j) {
        const double angle = (j + 0.5) / perFace * kPi / 2.0;
        const Eigen::Vector2d p =
            corner +
            offset * cone.cellSize * Eigen::Vector2d(sx * std::cos(angle), sy * std::sin(angle));
        normals.push_back(space.evaluate(control, weights, f, p, 1).normal);
      }
    }
    for (const auto& a : normals)
      for (const auto& b : normals)
        cone.spread = a.allFinite() && b.allFinite()
                          ? std::max(cone.spread, std::atan2(a.cross(b).norm(), a.dot(b)))
                          : kPi;
    spreads.push_back(cone);
  }
  return spreads;
}

}  // namespace mspline::spline
