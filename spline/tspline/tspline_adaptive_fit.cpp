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
  // The samples: the given ones, then the stray surface points the measurement adds.
  std::vector<FacePoint> current;
  current.reserve(parameters.size());
  for (const auto& p : parameters) current.push_back({p.face, p.position});
  Eigen::MatrixX3d samples = targets;
  SurfaceFitOptions fitOptions = options.fit;
  fitOptions.faceFairing = Eigen::VectorXd::Ones(mesh.numFaces());
  const Eigen::VectorXd unitWeights;
  int previousFolds = std::numeric_limits<int>::max();
  // The best round so far (see the header).
  struct Kept {
    TMesh mesh;
    SurfaceFitResult fit;
    std::vector<FacePoint> parameters;
    bool reachedTolerance = false, within = false;
    int folds = 0, round = -1;
  } kept;
  for (int round = 0;; ++round) {
    const auto start = std::chrono::steady_clock::now();
    const TSplineSpace space(result.mesh);
    const TSplineFitSpace fitSpace(space, unitWeights);
    const auto roundProgress = [&](const std::string& stage, double fraction) {
      if (progress) progress("round " + std::to_string(round + 1) + ": " + stage, fraction);
    };
    result.fit = fitSurface(fitSpace, current, samples, fitOptions, roundProgress);
    // The smoothing weight is relative to typical functions (surface_fit.h), so the one chosen
    // on the first round holds for the refined ones.
    fitOptions.smoothing = result.fit.smoothing;
    current = result.fit.parameters;
    TSplineFitRound summary;
    summary.controlPoints = space.numBasis();
    summary.faces = result.mesh.numFaces();
    summary.rmsError = result.fit.rmsError;
    summary.maxError = result.fit.maxError;
    TSplineSurfaceCheck check;
    if (options.measure) {
      roundProgress("measuring the surface", 1.0);
      check = options.measure(result.mesh, result.fit);
    }
    const bool samplesWithin = result.fit.rmsError <= options.tolerance &&
                               result.fit.maxError <= options.maxErrorFactor * options.tolerance;
    result.reachedTolerance = samplesWithin && check.accepted;
    summary.folds = check.foldCount;
    const bool within = samplesWithin && check.distancesWithin;
    if (!kept.within || (within && check.foldCount <= kept.folds))
      kept = {result.mesh, result.fit, current, result.reachedTolerance, within, check.foldCount,
              round};
    const auto finish = [&] {
      summary.seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      result.rounds.push_back(summary);
    };
    if (result.reachedTolerance || round >= options.maxRefinements) {
      finish();
      break;
    }
    // The worst distance per face, of the samples and of the stray surface points; faces beyond
    // the tolerance are split, worst first, as far as the budget goes (a split adds about five
    // vertices: one inside, four on sides).
    std::vector<double> faceError(std::size_t(result.mesh.numFaces()), 0.0);
    const auto count = [&](const FacePoint& p, double d) {
      if (std::isfinite(d))
        faceError[std::size_t(p.face)] = std::max(faceError[std::size_t(p.face)], d);
    };
    for (std::size_t s = 0; s < current.size(); ++s)
      count(current[s], result.fit.distances[Eigen::Index(s)] *
                            (fitOptions.sampleWeights.size() > 0
                                 ? std::sqrt(fitOptions.sampleWeights[Eigen::Index(s)])
                                 : 1.0));
    for (std::size_t k = 0; k < check.strays.size(); ++k)
      count(check.strays[k],
            (evaluateFitSurface(fitSpace, result.fit.controlPoints, check.strays[k]) -
             check.strayTargets.row(Eigen::Index(k)).transpose())
                .norm());
    // Folds: a stiffer fairing where they are, and no split there.
    std::vector<char> folded(faceError.size(), 0);
    for (const auto& p : check.folds) folded[std::size_t(p.face)] = 1;
    const int folds = int(check.folds.size());
    for (std::size_t f = 0; f < folded.size(); ++f)
      if (folded[f])
        fitOptions.faceFairing[Eigen::Index(f)] = std::min(
            fitOptions.faceFairing[Eigen::Index(f)] * options.foldFairing, options.maxFoldFairing);
    summary.stiffenedFaces = int(std::count(folded.begin(), folded.end(), 1));
    // Beyond the maximum wanted, or (when only the RMS is off) beyond the tolerance; when only
    // the measurement is off, only the faces of its stray points, not every face holding a
    // sample above the tolerance.
    const double maxError = *std::max_element(faceError.begin(), faceError.end());
    const double threshold =
        maxError > options.maxErrorFactor * options.tolerance
            ? std::max(options.tolerance,
                       std::min(0.5 * options.maxErrorFactor * options.tolerance, 0.5 * maxError))
        : !samplesWithin          ? options.tolerance
        : options.measure ? std::max(options.tolerance, check.strayDistance)
                          : 0.5 * options.maxErrorFactor * options.tolerance;
    std::vector<int> order(faceError.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return faceError[std::size_t(a)] > faceError[std::size_t(b)]; });
    const std::size_t budget =
        std::size_t(std::max(0, (options.maxControlPoints - space.numBasis()) / 5));
    std::vector<int> candidates;
    for (const int f : order) {
      if (faceError[std::size_t(f)] <= threshold) break;
      if (!folded[std::size_t(f)]) candidates.push_back(f);
    }
    // Cap regions at cones are split whole or not at all (no T-junction may enter them): the
    // longest run of candidates, worst first, whose faces with their whole regions fit the budget.
    const auto withinBudget = [&] {
      const auto closure = [&](std::size_t length) {
        return withWholeCapRegions(result.mesh, {candidates.begin(), candidates.begin() + length});
      };
      std::size_t fitting = 0, over = candidates.size() + 1;
      while (over - fitting > 1) {
        const std::size_t middle = (fitting + over) / 2;
        (closure(middle).size() <= budget ? fitting : over) = middle;
      }
      return closure(fitting);
    };
    std::vector<int> marked = withinBudget();
    // The stray points join the samples (unit weight: they are points of the scan).
    const auto strays = Eigen::Index(check.strays.size());
    summary.addedSamples = int(strays);
    if (strays > 0) {
      const Eigen::Index old = samples.rows();
      samples.conservativeResize(old + strays, 3);
      samples.bottomRows(strays) = check.strayTargets;
      current.insert(current.end(), check.strays.begin(), check.strays.end());
      if (fitOptions.sampleWeights.size() > 0) {
        fitOptions.sampleWeights.conservativeResize(samples.rows());
        fitOptions.sampleWeights.tail(samples.rows() - old).setOnes();
      }
    }
    // Another round when it has something to act on: refined faces, new samples, or folds that
    // the last stiffening reduced.
    const bool unfolding = summary.stiffenedFaces > 0 && folds < previousFolds;
    previousFolds = folds;
    // Nothing of that, but folds on a surface within the tolerance: the faces where they are are
    // split (cap regions whole), a last resort that costs nothing but time, since a round that
    // folds more is not the one kept.
    if (marked.empty() && strays == 0 && !unfolding && within && check.foldCount > 0) {
      candidates.clear();
      for (const auto& p : check.folds) candidates.push_back(p.face);
      for (const auto& p : check.facingAway) candidates.push_back(p.face);
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      marked = withinBudget();
      summary.foldSplits = !marked.empty();
    }
    summary.splitFaces = int(marked.size());
    finish();
    if (marked.empty() && summary.addedSamples == 0 && !unfolding) break;
    for (const int f : marked) {
      const Eigen::Index first = result.mesh.numFaces();
      splitIntoFour(result.mesh, f, current);
      // The new parts keep the face's fairing factor.
      fitOptions.faceFairing.conservativeResize(result.mesh.numFaces());
      fitOptions.faceFairing.tail(result.mesh.numFaces() - first)
          .setConstant(fitOptions.faceFairing[f]);
    }
  }
  result.keptRound = kept.round;
  result.mesh = std::move(kept.mesh);
  result.fit = std::move(kept.fit);
  result.reachedTolerance = kept.reachedTolerance;
  result.parameters.assign(kept.parameters.begin(),
                           kept.parameters.begin() + std::ptrdiff_t(parameters.size()));
  return result;
}

}  // namespace mspline::spline
