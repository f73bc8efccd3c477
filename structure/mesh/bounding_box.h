#pragma once
// The length of a point set's bounding-box diagonal: the unit every relative error is given in.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

/// The diagonal of the bounding box of `points` (rows); 0 for no points.
double boundingBoxDiagonal(const Eigen::MatrixX3d& points);
double boundingBoxDiagonal(const std::vector<std::array<double, 3>>& points);
double boundingBoxDiagonal(const TriMesh& mesh);

}  // namespace mspline::structure
