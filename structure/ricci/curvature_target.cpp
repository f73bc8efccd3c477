#include "mspline/structure/ricci/curvature_target.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::structure {

namespace {}  // namespace

CurvatureTarget flatTarget(const TriMesh& mesh, const std::vector<Cone>& cones,
                           BoundaryCondition boundary) {
  const auto n = static_cast<Eigen::Index>(mesh.n_vertices());
  CurvatureTarget target;
  target.curvature = Eigen::VectorXd::Zero(n);
  target.fixed.assign(mesh.n_vertices(), 0);
  if (boundary == BoundaryCondition::FixedScale) {
    for (const auto v : mesh.vertices())
      if (mesh.is_boundary(v)) target.fixed[v.idx()] = 1;
  }
  std::vector<char> seen(mesh.n_vertices(), 0);
  for (const Cone& cone : cones) {
    if (cone.vertex < 0 || cone.vertex >= static_cast<int>(n)) {
      std::ostringstream msg;
      msg << "cone vertex " << cone.vertex << " is out of range (the mesh has " << n
          << " vertices)";
      throw InputError(msg.str());
    }
    if (seen[cone.vertex]) {
      throw InputError("cone vertex " + std::to_string(cone.vertex) + " is listed twice");
    }
    seen[cone.vertex] = 1;
    if (target.fixed[cone.vertex]) {
      throw InputError("cone vertex " + std::to_string(cone.vertex) +
                       " is on the boundary, whose scale is fixed");
    }
    target.curvature[cone.vertex] = cone.curvature;
  }
  return target;
}

void checkGaussBonnet(const TriMesh& mesh, const CurvatureTarget& target,
                      double relativeTolerance) {
  MSPLINE_ASSERT(target.curvature.size() == static_cast<Eigen::Index>(mesh.n_vertices()) &&
                     target.fixed.size() == mesh.n_vertices(),
                 "one target per vertex");
  for (char f : target.fixed)
    if (f) return;
  const double expected = 2.0 * kPi * static_cast<double>(analyzeTopology(mesh).euler);
  const double sum = target.curvature.sum();
  const double scale = std::max(2.0 * kPi, target.curvature.cwiseAbs().sum());
  if (!(std::abs(sum - expected) <= relativeTolerance * scale)) {
    std::ostringstream msg;
    msg.precision(17);
    msg << "target curvatures sum to " << sum
        << " but Gauss-Bonnet requires 2 pi chi = " << expected
        << " (chi = " << analyzeTopology(mesh).euler << ")";
    throw InputError(msg.str());
  }
}

}  // namespace mspline::structure
