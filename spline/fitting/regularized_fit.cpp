#include "mspline/spline/fitting/regularized_fit.h"

#include <cmath>

#include "mspline/structure/core/sparse_cholesky.h"

namespace mspline::spline {

RegularizedFit solveRegularizedFit(const Eigen::SparseMatrix<double>& design,
                                   const Eigen::MatrixXd& targets, const Eigen::MatrixXd& guess,
                                   double regularization) {
  const Eigen::Index count = design.cols();
  Eigen::SparseMatrix<double> normal = design.transpose() * design;
  const double lambda = regularization * normal.diagonal().mean();
  Eigen::SparseMatrix<double> identity(count, count);
  identity.setIdentity();
  normal += lambda * identity;
  structure::SparseCholesky cholesky;
  cholesky.compute(normal);
  const Eigen::MatrixXd rhs = design.transpose() * targets + lambda * guess;
  RegularizedFit fit;
  fit.controlPoints.resize(count, targets.cols());
  for (Eigen::Index c = 0; c < targets.cols(); ++c)
    fit.controlPoints.col(c) = cholesky.solve(rhs.col(c));
  const Eigen::VectorXd distance = (design * fit.controlPoints - targets).rowwise().norm();
  fit.rmsError = std::sqrt(distance.squaredNorm() / double(distance.size()));
  fit.maxError = distance.maxCoeff();
  return fit;
}

}  // namespace mspline::spline
