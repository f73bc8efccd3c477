#include "mspline/structure/ricci/ricci_scheme.h"

#include "mspline/structure/ricci/vertex_scaling_energy.h"

namespace mspline::structure {

RicciScheme vertexScalingScheme(const TriMesh& mesh) {
  const Eigen::VectorXd inputLengths = edgeLengths(mesh);
  const TriMesh* m = &mesh;
  RicciScheme scheme;
  scheme.name = "yamabe";
  scheme.lengths = [m, inputLengths](const Eigen::VectorXd& u) {
    return scaledEdgeLengths(*m, inputLengths, u);
  };
  scheme.energy = [m, inputLengths](const Eigen::VectorXd& u, const Eigen::VectorXd& target) {
    return vertexScalingEnergy(*m, inputLengths, u, target);
  };
  scheme.gradient = [m, inputLengths](const Eigen::VectorXd& u, const Eigen::VectorXd& target) {
    return vertexScalingGradient(*m, inputLengths, u, target);
  };
  scheme.hessian = [m, inputLengths](const Eigen::VectorXd& u, const IndexMap& unknowns) {
    return vertexScalingHessian(*m, inputLengths, u, unknowns);
  };
  return scheme;
}

RicciScheme circlePackingScheme(const TriMesh& mesh, const CirclePackingMetric& metric,
                                const std::string& name) {
  const TriMesh* m = &mesh;
  RicciScheme scheme;
  scheme.name = name;
  scheme.lengths = [m, metric](const Eigen::VectorXd& u) {
    return circlePackingEdgeLengths(*m, metric, u);
  };
  scheme.energy = [m, metric](const Eigen::VectorXd& u, const Eigen::VectorXd& target) {
    return circlePackingEnergy(*m, metric, u, target);
  };
  scheme.gradient = [m, metric](const Eigen::VectorXd& u, const Eigen::VectorXd& target) {
    return circlePackingGradient(*m, metric, u, target);
  };
  scheme.hessian = [m, metric](const Eigen::VectorXd& u, const IndexMap& unknowns) {
    return circlePackingHessian(*m, metric, u, unknowns);
  };
  return scheme;
}

}  // namespace mspline::structure
