#pragma once
// The least-squares solve shared by the control point fits (control_fit.h, tspline_fit.h): the
// samples' design matrix D (one row per sample, one column per basis function), a light pull
// towards a guess G (the quasi-interpolant), solved by sparse Cholesky:
// (D^T D + lambda I) C = D^T T + lambda G, lambda = regularization * mean of diag(D^T D).
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace mspline::spline {

struct RegularizedFit {
  /// One row per basis function, as many columns as the targets.
  Eigen::MatrixXd controlPoints;
  /// Distance between D C and the targets: root mean square and maximum over the rows.
  double rmsError = 0.0;
  double maxError = 0.0;
};

RegularizedFit solveRegularizedFit(const Eigen::SparseMatrix<double>& design,
                                   const Eigen::MatrixXd& targets, const Eigen::MatrixXd& guess,
                                   double regularization);

}  // namespace mspline::spline
