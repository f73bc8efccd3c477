#pragma once
// The cotangent Laplacian of a triangle mesh with its embedding's edge lengths.
#include <Eigen/SparseCore>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

/// The V x V positive semidefinite cotangent Laplacian: L(i,j) = -w_ij for every edge ij and
/// L(i,i) = sum_j w_ij, with w_ij = (cot a + cot b) / 2 over the angles opposite the edge (one
/// term on a boundary edge). Both triangles are stored, compressed, indexed by vertex idx(); an
/// isolated vertex gets an explicit zero diagonal. Its null space holds the constants of each
/// component. Throws InputError naming the face when a face has zero area.
Eigen::SparseMatrix<double> cotanLaplacian(const TriMesh& mesh);

}  // namespace mspline::structure
