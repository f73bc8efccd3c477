#include "mspline/spline/fitting/surface_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>
#include <Eigen/Dense>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/sparse_cholesky.h"

namespace mspline::spline {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Weight of the pull towards the quasi-interpolant, relative to the mean diagonal of D^T W D.
constexpr double kGuessPull = 1e-7;
// Held-out RMS errors within this fraction of the least, and of the errors' range above it, are
// taken as equal when the smoothing is chosen.
constexpr double kHoldOutTolerance = 0.05;
constexpr double kHoldOutRangeFraction = 0.1;

// The surface and its derivatives from the basis terms.
struct SurfaceJet {
  Eigen::Vector3d position, ds, dt, dss, dst, dtt;
};

SurfaceJet jetOf(const std::vector<FitBasisTerm>& terms, const Eigen::MatrixXd& control) {
  SurfaceJet jet{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                 Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (const auto& term : terms) {
    const Eigen::Vector3d c = control.row(term.index).transpose();
    jet.position += term.value * c;
    jet.ds += term.ds * c;
    jet.dt += term.dt * c;
    jet.dss += term.dss * c;
    jet.dst += term.dst * c;
    jet.dtt += term.dtt * c;
  }
  return jet;
}

// The design matrix of the samples whose surface is defined (rows in the order of `rows`).
Eigen::SparseMatrix<double> designMatrix(const FitSpace& space,
                                         const std::vector<FacePoint>& parameters,
                                         std::vector<Eigen::Index>& rows) {
  const std::size_t count = parameters.size();
  std::vector<std::vector<FitBasisTerm>> terms(count);
  tbb::parallel_for(std::size_t(0), count,
                    [&](std::size_t s) { space.basisAt(parameters[s], terms[s], 0); });
  rows.clear();
  std::vector<Eigen::Triplet<double>> entries;
  for (std::size_t s = 0; s < count; ++s) {
    if (terms[s].empty()) continue;
    for (const auto& term : terms[s])
      entries.emplace_back(Eigen::Index(rows.size()), term.index, term.value);
    rows.push_back(Eigen::Index(s));
  }
  Eigen::SparseMatrix<double> design(Eigen::Index(rows.size()), space.numBasis());
  design.setFromTriplets(entries.begin(), entries.end());
  return design;
}

Eigen::SparseMatrix<double> scaledIdentity(Eigen::Index size, double value) {
  Eigen::SparseMatrix<double> identity(size, size);
  identity.setIdentity();
  return value * identity;
}

// n times the median diagonal entry of the energy: its trace as if every function were typical.
// The plain trace is dominated by the few functions whose second derivatives blow up (a T-spline's
// normalization next to a cone's hole, tiny refined faces): on bunny00 1% of the faces carried 83%
// of it before refinement and 99% after, which divided the fairing everywhere else by 6 and 400.
double typicalEnergyTrace(const Eigen::SparseMatrix<double>& energy) {
  Eigen::VectorXd diagonal = energy.diagonal();
  if (diagonal.size() == 0) return 1e-300;
  const auto middle = diagonal.data() + diagonal.size() / 2;
  std::nth_element(diagonal.data(), middle, diagonal.data() + diagonal.size());
  return std::max(*middle * double(diagonal.size()), 1e-300);
}

// Control points solving (normal + lambda K + guard) C = rhs with a factorization whose
// symbolic analysis `cholesky` holds (analyzed on the same pattern).
Eigen::MatrixXd solveNormal(structure::SparseCholesky& cholesky,
                            const Eigen::SparseMatrix<double>& system, const Eigen::MatrixXd& rhs) {
  cholesky.factorize(system);
  Eigen::MatrixXd solution(rhs.rows(), rhs.cols());
  for (Eigen::Index c = 0; c < rhs.cols(); ++c) solution.col(c) = cholesky.solve(rhs.col(c));
  return solution;
}

struct Solve {
  Eigen::MatrixXd control;
  double smoothing = 0.0, lambda = 0.0;
  int basisWithoutSamples = 0;
};

// One least-squares solve at the given parameters; chooses the smoothing on the first call when
// asked to (smoothing < 0).
Solve solveAt(const FitSpace& space, const std::vector<FacePoint>& parameters,
              const Eigen::MatrixX3d& targets, const Eigen::VectorXd& weights,
              const Eigen::SparseMatrix<double>& energy, double smoothing,
              std::vector<Eigen::Index>& rows) {
  Eigen::SparseMatrix<double> design = designMatrix(space, parameters, rows);
  if (rows.empty())
    throw structure::SolverError("fit: the surface is undefined at every sample's parameters");
  // Weighted least squares: rows and targets scaled by the square roots of the weights.
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(Eigen::Index(rows.size()));
  if (weights.size() > 0)
    for (std::size_t k = 0; k < rows.size(); ++k)
      scale[Eigen::Index(k)] = std::sqrt(weights[rows[k]]);
  design = scale.asDiagonal() * design;
  Eigen::MatrixXd used(Eigen::Index(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k)
    used.row(Eigen::Index(k)) = scale[Eigen::Index(k)] * targets.row(rows[k]);
  const Eigen::Index n = space.numBasis();
  const double energyTrace = typicalEnergyTrace(energy);

  // A light pull towards the quasi-interpolant (each control point the mean of the samples under
  // its function, weighted by it; the samples' mean where none is) for functions that neither
  // the samples nor the energy determine, such as those seen only very near a cone.
  const Eigen::VectorXd under = design.transpose() * scale;
  Eigen::MatrixXd guess = design.transpose() * (scale.asDiagonal() * used);
  const Eigen::RowVector3d mean =
      (scale.asDiagonal() * used).colwise().sum() / std::max(scale.squaredNorm(), 1e-300);
  for (Eigen::Index k = 0; k < n; ++k)
    guess.row(k) = under[k] > 0.0 ? Eigen::RowVector3d(guess.row(k) / under[k]) : mean;
  Solve solve;
  solve.basisWithoutSamples = int((under.array() <= 0.0).count());
  double pull = 0.0;
  const auto system = [&](const Eigen::SparseMatrix<double>& normal, double relative,
                          double& lambda) {
    const double dataTrace = normal.diagonal().sum();
    lambda = relative * dataTrace / energyTrace;
    pull = kGuessPull * dataTrace / double(n);
    Eigen::SparseMatrix<double> matrix = normal + lambda * energy;
    matrix += scaledIdentity(n, pull);
    return matrix;
  };

  solve.smoothing = smoothing;
  if (smoothing < 0.0) {
    // Hold-out validation: every eighth sample is left out of the fit and predicts.
    std::vector<Eigen::Index> trainRows, testRows;
    for (Eigen::Index r = 0; r < design.rows(); ++r) {
      auto& list = r % 8 == 7 ? testRows : trainRows;
      list.push_back(r);
    }
    Eigen::SparseMatrix<double, Eigen::RowMajor> byRow = design;
    const auto take = [&](const std::vector<Eigen::Index>& which, Eigen::MatrixXd& values) {
      std::vector<Eigen::Triplet<double>> entries;
      values.resize(Eigen::Index(which.size()), 3);
      for (std::size_t k = 0; k < which.size(); ++k) {
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(byRow, which[k]); it;
             ++it)
          entries.emplace_back(Eigen::Index(k), it.col(), it.value());
        values.row(Eigen::Index(k)) = used.row(which[k]);
      }
      Eigen::SparseMatrix<double> matrix(Eigen::Index(which.size()), n);
      matrix.setFromTriplets(entries.begin(), entries.end());
      return matrix;
    };
    Eigen::MatrixXd trainTargets, testTargets;
    const Eigen::SparseMatrix<double> train = take(trainRows, trainTargets);
    const Eigen::SparseMatrix<double> test = take(testRows, testTargets);
    const Eigen::SparseMatrix<double> trainNormal = train.transpose() * train;
    const Eigen::MatrixXd trainRhs = train.transpose() * trainTargets;
    structure::SparseCholesky cholesky;
    double lambda = 0.0;
    cholesky.analyze(system(trainNormal, 1.0, lambda));
    // The most smoothing whose held-out error is as good as the least: within 5 % of it, and
    // within a tenth of the errors' range above it (so that a clear minimum is kept). Where the
    // errors level off (data a spline reproduces, such as a box's faces), a weight near
    // interpolation predicts no better, and the parameter correction after it unsettles it (beam:
    // 1e-7 held out 2 % better than 1e-3, and its corrected fit folded 19,958 times, 1e-3 none).
    const std::array<double, 7> candidates = {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7};
    std::vector<double> errors;
    for (const double candidate : candidates) {
      const Eigen::MatrixXd control =
          solveNormal(cholesky, system(trainNormal, candidate, lambda), trainRhs + pull * guess);
      errors.push_back((test * control - testTargets).norm());
    }
    const auto [least, most] = std::minmax_element(errors.begin(), errors.end());
    const double bound =
        *least + std::min(kHoldOutTolerance * *least, kHoldOutRangeFraction * (*most - *least));
    const auto chosen =
        std::find_if(errors.begin(), errors.end(), [&](double error) { return error <= bound; });
    solve.smoothing = candidates[std::size_t(chosen - errors.begin())];
  }
  const Eigen::SparseMatrix<double> normal = design.transpose() * design;
  const Eigen::SparseMatrix<double> matrix = system(normal, solve.smoothing, solve.lambda);
  structure::SparseCholesky cholesky;
  cholesky.analyze(matrix);
  solve.control = solveNormal(cholesky, matrix, design.transpose() * used + pull * guess);
  return solve;
}

// Projects every sample; returns the distances (NaN where the surface is undefined).
Eigen::VectorXd projectAll(const FitSpace& space, const Eigen::MatrixXd& control,
                           std::vector<FacePoint>& parameters, const Eigen::MatrixX3d& targets,
                           int steps) {
  Eigen::VectorXd distances(Eigen::Index(parameters.size()));
  tbb::parallel_for(std::size_t(0), parameters.size(), [&](std::size_t s) {
    const SurfaceProjection projection = projectOntoSurface(
        space, control, parameters[s], targets.row(Eigen::Index(s)).transpose(), steps);
    parameters[s] = projection.parameter;
    distances[Eigen::Index(s)] = projection.distance;
  });
  return distances;
}

// Weighted: rms = sqrt(sum w d^2 / sum w), max = max sqrt(w) d, over the finite distances.
void summarize(const Eigen::VectorXd& distances, const Eigen::VectorXd& weights, double& rms,
               double& max, int& undefined) {
  double squares = 0.0, total = 0.0;
  max = 0.0;
  undefined = 0;
  for (Eigen::Index k = 0; k < distances.size(); ++k) {
    const double d = distances[k];
    if (std::isnan(d)) {
      ++undefined;
      continue;
    }
    const double w = weights.size() > 0 ? weights[k] : 1.0;
    squares += w * d * d;
    total += w;
    max = std::max(max, std::sqrt(w) * d);
  }
  rms = total > 0.0 ? std::sqrt(squares / total) : 0.0;
}

}  // namespace

Eigen::SparseMatrix<double> thinPlateEnergy(const FitSpace& space,
                                            const Eigen::VectorXd& faceFactors) {
  std::vector<FacePoint> nodes;
  std::vector<double> weights;
  space.quadrature(nodes, weights);
  const Eigen::Index n = space.numBasis();
  for (const auto& node : nodes)
    if (faceFactors.size() > 0 && (node.face < 0 || node.face >= faceFactors.size()))
      throw structure::InputError("fit: " + std::to_string(faceFactors.size()) +
                                  " fairing factors for a domain with face " +
                                  std::to_string(node.face));
  // Consecutive nodes with the same functions (one face) are summed into a dense block first.
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<FitBasisTerm> terms;
  std::vector<int> blockIndices;
  Eigen::MatrixXd block;
  const auto flush = [&] {
    for (std::size_t i = 0; i < blockIndices.size(); ++i)
      for (std::size_t j = 0; j < blockIndices.size(); ++j)
        if (block(Eigen::Index(i), Eigen::Index(j)) != 0.0)
          entries.emplace_back(blockIndices[i], blockIndices[j],
                               block(Eigen::Index(i), Eigen::Index(j)));
    blockIndices.clear();
  };
  for (std::size_t q = 0; q < nodes.size(); ++q) {
    space.basisAt(nodes[q], terms, 2);
    if (terms.empty()) continue;
    bool same = terms.size() == blockIndices.size();
    for (std::size_t k = 0; same && k < terms.size(); ++k) same = terms[k].index == blockIndices[k];
    if (!same) {
      flush();
      for (const auto& term : terms) blockIndices.push_back(term.index);
      block.setZero(Eigen::Index(terms.size()), Eigen::Index(terms.size()));
    }
    Eigen::VectorXd ss(Eigen::Index(terms.size())), st(ss.size()), tt(ss.size());
    for (std::size_t k = 0; k < terms.size(); ++k) {
      ss[Eigen::Index(k)] = terms[k].dss;
      st[Eigen::Index(k)] = terms[k].dst;
      tt[Eigen::Index(k)] = terms[k].dtt;
    }
    const double factor = faceFactors.size() > 0 ? faceFactors[nodes[q].face] : 1.0;
    block.noalias() += factor * weights[q] *
                       (ss * ss.transpose() + 2.0 * st * st.transpose() + tt * tt.transpose());
  }
  flush();
  Eigen::SparseMatrix<double> energy(n, n);
  energy.setFromTriplets(entries.begin(), entries.end());
  return energy;
}

Eigen::Vector3d evaluateFitSurface(const FitSpace& space, const Eigen::MatrixXd& control,
                                   const FacePoint& p) {
  std::vector<FitBasisTerm> terms;
  space.basisAt(p, terms, 0);
  if (terms.empty()) return Eigen::Vector3d::Constant(kNaN);
  return jetOf(terms, control).position;
}

bool evaluateFitTangents(const FitSpace& space, const Eigen::MatrixXd& control, const FacePoint& p,
                         std::vector<FitBasisTerm>& terms, Eigen::Vector3d& ds,
                         Eigen::Vector3d& dt) {
  space.basisAt(p, terms, 1);
  const SurfaceJet jet = jetOf(terms, control);
  ds = jet.ds;
  dt = jet.dt;
  return !terms.empty() && ds.allFinite() && dt.allFinite();
}

SurfaceProjection projectOntoSurface(const FitSpace& space, const Eigen::MatrixXd& control,
                                     const FacePoint& start, const Eigen::Vector3d& target,
                                     int steps) {
  std::vector<FitBasisTerm> terms;
  SurfaceProjection current{start, kNaN};
  space.basisAt(start, terms, 2);
  if (terms.empty()) return current;
  SurfaceJet jet = jetOf(terms, control);
  current.distance = (jet.position - target).norm();
  for (int step = 0; step < steps; ++step) {
    const Eigen::Vector3d residual = jet.position - target;
    Eigen::Matrix<double, 3, 2> jacobian;
    jacobian << jet.ds, jet.dt;
    const Eigen::Vector2d gradient = jacobian.transpose() * residual;
    const Eigen::Matrix2d gaussNewton = jacobian.transpose() * jacobian;
    Eigen::Matrix2d hessian = gaussNewton;
    hessian(0, 0) += residual.dot(jet.dss);
    hessian(0, 1) += residual.dot(jet.dst);
    hessian(1, 0) += residual.dot(jet.dst);
    hessian(1, 1) += residual.dot(jet.dtt);
    Eigen::LLT<Eigen::Matrix2d> llt(hessian);
    if (llt.info() != Eigen::Success || hessian.determinant() <= 0.0)
      llt.compute(gaussNewton + 1e-12 * gaussNewton.trace() * Eigen::Matrix2d::Identity());
    if (llt.info() != Eigen::Success) break;
    Eigen::Vector2d move = -llt.solve(gradient);
    // A step much longer than the distance to the target is not to be trusted, neither in space
    // nor in the parameters.
    const double limit = 2.0 * current.distance + 1e-300;
    const double reach = (jacobian * move).norm();
    if (reach > limit) move *= limit / reach;
    const double longest = space.faceSize(current.parameter.face);
    if (move.norm() > longest) move *= longest / move.norm();
    if (!(move.allFinite()) || move.norm() == 0.0) break;
    bool improved = false;
    for (int halving = 0; halving < 6 && !improved; ++halving, move *= 0.5) {
      const FacePoint trial = space.walk(current.parameter, move);
      space.basisAt(trial, terms, 2);
      if (terms.empty()) continue;
      const SurfaceJet trialJet = jetOf(terms, control);
      const double distance = (trialJet.position - target).norm();
      if (distance < current.distance) {
        improved = true;
        const double gain = current.distance - distance;
        current = {trial, distance};
        jet = trialJet;
        // A gain at the rounding of the positions (relative to their magnitude, any unit).
        if (gain <= 1e-13 * (target.norm() + distance)) return current;
      }
    }
    if (!improved) break;
  }
  return current;
}

SurfaceFitResult fitSurface(const FitSpace& space, const std::vector<FacePoint>& parameters,
                            const Eigen::MatrixX3d& targets, const SurfaceFitOptions& options,
                            const FitProgress& progress) {
  if (parameters.empty() || Eigen::Index(parameters.size()) != targets.rows())
    throw structure::InputError("fit: " + std::to_string(parameters.size()) + " parameters for " +
                                std::to_string(targets.rows()) + " samples");
  if (options.sampleWeights.size() != 0 && (options.sampleWeights.size() != targets.rows() ||
                                            !(options.sampleWeights.array() >= 0.0).all()))
    throw structure::InputError(
        "fit: the sample weights must be one non-negative number per sample");
  const auto report = [&](const std::string& stage, double fraction) {
    if (progress) progress(stage, fraction);
  };
  const int rounds = std::max(0, options.correctionRounds);
  const double total = 2.0 * rounds + 2.0;
  report("fairing energy", 0.0);
  const Eigen::SparseMatrix<double> energy = thinPlateEnergy(space, options.faceFairing);
  SurfaceFitResult result;
  result.parameters = parameters;
  std::vector<Eigen::Index> rows;
  report("least squares", 0.5 / total);
  Solve solve = solveAt(space, result.parameters, targets, options.sampleWeights, energy,
                        options.smoothing, rows);
  {
    Eigen::VectorXd initial = Eigen::VectorXd::Constant(targets.rows(), kNaN);
    for (const Eigen::Index r : rows)
      initial[r] = (evaluateFitSurface(space, solve.control, result.parameters[std::size_t(r)]) -
                    targets.row(r).transpose())
                       .norm();
    double max = 0.0;
    int undefined = 0;
    summarize(initial, options.sampleWeights, result.initialRmsError, max, undefined);
  }
  for (int round = 0; round < rounds; ++round) {
    report("parameter correction", (2.0 * round + 1.0) / total);
    projectAll(space, solve.control, result.parameters, targets, options.projectionSteps);
    report("least squares", (2.0 * round + 2.0) / total);
    // The weight chosen on the first solve holds: parameter correction moves the samples by a
    // fraction of a face, which does not change what the data can determine (and each choice
    // costs seven factorizations).
    solve = solveAt(space, result.parameters, targets, options.sampleWeights, energy,
                    solve.smoothing, rows);
    result.rounds = round + 1;
  }
  report("projection", (total - 1.0) / total);
  result.distances =
      projectAll(space, solve.control, result.parameters, targets, options.projectionSteps);
  summarize(result.distances, options.sampleWeights, result.rmsError, result.maxError,
            result.samplesOutside);
  result.controlPoints = std::move(solve.control);
  result.smoothing = solve.smoothing;
  result.lambda = solve.lambda;
  result.basisWithoutSamples = solve.basisWithoutSamples;
  report("done", 1.0);
  return result;
}

}  // namespace mspline::spline
