#include "mspline/structure/mesh/mesh_statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/exact_scale.h"

namespace mspline::structure {

MeshStatistics meshStatistics(const TriMesh& mesh) {
  MeshStatistics stats;
  bool first = true;
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    if (first) {
      stats.bboxMin = stats.bboxMax = p;
      first = false;
    } else {
      stats.bboxMin.minimize(p);
      stats.bboxMax.maximize(p);
    }
  }
  const OpenMesh::Vec3d extent = stats.bboxMax - stats.bboxMin;
  stats.bboxDiagonal = exactScaledNorm(extent[0], extent[1], extent[2]);

  if (mesh.n_edges() > 0) {
    stats.minEdgeLength = std::numeric_limits<double>::infinity();
    for (const auto e : mesh.edges()) {
      OpenMesh::Vec3d edge;
      mesh.calc_edge_vector(e, edge);
      const double length = exactScaledNorm(edge[0], edge[1], edge[2]);
      stats.minEdgeLength = std::min(stats.minEdgeLength, length);
      stats.maxEdgeLength = std::max(stats.maxEdgeLength, length);
    }
  }

  std::vector<double> angles;
  angles.reserve(3 * mesh.n_faces());
  std::vector<OpenMesh::Vec3d> unitNormals(mesh.n_faces(), OpenMesh::Vec3d(0, 0, 0));
  constexpr double kDegrees = 180.0 / kPi;
  for (const auto f : mesh.faces()) {
    const auto h0 = mesh.halfedge_handle(f);
    const auto h1 = mesh.next_halfedge_handle(h0);
    const OpenMesh::Vec3d p[3] = {mesh.point(mesh.from_vertex_handle(h0)),
                                  mesh.point(mesh.from_vertex_handle(h1)),
                                  mesh.point(mesh.to_vertex_handle(h1))};
    // Angles on edges scaled by a power of two (exact): the products below neither overflow nor
    // underflow at any unit, and the area is scaled back.
    const double scale =
        exactUnitScale(std::max({(p[1] - p[0]).max_abs(), (p[2] - p[0]).max_abs()}));
    const OpenMesh::Vec3d normal = OpenMesh::cross((p[1] - p[0]) * scale, (p[2] - p[0]) * scale);
    const double twiceArea = normal.norm();
    stats.area += 0.5 * twiceArea / scale / scale;
    if (twiceArea > 0.0) unitNormals[std::size_t(f.idx())] = normal / twiceArea;
    for (int k = 0; k < 3; ++k) {
      const OpenMesh::Vec3d a = (p[(k + 1) % 3] - p[k]) * scale,
                            b = (p[(k + 2) % 3] - p[k]) * scale;
      // atan2 stays accurate for angles near 0 and 180 degrees, where acos of the cosine does not;
      // |a x b| equals twice the area at every corner.
      angles.push_back(std::atan2(twiceArea, OpenMesh::dot(a, b)) * kDegrees);
    }
  }
  if (!angles.empty()) {
    stats.minAngleDegrees = *std::min_element(angles.begin(), angles.end());
    const auto middle = angles.begin() + angles.size() / 2;
    std::nth_element(angles.begin(), middle, angles.end());
    stats.medianAngleDegrees = *middle;
    if (angles.size() % 2 == 0)  // even count: average the two middle values
      stats.medianAngleDegrees =
          0.5 * (stats.medianAngleDegrees + *std::max_element(angles.begin(), middle));
  }

  for (const auto e : mesh.edges()) {
    if (mesh.is_boundary(e)) continue;
    const auto& a = unitNormals[std::size_t(mesh.face_handle(mesh.halfedge_handle(e, 0)).idx())];
    const auto& b = unitNormals[std::size_t(mesh.face_handle(mesh.halfedge_handle(e, 1)).idx())];
    if (a.sqrnorm() == 0.0 || b.sqrnorm() == 0.0) continue;
    const double angle = std::atan2(OpenMesh::cross(a, b).norm(), OpenMesh::dot(a, b)) * kDegrees;
    stats.maxDihedralDegrees = std::max(stats.maxDihedralDegrees, angle);
    stats.foldedEdges += angle > 90.0 ? 1 : 0;
  }
  return stats;
}

}  // namespace mspline::structure
