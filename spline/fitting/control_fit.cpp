#include "mspline/spline/fitting/control_fit.h"

#include <string>

#include <Eigen/SparseCore>

#include "mspline/spline/fitting/regularized_fit.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

ControlFitResult fitControlPoints(const TriBSplineSpace& space,
                                  const std::vector<DomainPoint>& sites,
                                  const Eigen::MatrixXd& targets,
                                  const ControlFitOptions& options) {
  if (sites.empty() || Eigen::Index(sites.size()) != targets.rows())
    throw structure::InputError("control point fit: " + std::to_string(sites.size()) +
                                " sites for " + std::to_string(targets.rows()) + " targets");
  const int count = space.numBasis();
  std::vector<Eigen::Triplet<double>> entries;
  BasisValues basis;
  // Sites at cone points, where the spline is undefined, are left out.
  std::vector<Eigen::Index> used;
  for (std::size_t s = 0; s < sites.size(); ++s) {
    space.basisAt(sites[s], basis);
    if (basis.index.empty()) continue;
    for (std::size_t k = 0; k < basis.index.size(); ++k)
      entries.emplace_back(int(used.size()), basis.index[k], basis.value[k]);
    used.push_back(Eigen::Index(s));
  }
  ControlFitResult result;
  result.sitesAtCones = int(sites.size() - used.size());
  Eigen::SparseMatrix<double> design(Eigen::Index(used.size()), count);
  design.setFromTriplets(entries.begin(), entries.end());
  Eigen::MatrixXd usedTargets(Eigen::Index(used.size()), targets.cols());
  for (std::size_t s = 0; s < used.size(); ++s)
    usedTargets.row(Eigen::Index(s)) = targets.row(used[s]);

  // The quasi-interpolant: each control point the basis-weighted mean of the targets.
  const Eigen::VectorXd weight = design.transpose() * Eigen::VectorXd::Ones(design.rows());
  Eigen::MatrixXd guess = design.transpose() * usedTargets;
  const int perFace = space.basisPerFace();
  const Eigen::RowVectorXd mean = usedTargets.colwise().mean();
  for (int f = 0; f < space.domain().faceCount(); ++f) {
    Eigen::RowVectorXd faceSum = Eigen::RowVectorXd::Zero(targets.cols());
    int supported = 0;
    for (int k = f * perFace; k < (f + 1) * perFace; ++k)
      if (weight[k] > 0.0) {
        guess.row(k) /= weight[k];
        faceSum += guess.row(k);
        ++supported;
      }
    for (int k = f * perFace; k < (f + 1) * perFace; ++k)
      if (!(weight[k] > 0.0)) {
        guess.row(k) = supported > 0 ? Eigen::RowVectorXd(faceSum / supported) : mean;
        ++result.basisWithoutSamples;
      }
  }

  const RegularizedFit fit =
      solveRegularizedFit(design, usedTargets, guess, options.regularization);
  result.controlPoints = fit.controlPoints;
  result.rmsError = fit.rmsError;
  result.maxError = fit.maxError;
  return result;
}

}  // namespace mspline::spline
