#include "mspline/structure/core/surface_point.h"

#include <cmath>
#include <random>
#include <sstream>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

void checkSurfacePoint(const TriMesh& mesh, const SurfacePoint& point, const std::string& what) {
  if (point.face < 0 || point.face >= static_cast<int>(mesh.n_faces()))
    throw InputError(what + ": face " + std::to_string(point.face) +
                     " is out of range (the mesh has " + std::to_string(mesh.n_faces()) +
                     " faces)");
  const Eigen::Vector3d& b = point.barycentric;
  if (!b.allFinite() || b.minCoeff() < -1e-12 || std::abs(b.sum() - 1.0) > 1e-9) {
    std::ostringstream shown;
    shown.precision(17);
    shown << b[0] << ' ' << b[1] << ' ' << b[2];
    throw InputError(what + ": barycentric coordinates " + shown.str() +
                     " are not >= 0 with sum 1");
  }
}

Eigen::Vector3d surfacePosition(const TriMesh& mesh, const SurfacePoint& point) {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  int k = 0;
  for (auto v : mesh.fv_range(TriMesh::FaceHandle(point.face))) {
    const auto& p = mesh.point(v);
    position += point.barycentric[k++] * Eigen::Vector3d(p[0], p[1], p[2]);
  }
  return position;
}

std::vector<SurfacePoint> randomSurfacePoints(const TriMesh& mesh, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> face(0, static_cast<int>(mesh.n_faces()) - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<SurfacePoint> points(static_cast<std::size_t>(count));
  for (SurfacePoint& point : points) {
    point.face = face(random);
    // Uniform in the triangle: the square-root trick.
    const double s = std::sqrt(unit(random)), t = unit(random);
    point.barycentric = {1.0 - s, s * (1.0 - t), s * t};
  }
  return points;
}

}  // namespace mspline::structure
