#pragma once
// Circle-packing metrics and their Ricci energy (paper, eq. 7 and 13; Zhang, Guo, Zeng, Luo, Yau
// and Gu 2014, "The unified discrete surface Ricci flow").
//
// Every vertex carries a circle of radius r_i = radius_i * exp(u_i); the length of edge ij is
//   l_ij^2 = r_i^2 + r_j^2 + 2 eta_ij r_i r_j,
// with eta_ij = cos Phi_ij for Thurston's packing with intersection angles Phi_ij in [0, pi/2], and
// eta_ij = I_ij >= -1, the inversive distance, for inversive-distance packing. The energy's
// gradient is K - K_target and its Hessian dK/du is symmetric with zero row sums (scaling every
// radius scales the metric); for Thurston's packing it is positive semidefinite. Vectors are
// indexed by OpenMesh idx(): u, radii and curvatures by vertex, eta and lengths by edge.
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "mspline/structure/core/index_map.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

/// The fixed data of a circle-packing metric; u = 0 gives radii `radius`.
struct CirclePackingMetric {
  /// Circle radius per vertex at u = 0 (positive).
  Eigen::VectorXd radius;
  /// Per edge: cos Phi (Thurston) or the inversive distance I (>= -1).
  Eigen::VectorXd eta;
};

/// Thurston's packing approximating the input: radius_i is the mean over the faces at i of the
/// radius of the face's tangent circle at i, (l_ij + l_ik - l_jk) / 2, and Phi_ij solves eq. 7 for
/// the input length, clamped to [0, pi/2] (so u = 0 reproduces the input only approximately; where
/// the circles do not overlap, Phi = 0 and the edge comes out shorter). Throws InputError when a
/// face violates the strict triangle inequality.
CirclePackingMetric thurstonPackingMetric(const TriMesh& mesh);

/// Inversive-distance packing reproducing the input at u = 0: the radii of
/// thurstonPackingMetric and I_ij computed from the input lengths. Throws InputError when a face
/// violates the strict triangle inequality or some I_ij < -1 (one circle inside the other).
CirclePackingMetric inversiveDistanceMetric(const TriMesh& mesh);

/// Edge lengths of the metric at u, by edge index.
Eigen::VectorXd circlePackingEdgeLengths(const TriMesh& mesh, const CirclePackingMetric& metric,
                                         const Eigen::VectorXd& u);

/// The Ricci energy int_0^u sum_i (K_i - target_i) du_i along the straight segment from 0,
/// normalized to E(0) = 0. `targetCurvature` holds K_target (interior) or the target geodesic
/// curvature (boundary) per vertex.
double circlePackingEnergy(const TriMesh& mesh, const CirclePackingMetric& metric,
                           const Eigen::VectorXd& u, const Eigen::VectorXd& targetCurvature);

/// Gradient of circlePackingEnergy: K(u) - targetCurvature, per vertex. Triangles violating the
/// triangle inequality (possible for inversive distances) get the angles (0, 0, pi).
Eigen::VectorXd circlePackingGradient(const TriMesh& mesh, const CirclePackingMetric& metric,
                                      const Eigen::VectorXd& u,
                                      const Eigen::VectorXd& targetCurvature);

/// Hessian of circlePackingEnergy, dK/du. Triangles violating the triangle inequality contribute
/// zero but keep their entries, so the pattern is fixed.
Eigen::SparseMatrix<double> circlePackingHessian(const TriMesh& mesh,
                                                 const CirclePackingMetric& metric,
                                                 const Eigen::VectorXd& u);

/// The rows and columns of the Hessian that belong to the unknowns of `unknowns`, built directly in
/// that numbering.
Eigen::SparseMatrix<double> circlePackingHessian(const TriMesh& mesh,
                                                 const CirclePackingMetric& metric,
                                                 const Eigen::VectorXd& u,
                                                 const IndexMap& unknowns);

}  // namespace mspline::structure
