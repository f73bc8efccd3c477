#pragma once
// A mesh whose faces carry labels (e.g. Voronoi cells) with polylines drawn on it, as OBJ.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::io {

struct LabeledPolyline {
  /// OBJ group the polyline is written in.
  std::string group;
  /// Points in space; a last point equal to the first closes the line.
  std::vector<Eigen::Vector3d> points;
};

/// Writes `path` (.obj) through a temporary file renamed into place: the mesh's vertices, its
/// faces grouped by label in ascending order, each group headed `g <labelPrefix><label>`, then
/// every polyline in `g <group>` as extra vertices and one `l` element (a closed one ends on its
/// first vertex). Throws InputError for a path that is not .obj, labels that are not one per face
/// or negative, or a polyline with fewer than two points; IoError when writing fails.
void writeLabeledObj(const std::string& path, const structure::TriMesh& mesh,
                     const std::vector<int>& faceLabels, const std::string& labelPrefix,
                     const std::vector<LabeledPolyline>& polylines);

}  // namespace mspline::io
