#include "mspline/spline/tspline/tspline_adaptive_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_fit_space.h"
#include "mspline/spline/tspline/tspline_refine.h"

namespace mspline::spline {

TSplineAdaptiveFitResult fitTSplineAdaptively(const TMesh& mesh,
                                              const std::vector<FacePoint>& parameters,
                                              const Eigen::MatrixX3d& targets,
                                              const TSplineAdaptiveFitOptions& options,
                                              const FitProgress& progress) {
  TSplineAdaptiveFitResult result;
  result.mesh = mesh;
  std::vector<FacePoint> current;
  current.reserve(parameters.size());
  for (const auto& p : parameters) current.push_back({p.face, p.position});
  const Eigen::VectorXd unitWeights;
  for (int round = 0;; ++round) {
    const auto start = std::chrono::steady_clock::now();
    const TSplineSpace space(result.mesh);
    const TSplineFitSpace fitSpace(space, unitWeights);
    const auto roundProgress = [&](const std::string& stage, double fraction) {
      if (progress) progress("round " + std::to_string(round + 1) + ": " + stage, fraction);
    };
    result.fit = fitSurface(fitSpace, current, targets, options.fit, roundProgress);
    current = result.fit.parameters;
    TSplineFitRound summary;
    summary.controlPoints = space.numBasis();
    summary.faces = result.mesh.numFaces();
    summary.rmsError = result.fit.rmsError;
    summary.maxError = result.fit.maxError;
    result.reachedTolerance = result.fit.rmsError <= options.tolerance &&
                              result.fit.maxError <= options.maxErrorFactor * options.tolerance;
    const auto finish = [&] {
      summary.seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      result.rounds.push_back(summary);
    };
    if (result.reachedTolerance || round >= options.maxRefinements) {
      finish();
      break;
    }
    // The worst sample distance per face; faces beyond the tolerance are split, worst first,
    // as far as the budget goes (a split adds about five vertices: one inside, four on sides).
    std::vector<double> faceError(std::size_t(result.mesh.numFaces()), 0.0);
    for (std::size_t s = 0; s < current.size(); ++s) {
      const double d = result.fit.distances[Eigen::Index(s)] *
                       (options.fit.sampleWeights.size() > 0
                            ? std::sqrt(options.fit.sampleWeights[Eigen::Index(s)])
                            : 1.0);
      if (std::isfinite(d))
        faceError[std::size_t(current[s].face)] =
            std::max(faceError[std::size_t(current[s].face)], d);
    }
    // Beyond the maximum wanted, or (when only the RMS is off) beyond the tolerance.
    const double threshold =
        result.fit.maxError > options.maxErrorFactor * options.tolerance
            ? std::max(options.tolerance, std::min(0.5 * options.maxErrorFactor * options.tolerance,
                                                   0.5 * result.fit.maxError))
            : options.tolerance;
    std::vector<int> order(faceError.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return faceError[std::size_t(a)] > faceError[std::size_t(b)]; });
    const int budget = (options.maxControlPoints - space.numBasis()) / 5;
    std::vector<int> marked;
    for (const int f : order) {
      if (faceError[std::size_t(f)] <= threshold || int(marked.size()) >= budget) break;
      marked.push_back(f);
    }
    // Cap regions at cones are split whole or not at all (no T-junction may enter them).
    marked = withWholeCapRegions(result.mesh, marked);
    summary.splitFaces = int(marked.size());
    finish();
    if (marked.empty()) break;
    for (const int f : marked) splitIntoFour(result.mesh, f, current);
  }
  result.parameters.clear();
  for (const auto& p : current) result.parameters.push_back({p.face, p.position});
  return result;
}

}  // namespace mspline::spline
