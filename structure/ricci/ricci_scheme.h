#pragma once
// A discrete metric scheme for the Ricci flow: how edge lengths follow from the conformal factors
// u, and the convex Ricci energy with its gradient (K - K_target) and Hessian (dK/du).
#include <functional>
#include <string>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "mspline/structure/core/index_map.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/circle_packing_energy.h"

namespace mspline::structure {

/// The functions refer to the mesh they were made for: it must outlive the scheme.
struct RicciScheme {
  /// Short name for reports: "yamabe", "tangential" or "inversive".
  std::string name;
  /// Edge lengths (by edge index) of the metric with factors u (per vertex).
  std::function<Eigen::VectorXd(const Eigen::VectorXd& u)> lengths;
  /// Ricci energy up to a constant, and its gradient K(u) - target (per vertex).
  std::function<double(const Eigen::VectorXd& u, const Eigen::VectorXd& target)> energy;
  std::function<Eigen::VectorXd(const Eigen::VectorXd& u, const Eigen::VectorXd& target)> gradient;
  /// Hessian dK/du restricted to the unknowns.
  std::function<Eigen::SparseMatrix<double>(const Eigen::VectorXd& u, const IndexMap& unknowns)>
      hessian;
};

/// Vertex scaling (discrete Yamabe flow): u = 0 reproduces the input lengths exactly.
RicciScheme vertexScalingScheme(const TriMesh& mesh);

/// Circle packing with the given radii and edge coefficients (thurstonPackingMetric or
/// inversiveDistanceMetric); `name` goes into reports.
RicciScheme circlePackingScheme(const TriMesh& mesh, const CirclePackingMetric& metric,
                                const std::string& name);

}  // namespace mspline::structure
