#pragma once
// Geometric summary of a mesh, as `mspline info` prints it.
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct MeshStatistics {
  /// Length of the axis-aligned bounding box's diagonal.
  double bboxDiagonal = 0;
  /// Corners of the bounding box.
  OpenMesh::Vec3d bboxMin{0, 0, 0}, bboxMax{0, 0, 0};
  /// Smallest and median interior angle over all triangle corners, in degrees.
  double minAngleDegrees = 0;
  double medianAngleDegrees = 0;
  /// Shortest and longest edge.
  double minEdgeLength = 0;
  double maxEdgeLength = 0;
  /// Total surface area.
  double area = 0;
  /// Largest angle between the normals of two triangles sharing an edge (degrees; degenerate
  /// triangles left out), and the edges where it exceeds 90 degrees: creases that a smooth surface
  /// following the mesh closely folds at (a fitted surface's folds are judged against this mesh's
  /// normals, spline/quality/surface_quality.h).
  double maxDihedralDegrees = 0;
  int foldedEdges = 0;
};

MeshStatistics meshStatistics(const TriMesh& mesh);

}  // namespace mspline::structure
