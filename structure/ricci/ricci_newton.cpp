#include "mspline/structure/ricci/ricci_newton.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/index_map.h"
#include "mspline/structure/core/sparse_cholesky.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::structure {

namespace {

double maxAbsOnUnknowns(const Eigen::VectorXd& perVertex, const IndexMap& unknowns) {
  return unknowns.size() == 0 ? 0.0 : unknowns.gather(perVertex).cwiseAbs().maxCoeff();
}

std::string describeFaces(const std::vector<int>& faces) {
  std::ostringstream out;
  out << faces.size() << " triangle" << (faces.size() == 1 ? "" : "s") << " (face";
  for (std::size_t i = 0; i < faces.size() && i < 5; ++i) out << ' ' << faces[i];
  if (faces.size() > 5) out << " ...";
  out << ')';
  return out.str();
}

}  // namespace

IndexMap ricciUnknowns(const TriMesh& mesh, const CurvatureTarget& target) {
  const auto topology = analyzeTopology(mesh);
  if (mesh.n_faces() == 0 || topology.components != 1) {
    throw TopologyError("Ricci flow needs a connected mesh with faces; this one has " +
                        std::to_string(topology.components) + " components and " +
                        std::to_string(mesh.n_faces()) + " faces");
  }
  MSPLINE_ASSERT(target.curvature.size() == static_cast<Eigen::Index>(mesh.n_vertices()) &&
                     target.fixed.size() == mesh.n_vertices(),
                 "one target per vertex");
  checkGaussBonnet(mesh, target);

  bool anyFixed = false;
  for (char f : target.fixed) anyFixed = anyFixed || f;
  std::vector<char> excluded = target.fixed;
  if (!anyFixed && !excluded.empty()) excluded[0] = 1;
  return IndexMap(mesh.n_vertices(), excluded);
}

Eigen::VectorXd newtonDirection(SparseCholesky& solver, const Eigen::SparseMatrix<double>& hessian,
                                const Eigen::VectorXd& gradient, bool reanalyze) {
  if (reanalyze) solver.analyze(hessian);
  solver.factorize(hessian);
  Eigen::VectorXd direction = -solver.solve(gradient);
  const double slope = gradient.dot(direction);
  if (!std::isfinite(slope) || slope >= 0.0)
    throw SolverError("the Newton direction is not a descent direction");
  return direction;
}

RicciResult solveVertexScaling(const TriMesh& mesh, const CurvatureTarget& target,
                               const RicciNewtonOptions& options) {
  return solveRicciFlow(mesh, vertexScalingScheme(mesh), target, options);
}

RicciResult solveRicciFlow(const TriMesh& mesh, const RicciScheme& scheme,
                           const CurvatureTarget& target, const RicciNewtonOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const IndexMap unknowns = ricciUnknowns(mesh, target);

  RicciResult result;
  result.u = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  const double tolerance = options.tolerance * 2.0 * kPi;
  const auto finish = [&](RicciStatus status, const std::string& message) {
    result.status = status;
    result.converged = status == RicciStatus::Converged;
    if (status != RicciStatus::DegenerateTriangles) result.degenerateFaces.clear();
    result.message = message;
    result.edgeLengths = scheme.lengths(result.u);
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  };

  result.degenerateFaces = degenerateFaces(mesh, scheme.lengths(result.u));
  if (!result.degenerateFaces.empty()) {
    return finish(RicciStatus::DegenerateTriangles,
                  "the input has " + describeFaces(result.degenerateFaces) +
                      " violating the strict triangle inequality");
  }

  const auto step = [&](const Eigen::VectorXd& u, const Eigen::VectorXd& direction, double t) {
    Eigen::VectorXd next = u;
    unknowns.scatter(unknowns.gather(u) + t * direction, next);
    return next;
  };

  SparseCholesky solver;
  bool analyzed = false;
  int degenerateSteps = 0;  // consecutive steps cut short by degenerating triangles
  double energy = scheme.energy(result.u, target.curvature);
  Eigen::VectorXd gradient = scheme.gradient(result.u, target.curvature);
  for (int iteration = 0;; ++iteration) {
    result.iterations = iteration;
    result.maxCurvatureError = maxAbsOnUnknowns(gradient, unknowns);
    result.log.push_back({energy, result.maxCurvatureError, 0.0, 0});
    std::ostringstream where;
    where << " after " << iteration << " Newton steps (max curvature error "
          << result.maxCurvatureError << ")";
    if (result.maxCurvatureError <= tolerance || unknowns.size() == 0)
      return finish(RicciStatus::Converged, "converged" + where.str());
    if (iteration == options.maxIterations || degenerateSteps >= options.maxDegenerateSteps) {
      if (!result.degenerateFaces.empty()) {
        // The iterates were still pressing against the triangle inequality: the solution lies
        // outside what this triangulation can represent.
        return finish(RicciStatus::DegenerateTriangles,
                      "no convergence" + where.str() + "; " + std::to_string(degenerateSteps) +
                          " line searches in a row were cut short, the last by " +
                          describeFaces(result.degenerateFaces) +
                          " degenerating; intrinsic Delaunay flips are needed");
      }
      return finish(RicciStatus::MaxIterations, "no convergence" + where.str());
    }

    const Eigen::SparseMatrix<double> hessian = scheme.hessian(result.u, unknowns);
    const Eigen::VectorXd g = unknowns.gather(gradient);
    Eigen::VectorXd direction;
    try {
      direction = newtonDirection(solver, hessian, g, !analyzed);
      analyzed = true;
    } catch (const SolverError& error) {
      return finish(RicciStatus::SolverFailed, std::string(error.what()) + where.str());
    }
    const double slope = g.dot(direction);

    // Backtracking (Armijo) line search; trial metrics with degenerate triangles are rejected
    // because this triangulation cannot represent them (no flips here).
    double t = std::min(1.0, options.maxUStep / direction.lpNorm<Eigen::Infinity>());
    // Near the solution the decrease t*|slope| sinks below the rounding of E; then a step is
    // accepted when E does not rise beyond rounding and the curvature error drops.
    const double roundoff = 1e-12 * (1.0 + std::abs(energy));
    bool accepted = false;
    int degenerateTrials = 0;
    std::vector<int> lastDegenerate;
    int backtracks = 0;
    for (; backtracks <= options.maxBacktracks; ++backtracks, t *= 0.5) {
      const Eigen::VectorXd trial = step(result.u, direction, t);
      std::vector<int> degenerate = degenerateFaces(mesh, scheme.lengths(trial));
      if (!degenerate.empty()) {
        ++degenerateTrials;
        lastDegenerate = std::move(degenerate);
        continue;
      }
      const double trialEnergy = scheme.energy(trial, target.curvature);
      bool ok = trialEnergy <= energy + options.armijo * t * slope;
      Eigen::VectorXd trialGradient;
      if (!ok && trialEnergy - energy <= roundoff) {
        trialGradient = scheme.gradient(trial, target.curvature);
        ok = maxAbsOnUnknowns(trialGradient, unknowns) < result.maxCurvatureError;
      }
      if (ok) {
        result.u = trial;
        energy = trialEnergy;
        gradient = trialGradient.size() ? trialGradient : scheme.gradient(trial, target.curvature);
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      if (degenerateTrials > 0) {
        result.degenerateFaces = lastDegenerate;
        return finish(RicciStatus::DegenerateTriangles,
                      "the line search could not keep the triangle inequality (" +
                          std::to_string(degenerateTrials) + " trials degenerated, last in " +
                          describeFaces(lastDegenerate) + ")" + where.str() +
                          "; intrinsic Delaunay flips are needed");
      }
      return finish(RicciStatus::LineSearchFailed,
                    "the line search found no decrease of the energy" + where.str());
    }
    result.log.back().step = t;
    result.log.back().backtracks = backtracks;
    // Remembered only for the diagnosis when the solve stops.
    result.degenerateFaces = lastDegenerate;
    degenerateSteps = degenerateTrials > 0 ? degenerateSteps + 1 : 0;
  }
}

}  // namespace mspline::structure
