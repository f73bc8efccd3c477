#include "mspline/spline/fitting/tspline_fit.h"

#include <string>

#include <Eigen/SparseCore>

#include "mspline/spline/fitting/regularized_fit.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

TSplineFitResult fitTSplineControlPoints(const TSplineSpace& space,
                                         const std::vector<TMeshPoint>& sites,
                                         const Eigen::MatrixXd& targets,
                                         const TSplineFitOptions& options) {
  if (sites.empty() || Eigen::Index(sites.size()) != targets.rows())
    throw structure::InputError("T-spline fit: " + std::to_string(sites.size()) + " sites for " +
                                std::to_string(targets.rows()) + " targets");
  const int count = space.numBasis();
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<TSplineBasisValue> basis;
  std::vector<Eigen::Index> used;
  for (std::size_t s = 0; s < sites.size(); ++s) {
    if (sites[s].face < 0 || sites[s].face >= space.mesh().numFaces())
      throw structure::InputError("T-spline fit: site " + std::to_string(s) + " is on no face");
    space.basisAt(sites[s].face, sites[s].position, basis);
    double sum = 0.0;
    for (const auto& b : basis) sum += b.value;
    if (!(sum > 0.0)) continue;
    // Rows of the rational basis with unit weights: the spline is linear in its control points.
    for (const auto& b : basis) entries.emplace_back(int(used.size()), b.anchor, b.value / sum);
    used.push_back(Eigen::Index(s));
  }
  TSplineFitResult result;
  result.sitesInHoles = int(sites.size() - used.size());
  if (used.empty()) throw structure::InputError("T-spline fit: every site lies in a hole");
  Eigen::SparseMatrix<double> design(Eigen::Index(used.size()), count);
  design.setFromTriplets(entries.begin(), entries.end());
  Eigen::MatrixXd usedTargets(Eigen::Index(used.size()), targets.cols());
  for (std::size_t s = 0; s < used.size(); ++s)
    usedTargets.row(Eigen::Index(s)) = targets.row(used[s]);
  const Eigen::VectorXd weight = design.transpose() * Eigen::VectorXd::Ones(design.rows());
  Eigen::MatrixXd guess = design.transpose() * usedTargets;
  const Eigen::RowVectorXd mean = usedTargets.colwise().mean();
  for (int k = 0; k < count; ++k) {
    if (weight[k] > 0.0) {
      guess.row(k) /= weight[k];
    } else {
      guess.row(k) = mean;
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
