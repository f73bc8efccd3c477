#pragma once
// The vertex-scaling (discrete Yamabe) metric and its convex Ricci energy.
//
// Edge lengths l_ij = exp((u_i + u_j) / 2) * l0_ij, where l0 are the input lengths, so u = 0
// reproduces the input exactly (Luo 2004). The energy is the one of Bobenko, Pinkall and Springborn
// 2015 ("Discrete conformal maps and ideal hyperbolic polyhedra"), extended to triangles that
// violate the triangle inequality by the angles (0, 0, pi); it is convex and C^1 on all of R^n,
//   gradient_i = K_i - K_target_i,   Hessian = cotangent Laplacian of the current metric,
// with K_i = 2 pi - (angle sum) at interior vertices and pi - (angle sum) (the geodesic curvature)
// at boundary vertices. Vectors are indexed by OpenMesh idx(): u and curvatures by vertex, lengths
// by edge, corner angles by halfedge.
#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "mspline/structure/core/index_map.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

/// The Lobachevsky (Milnor) function L(x) = -int_0^x log|2 sin t| dt = Cl2(2x) / 2, pi-periodic
/// and odd; accurate to about 1e-16 absolute (two 16-term power series of the Clausen integral,
/// about 0 and about pi).
double lobachevsky(double x);

/// Angles opposite the sides a, b, c of a triangle, by the half-angle formula (accurate for
/// needles). When the lengths violate the triangle inequality, the angle opposite the longest side
/// is pi and the others 0, the continuous extension of Bobenko, Pinkall and Springborn.
std::array<double, 3> triangleAngles(double a, double b, double c);

/// Four times the area of a triangle with side lengths a, b, c (Kahan's stable Heron formula); 0
/// when the lengths violate the triangle inequality. Every metric scheme's cotangents use it.
double fourTimesArea(double a, double b, double c);

/// True when a, b, c satisfy the strict triangle inequality (the triangle has positive area).
bool satisfiesTriangleInequality(double a, double b, double c);

/// Input edge lengths, by edge index.
Eigen::VectorXd edgeLengths(const TriMesh& mesh);

/// Lengths exp((u_i + u_j) / 2) * l0_ij of the scaled metric, by edge index.
Eigen::VectorXd scaledEdgeLengths(const TriMesh& mesh, const Eigen::VectorXd& inputLengths,
                                  const Eigen::VectorXd& u);

/// Faces whose lengths violate the strict triangle inequality (ascending face indices).
std::vector<int> degenerateFaces(const TriMesh& mesh, const Eigen::VectorXd& lengths);

/// For every halfedge inside a face, the angle of that face opposite the halfedge; 0 on boundary
/// halfedges.
Eigen::VectorXd cornerAngles(const TriMesh& mesh, const Eigen::VectorXd& lengths);

/// Curvature of every vertex: 2 pi - angle sum inside, pi - angle sum on the boundary.
Eigen::VectorXd vertexCurvatures(const TriMesh& mesh, const Eigen::VectorXd& lengths);

/// The Ricci energy at u, normalized to E(0) = 0. `targetCurvature` holds K_target (interior) or
/// the target geodesic curvature (boundary) per vertex.
double vertexScalingEnergy(const TriMesh& mesh, const Eigen::VectorXd& inputLengths,
                           const Eigen::VectorXd& u, const Eigen::VectorXd& targetCurvature);

/// Gradient of vertexScalingEnergy: K(u) - targetCurvature, per vertex.
Eigen::VectorXd vertexScalingGradient(const TriMesh& mesh, const Eigen::VectorXd& inputLengths,
                                      const Eigen::VectorXd& u,
                                      const Eigen::VectorXd& targetCurvature);

/// Hessian of vertexScalingEnergy: the cotangent Laplacian of the metric at u, edge weights
/// (cot a + cot b) / 2, positive diagonal. Triangles violating the triangle inequality contribute
/// zero (the extended energy is flat in them) but keep their entries, so the pattern is fixed.
Eigen::SparseMatrix<double> vertexScalingHessian(const TriMesh& mesh,
                                                 const Eigen::VectorXd& inputLengths,
                                                 const Eigen::VectorXd& u);

/// The rows and columns of the Hessian that belong to the unknowns of `unknowns` (vertices whose u
/// is held fixed are excluded), built directly in that numbering.
Eigen::SparseMatrix<double> vertexScalingHessian(const TriMesh& mesh,
                                                 const Eigen::VectorXd& inputLengths,
                                                 const Eigen::VectorXd& u,
                                                 const IndexMap& unknowns);

}  // namespace mspline::structure
