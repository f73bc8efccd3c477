#pragma once
// An intrinsic triangulation for vertex scaling: the input's vertices with a connectivity of its
// own, changed by Ptolemy edge flips, and per-edge log-lengths at u = 0 (Penner coordinates, up
// to the factor 2 of lambda = 2 log l).
//
// The length of edge ij at scale factors u is exp(lambda0_ij + (u_i + u_j) / 2). A Ptolemy flip of
// the diagonal e of the quadrilateral with sides a, b (one triangle) and c, d (the other, a
// opposite c) sets l_new = (l_a l_c + l_b l_d) / l_e; since both sides scale by exp((u_k + u_l) /
// 2) the flip commutes with scaling, so lambda0 is updated once, independently of u, and the
// surface keeps its discrete conformal class (Gillespie, Springborn, Crane 2021, "Discrete
// conformal equivalence of polyhedral surfaces"). Flipping to the ideal Delaunay triangulation at u
// makes the Ricci energy of Bobenko, Pinkall and Springborn a convex C^1 function of u on all of
// R^n.
//
// Storage is a corner table (Delta-complex: loops and multiple edges between two vertices are
// allowed, as flips produce them): halfedge h lies in face h / 3, next(h) is the following one in
// that face, tip(h) is the vertex h points to. Edge indices start as the input's edge idx() and
// keep their index when flipped (then joining other vertices).
#include <array>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "mspline/structure/core/index_map.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

class IntrinsicTriangulation {
 public:
  /// No vertices, no faces.
  IntrinsicTriangulation() = default;
  /// The input connectivity with the input's Euclidean edge lengths.
  explicit IntrinsicTriangulation(const TriMesh& mesh);
  /// The input connectivity with the given positive lengths (by edge idx()).
  IntrinsicTriangulation(const TriMesh& mesh, const Eigen::VectorXd& edgeLengths);

  int vertexCount() const { return int(boundaryVertex_.size()); }
  int faceCount() const { return int(tip_.size() / 3); }
  int edgeCount() const { return int(edgeHalfedge_.size()); }

  int next(int h) const { return h - h % 3 + (h + 1) % 3; }
  int prev(int h) const { return h - h % 3 + (h + 2) % 3; }
  int tip(int h) const { return tip_[std::size_t(h)]; }
  int tail(int h) const { return tip_[std::size_t(prev(h))]; }
  /// The opposite halfedge in the neighbouring face, -1 on the boundary.
  int twin(int h) const { return twin_[std::size_t(h)]; }
  int edge(int h) const { return edge_[std::size_t(h)]; }
  /// One halfedge of edge e; flips of other edges keep its direction (edgeVertices' order).
  int halfedge(int e) const { return edgeHalfedge_[std::size_t(e)]; }
  bool isBoundaryEdge(int e) const { return twin(halfedge(e)) < 0; }
  bool isBoundaryVertex(int v) const { return boundaryVertex_[std::size_t(v)] != 0; }

  /// The two vertices of edge e.
  std::array<int, 2> edgeVertices(int e) const;
  /// The faces as vertex triples, in the faces' orientation (the input's, flips keep it).
  std::vector<std::array<int, 3>> faces() const;
  /// log l of every edge at u = 0.
  const Eigen::VectorXd& logLengths0() const { return logLength0_; }
  /// Replaces them (another metric on the same triangles, as when holonomy is prescribed).
  void setLogLengths0(const Eigen::VectorXd& logLengths);
  /// log l of every edge at u: lambda0_ij + (u_i + u_j) / 2.
  Eigen::VectorXd logLengths(const Eigen::VectorXd& u) const;
  /// Edge lengths at u, by edge index.
  Eigen::VectorXd lengths(const Eigen::VectorXd& u) const;
  /// False once edge e has been flipped (it then no longer is the input edge of that index).
  bool isInputEdge(int e) const { return inputEdge_[std::size_t(e)] != 0; }
  /// Number of flips made so far.
  long flipCount() const { return long(flippedEdges_.size()); }
  /// The edges flipped so far, in order: replaying these flips on the input reproduces this
  /// connectivity (intrinsic_overlay.h does, to map the input onto it).
  const std::vector<int>& flippedEdges() const { return flippedEdges_; }
  /// Mean input log-length: a fixed unit that keeps the energy's terms small (see
  /// intrinsicEnergy); flips do not change it.
  double logUnit() const { return logUnit_; }

  /// cos(alpha) + cos(beta) for the angles alpha, beta opposite interior edge e at u, by the law of
  /// cosines on the lengths (defined even where a triangle inequality fails; there it is the
  /// ideal-hyperbolic Delaunay quantity). The edge is Delaunay iff it is >= 0, i.e. alpha + beta <=
  /// pi. 0 on boundary edges.
  double delaunayCosineSum(int e, const Eigen::VectorXd& u) const;

  /// Ptolemy flip of interior edge e (InternalError on a boundary edge or an edge with the same
  /// face on both sides). Orientation and the other edges' indices are kept.
  void flip(int e);

  /// Flips interior edges with delaunayCosineSum < -tolerance until there is none; returns the
  /// number of flips. Terminates because every flip strictly lowers a bounded-below quantity
  /// (Springborn); InternalError after 100 * (edges + 1) flips, a guard against rounding cycles.
  /// `flipped`, when given, is called with each edge right after its flip.
  long flipToDelaunay(const Eigen::VectorXd& u, double tolerance = 1e-13,
                      const std::function<void(int)>& flipped = {});

 private:
  std::vector<int> tip_, twin_, edge_;
  std::vector<int> edgeHalfedge_;
  std::vector<char> boundaryVertex_;
  std::vector<char> inputEdge_;
  Eigen::VectorXd logLength0_;
  double logUnit_ = 0.0;
  std::vector<int> flippedEdges_;
};

/// For every halfedge, the angle of its face opposite it at u (BPS extension: pi opposite the
/// longest side and 0 elsewhere when the lengths violate the triangle inequality).
Eigen::VectorXd intrinsicCornerAngles(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u);

/// Curvature per vertex at u: 2 pi - angle sum inside, pi - angle sum on the boundary.
Eigen::VectorXd intrinsicCurvatures(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u);

/// The same from corner angles already computed (intrinsicCornerAngles).
Eigen::VectorXd curvaturesFromCornerAngles(const IntrinsicTriangulation& tri,
                                           const Eigen::VectorXd& cornerAngles);

/// The vertex-scaling Ricci energy of Bobenko, Pinkall and Springborn on this triangulation, up to
/// a constant that depends only on the face count:
///   E(u) = sum_i (Theta_i - angle sum_i(u)) u_i + sum_faces sum_k [(2 alpha_k - pi)
///          (lambda0_k - logUnit) + 2 L(alpha_k)],
/// Theta_i = (2 pi or pi) - targetCurvature_i. Its value is invariant under Ptolemy flips of edges
/// with cosine sum 0, so evaluated on the Delaunay triangulation at u it is one convex function.
/// When `magnitude` is given it receives the sum of the absolute values of the summed terms, the
/// scale of the rounding error of E.
double intrinsicEnergy(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u,
                       const Eigen::VectorXd& targetCurvature, double* magnitude = nullptr);

/// Gradient of intrinsicEnergy: curvature(u) - targetCurvature.
Eigen::VectorXd intrinsicGradient(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u,
                                  const Eigen::VectorXd& targetCurvature);

/// Hessian of intrinsicEnergy restricted to `unknowns`: the cotangent Laplacian of this
/// triangulation at u (weights (cot a + cot b) / 2; triangles violating the triangle inequality
/// contribute zero). Its pattern follows the connectivity.
Eigen::SparseMatrix<double> intrinsicHessian(const IntrinsicTriangulation& tri,
                                             const Eigen::VectorXd& u, const IndexMap& unknowns);

}  // namespace mspline::structure
