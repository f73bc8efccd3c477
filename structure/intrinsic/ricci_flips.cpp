#include "mspline/structure/intrinsic/ricci_flips.h"

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

std::vector<int> degenerateIntrinsicFaces(const IntrinsicTriangulation& tri,
                                          const Eigen::VectorXd& u) {
  const Eigen::VectorXd l = tri.lengths(u);
  std::vector<int> faces;
  for (int f = 0; f < tri.faceCount(); ++f) {
    if (!satisfiesTriangleInequality(l[tri.edge(3 * f)], l[tri.edge(3 * f + 1)],
                                     l[tri.edge(3 * f + 2)]))
      faces.push_back(f);
  }
  return faces;
}

}  // namespace

RicciFlipsResult solveVertexScalingWithFlips(const TriMesh& mesh, const CurvatureTarget& target,
                                             const RicciNewtonOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const IndexMap unknowns = ricciUnknowns(mesh, target);

  RicciFlipsResult out;
  RicciResult& result = out.ricci;
  result.u = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  const double tolerance = options.tolerance * 2.0 * kPi;
  const auto finish = [&](RicciStatus status, const std::string& message) {
    result.status = status;
    result.message = message;
    result.edgeLengths = out.triangulation.lengths(result.u);
    result.degenerateFaces = degenerateIntrinsicFaces(out.triangulation, result.u);
    // Boundary edges cannot flip: a triangle on one may stay degenerate, and the critical point
    // of the extended energy is then no metric (flatten doubles such surfaces instead).
    if (status == RicciStatus::Converged && !result.degenerateFaces.empty()) {
      result.status = RicciStatus::DegenerateTriangles;
      result.message += ", but " + std::to_string(result.degenerateFaces.size()) +
                        " triangles violate the triangle inequality";
    }
    result.converged = result.status == RicciStatus::Converged;
    out.faces = out.triangulation.faces();
    out.flips = out.triangulation.flipCount();
    out.inputEdgesFlipped = 0;
    for (int e = 0; e < out.triangulation.edgeCount(); ++e)
      out.inputEdgesFlipped += !out.triangulation.isInputEdge(e);
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  };

  const Eigen::VectorXd inputLengths = edgeLengths(mesh);
  if (inputLengths.minCoeff() <= 0.0) {
    out.triangulation = IntrinsicTriangulation();
    result.edgeLengths = inputLengths;
    result.status = RicciStatus::DegenerateTriangles;
    result.message = "the input has an edge of length 0; Ptolemy flips need positive lengths";
    for (const auto f : mesh.faces())
      for (const auto e : mesh.fe_range(f))
        if (inputLengths[e.idx()] <= 0.0) {
          result.degenerateFaces.push_back(f.idx());
          break;
        }
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }
  out.triangulation = IntrinsicTriangulation(mesh, inputLengths);
  out.trialFlips += out.triangulation.flipToDelaunay(result.u);

  const auto step = [&](const Eigen::VectorXd& u, const Eigen::VectorXd& direction, double t) {
    Eigen::VectorXd next = u;
    unknowns.scatter(unknowns.gather(u) + t * direction, next);
    return next;
  };

  SparseCholesky solver;
  // The Hessian's pattern is the connectivity's: analyze again after flips.
  long analyzedAtFlips = -1;
  double magnitude = 0.0;
  double energy = intrinsicEnergy(out.triangulation, result.u, target.curvature, &magnitude);
  Eigen::VectorXd gradient = intrinsicGradient(out.triangulation, result.u, target.curvature);
  for (int iteration = 0;; ++iteration) {
    result.iterations = iteration;
    result.maxCurvatureError = maxAbsOnUnknowns(gradient, unknowns);
    result.log.push_back({energy, result.maxCurvatureError, 0.0, 0});
    std::ostringstream where;
    where << " after " << iteration << " Newton steps and " << out.triangulation.flipCount()
          << " flips (max curvature error " << result.maxCurvatureError << ")";
    if (result.maxCurvatureError <= tolerance || unknowns.size() == 0)
      return finish(RicciStatus::Converged, "converged" + where.str());
    if (iteration == options.maxIterations)
      return finish(RicciStatus::MaxIterations, "no convergence" + where.str());

    const Eigen::SparseMatrix<double> hessian =
        intrinsicHessian(out.triangulation, result.u, unknowns);
    const Eigen::VectorXd g = unknowns.gather(gradient);
    Eigen::VectorXd direction;
    try {
      direction =
          newtonDirection(solver, hessian, g, analyzedAtFlips != out.triangulation.flipCount());
      analyzedAtFlips = out.triangulation.flipCount();
    } catch (const SolverError& error) {
      return finish(RicciStatus::SolverFailed, std::string(error.what()) + where.str());
    }
    const double slope = g.dot(direction);

    // Armijo backtracking; each trial is evaluated on its own Delaunay triangulation.
    double t = std::min(1.0, options.maxUStep / direction.lpNorm<Eigen::Infinity>());
    // Near the solution the decrease t*|slope| sinks below the rounding of E (a small multiple of
    // eps times the magnitude of its terms); then a step is accepted when E does not rise beyond
    // rounding and the curvature error drops.
    const double roundoff = 1e-13 * (1.0 + magnitude);
    bool accepted = false;
    int backtracks = 0;
    for (; backtracks <= options.maxBacktracks; ++backtracks, t *= 0.5) {
      const Eigen::VectorXd trial = step(result.u, direction, t);
      IntrinsicTriangulation trialTriangulation = out.triangulation;
      out.trialFlips += trialTriangulation.flipToDelaunay(trial);
      double trialMagnitude = 0.0;
      const double trialEnergy =
          intrinsicEnergy(trialTriangulation, trial, target.curvature, &trialMagnitude);
      bool ok = trialEnergy <= energy + options.armijo * t * slope;
      Eigen::VectorXd trialGradient;
      if (!ok && trialEnergy - energy <= roundoff) {
        trialGradient = intrinsicGradient(trialTriangulation, trial, target.curvature);
        ok = maxAbsOnUnknowns(trialGradient, unknowns) < result.maxCurvatureError;
      }
      if (ok) {
        result.u = trial;
        out.triangulation = std::move(trialTriangulation);
        energy = trialEnergy;
        magnitude = trialMagnitude;
        gradient = trialGradient.size()
                       ? trialGradient
                       : intrinsicGradient(out.triangulation, trial, target.curvature);
        accepted = true;
        break;
      }
    }
    if (!accepted)
      return finish(RicciStatus::LineSearchFailed,
                    "the line search found no decrease of the energy" + where.str());
    result.log.back().step = t;
    result.log.back().backtracks = backtracks;
  }
}

}  // namespace mspline::structure
