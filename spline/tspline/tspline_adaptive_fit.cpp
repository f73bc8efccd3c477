#include "mspline/spline/tspline/tspline_adaptive_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_fit_space.h"
#include "mspline/spline/tspline/tspline_refine.h"

namespace mspline::spline {
namespace {

// The fit space keeps a reference to its weights: unit weights, for the whole fit.
const Eigen::VectorXd unitWeights;

// What a fit starts from (T-mesh, samples, options) and what it gave.
struct FitState {
  TMesh mesh;
  /// The samples' parameters and positions: the given ones, then the stray surface points the
  /// measurement added.
  std::vector<FacePoint> at;
  Eigen::MatrixX3d samples;
  SurfaceFitOptions fitOptions;
  SurfaceFitResult fit;
  TSplineSurfaceCheck check;
  bool samplesWithin = false;
  int round = -1;

  bool within() const { return samplesWithin && check.distancesWithin; }
  bool reachedTolerance() const { return samplesWithin && check.accepted; }
  /// How far the fit is from the tolerance: the larger of its RMS distance over the tolerance and
  /// its maximum over the maximum wanted, of the samples and of the measurement (1 or less when
  /// within).
  double excess(const TSplineAdaptiveFitOptions& options) const {
    return std::max(
        std::max(fit.rmsError, check.rms) / options.tolerance,
        std::max(fit.maxError, check.max) / (options.maxErrorFactor * options.tolerance));
  }
};

// Fits `state` and measures its surface; the round's summary (but for what follows the fit).
TSplineFitRound fitAndMeasure(FitState& state, int round, const TSplineAdaptiveFitOptions& options,
                              const FitProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  const TSplineSpace space(state.mesh);
  const TSplineFitSpace fitSpace(space, unitWeights);
  const auto roundProgress = [&](const std::string& stage, double fraction) {
    if (progress) progress("round " + std::to_string(round + 1) + ": " + stage, fraction);
  };
  state.fit = fitSurface(fitSpace, state.at, state.samples, state.fitOptions, roundProgress);
  // The smoothing weight is relative to typical functions (surface_fit.h), so the one chosen on
  // the first round holds for the refined ones.
  state.fitOptions.smoothing = state.fit.smoothing;
  state.at = state.fit.parameters;
  state.round = round;
  state.check = {};
  if (options.measure) {
    roundProgress("measuring the surface", 1.0);
    state.check = options.measure(state.mesh, state.fit);
  }
  state.samplesWithin = state.fit.rmsError <= options.tolerance &&
                        state.fit.maxError <= options.maxErrorFactor * options.tolerance;
  TSplineFitRound summary;
  summary.controlPoints = space.numBasis();
  summary.faces = state.mesh.numFaces();
  summary.rmsError = state.fit.rmsError;
  summary.maxError = state.fit.maxError;
  summary.folds = state.check.foldCount;
  summary.measuredRms = state.check.rms;
  summary.measuredMax = state.check.max;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

// The faces of `candidates` (worst first) to split: the longest run whose faces, with the cells
// around the cones whose caps they touch (withTouchedCapsSplit), fit the control point budget (a
// split adds about five vertices: one inside, four on sides).
std::vector<int> splitWithinBudget(const FitState& state, const std::vector<int>& candidates,
                                   const TSplineAdaptiveFitOptions& options) {
  const std::size_t budget = std::size_t(
      std::max(0, (options.maxControlPoints - int(state.fit.controlPoints.rows())) / 5));
  const std::vector<TSplineCapRegion> regions = capRegions(state.mesh);
  const auto closure = [&](std::size_t length) {
    return withTouchedCapsSplit(state.mesh, regions,
                                {candidates.begin(), candidates.begin() + length});
  };
  std::size_t fitting = 0, over = candidates.size() + 1;
  while (over - fitting > 1) {
    const std::size_t middle = (fitting + over) / 2;
    (closure(middle).size() <= budget ? fitting : over) = middle;
  }
  return closure(fitting);
}

void split(FitState& state, const std::vector<int>& faces) {
  const Eigen::Index first = state.mesh.numFaces();
  splitIntoFour(state.mesh, faces, state.at);
  // The new parts keep the face's fairing factor.
  Eigen::VectorXd& fairing = state.fitOptions.faceFairing;
  fairing.conservativeResize(state.mesh.numFaces());
  for (std::size_t i = 0; i < faces.size(); ++i)
    fairing.segment(first + 3 * Eigen::Index(i), 3).setConstant(fairing[faces[i]]);
}

// Multiplies the fairing factor of `faces` by options.foldFairing up to maxFoldFairing; the
// number of faces whose factor grew.
int stiffen(FitState& state, const std::vector<int>& faces,
            const TSplineAdaptiveFitOptions& options) {
  int stiffened = 0;
  for (const int f : faces) {
    double& factor = state.fitOptions.faceFairing[f];
    const double raised = std::min(factor * options.foldFairing, options.maxFoldFairing);
    stiffened += raised > factor;
    factor = raised;
  }
  return stiffened;
}

// The faces holding `points`, each once.
std::vector<int> facesOf(const std::vector<FacePoint>& points) {
  std::vector<int> faces;
  for (const auto& p : points) faces.push_back(p.face);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

// `faces` and every face sharing a vertex with one of them, in increasing order.
std::vector<int> withNeighbours(const TMesh& mesh, const std::vector<int>& faces) {
  std::vector<char> touched(std::size_t(mesh.numVertices), 0);
  for (const int f : faces)
    for (const int v : mesh.faces[std::size_t(f)].vertices) touched[std::size_t(v)] = 1;
  std::vector<int> out;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const auto& corners = mesh.faces[std::size_t(f)].vertices;
    if (std::any_of(corners.begin(), corners.end(),
                    [&](int v) { return touched[std::size_t(v)] != 0; }))
      out.push_back(f);
  }
  return out;
}

// One repair search from `start`, a round that folds: each step fits every remedy from the state
// kept so far and keeps the remedied fit that folds least when it is within the tolerance, or its
// excess at most `excessLimit` (0 when the start is within), and folds less. With
// `holdParameters` the fits keep the samples' parameters (no parameter correction), so a remedy
// changes the surface only near the faces it acts on. Every fit's summary goes to `rounds`;
// returns the state kept last.
FitState repairFolds(const FitState& start, bool holdParameters, double excessLimit,
                     const TSplineAdaptiveFitOptions& options, const FitProgress& progress,
                     std::vector<TSplineFitRound>& rounds) {
  FitState kept = start;
  if (holdParameters) kept.fitOptions.correctionRounds = 0;
  for (int step = 0; step < options.maxRepairSteps && kept.check.foldCount > 0; ++step) {
    std::vector<int> at = facesOf(kept.check.folds);
    const std::vector<int> away = facesOf(kept.check.facingAway);
    at.insert(at.end(), away.begin(), away.end());
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end()), at.end());
    const std::vector<int> around = withNeighbours(kept.mesh, at);
    std::optional<FitState> best;
    for (const FoldRemedy remedy : {FoldRemedy::Split, FoldRemedy::Stiffen, FoldRemedy::SplitAround,
                                    FoldRemedy::StiffenAround}) {
      FitState candidate = kept;
      const std::vector<int>& faces =
          remedy == FoldRemedy::SplitAround || remedy == FoldRemedy::StiffenAround ? around : at;
      int remedied = 0;
      if (remedy == FoldRemedy::Split || remedy == FoldRemedy::SplitAround) {
        const std::vector<int> splits = splitWithinBudget(candidate, faces, options);
        split(candidate, splits);
        remedied = int(splits.size());
      } else {
        remedied = stiffen(candidate, faces, options);
      }
      if (remedied == 0) continue;
      TSplineFitRound summary = fitAndMeasure(candidate, int(rounds.size()), options, progress);
      summary.repairOf = kept.round;
      summary.remedy = remedy;
      summary.remediedFaces = remedied;
      summary.parametersHeld = holdParameters;
      rounds.push_back(summary);
      if ((candidate.within() || candidate.excess(options) <= excessLimit) &&
          candidate.check.foldCount < (best ? best->check : kept.check).foldCount)
        best = std::move(candidate);
      // No remedy can fold less than none.
      if (best && best->check.foldCount == 0) break;
    }
    if (!best) break;
    kept = std::move(*best);
  }
  return kept;
}

}  // namespace

const char* foldRemedyName(FoldRemedy remedy) {
  switch (remedy) {
    case FoldRemedy::Split:
      return "split";
    case FoldRemedy::Stiffen:
      return "stiffen";
    case FoldRemedy::SplitAround:
      return "split around";
    case FoldRemedy::StiffenAround:
      return "stiffen around";
  }
  return "";
}

TSplineAdaptiveFitResult fitTSplineAdaptively(const TMesh& mesh,
                                              const std::vector<FacePoint>& parameters,
                                              const Eigen::MatrixX3d& targets,
                                              const TSplineAdaptiveFitOptions& options,
                                              const FitProgress& progress) {
  TSplineAdaptiveFitResult result;
  FitState state;
  state.mesh = mesh;
  state.at.reserve(parameters.size());
  for (const auto& p : parameters) state.at.push_back({p.face, p.position});
  state.samples = targets;
  state.fitOptions = options.fit;
  state.fitOptions.faceFairing = Eigen::VectorXd::Ones(mesh.numFaces());
  int previousFolds = std::numeric_limits<int>::max();
  // The best round within the tolerance so far, and while there is none, every round whose
  // excess is within excessSlack times the least met (see the header): the least only falls, so
  // a round dropped can never be kept, and each holds a T-mesh, a fit and the samples.
  std::optional<FitState> kept;
  std::vector<FitState> outside;
  const auto keepIfBetter = [&](const FitState& s) {
    if (!s.within()) {
      if (kept) return;
      outside.push_back(s);
      double least = std::numeric_limits<double>::infinity();
      for (const FitState& o : outside) least = std::min(least, o.excess(options));
      outside.erase(std::remove_if(outside.begin(), outside.end(),
                                   [&](const FitState& o) {
                                     return o.excess(options) > options.excessSlack * least;
                                   }),
                    outside.end());
    } else if (!kept || s.check.foldCount <= kept->check.foldCount) {
      kept = s;
      outside.clear();
    }
  };
  for (int round = 0;; ++round) {
    TSplineFitRound summary = fitAndMeasure(state, round, options, progress);
    keepIfBetter(state);
    const TSplineSurfaceCheck& check = state.check;
    if (state.reachedTolerance() || round >= options.maxRefinements) {
      result.rounds.push_back(summary);
      break;
    }
    // The worst distance per face, of the samples and of the stray surface points; faces beyond
    // the tolerance are split, worst first, as far as the budget goes.
    const TSplineSpace space(state.mesh);
    const TSplineFitSpace fitSpace(space, unitWeights);
    std::vector<double> faceError(std::size_t(state.mesh.numFaces()), 0.0);
    const auto count = [&](const FacePoint& p, double d) {
      if (std::isfinite(d))
        faceError[std::size_t(p.face)] = std::max(faceError[std::size_t(p.face)], d);
    };
    const Eigen::VectorXd& weights = state.fitOptions.sampleWeights;
    for (std::size_t s = 0; s < state.at.size(); ++s)
      count(state.at[s], state.fit.distances[Eigen::Index(s)] *
                             (weights.size() > 0 ? std::sqrt(weights[Eigen::Index(s)]) : 1.0));
    for (std::size_t k = 0; k < check.strays.size(); ++k)
      count(check.strays[k],
            (evaluateFitSurface(fitSpace, state.fit.controlPoints, check.strays[k]) -
             check.strayTargets.row(Eigen::Index(k)).transpose())
                .norm());
    // Folds: a stiffer fairing where they are, and no split there.
    const std::vector<int> folded = facesOf(check.folds);
    summary.stiffenedFaces = stiffen(state, folded, options);
    const int folds = int(check.folds.size());
    // Beyond the maximum wanted, or (when only the RMS is off) beyond the tolerance; when only
    // the measurement is off, only the faces of its stray points, not every face holding a
    // sample above the tolerance.
    const double maxError = *std::max_element(faceError.begin(), faceError.end());
    const double threshold =
        maxError > options.maxErrorFactor * options.tolerance
            ? std::max(options.tolerance,
                       std::min(0.5 * options.maxErrorFactor * options.tolerance, 0.5 * maxError))
        : !state.samplesWithin ? options.tolerance
        : options.measure      ? std::max(options.tolerance, check.strayDistance)
                               : 0.5 * options.maxErrorFactor * options.tolerance;
    std::vector<int> order(faceError.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return faceError[std::size_t(a)] > faceError[std::size_t(b)]; });
    std::vector<int> candidates;
    for (const int f : order) {
      if (faceError[std::size_t(f)] <= threshold) break;
      if (!std::binary_search(folded.begin(), folded.end(), f)) candidates.push_back(f);
    }
    const std::vector<int> marked = splitWithinBudget(state, candidates, options);
    // The stray points join the samples (unit weight: they are points of the scan).
    const auto strays = Eigen::Index(check.strays.size());
    summary.addedSamples = int(strays);
    if (strays > 0) {
      const Eigen::Index old = state.samples.rows();
      state.samples.conservativeResize(old + strays, 3);
      state.samples.bottomRows(strays) = check.strayTargets;
      state.at.insert(state.at.end(), check.strays.begin(), check.strays.end());
      if (weights.size() > 0) {
        state.fitOptions.sampleWeights.conservativeResize(state.samples.rows());
        state.fitOptions.sampleWeights.tail(state.samples.rows() - old).setOnes();
      }
    }
    // Another round when it has something to act on: refined faces, new samples, or folds that
    // the last stiffening reduced.
    const bool unfolding = summary.stiffenedFaces > 0 && folds < previousFolds;
    previousFolds = folds;
    summary.splitFaces = int(marked.size());
    result.rounds.push_back(summary);
    if (marked.empty() && strays == 0 && !unfolding) break;
    split(state, marked);
  }
  // No round within: of those nearly as close as the closest, the one that folds least (the
  // latest of equals).
  double excessLimit = 0.0;
  if (!kept) {
    double least = std::numeric_limits<double>::infinity();
    for (const FitState& s : outside) least = std::min(least, s.excess(options));
    excessLimit = options.excessSlack * least;
    for (FitState& s : outside)
      if (s.excess(options) <= excessLimit && (!kept || s.check.foldCount <= kept->check.foldCount))
        kept = std::move(s);
    // Excesses that are not numbers: the last round, as without a measurement.
    if (!kept) kept = std::move(outside.back());
  }
  // The repair (see the header): two searches from the round kept, the better one's end kept
  // (the second only when the first still folds).
  if (kept->check.foldCount > 0) {
    FitState moved = repairFolds(*kept, false, excessLimit, options, progress, result.rounds);
    if (moved.check.foldCount > 0) {
      FitState held = repairFolds(*kept, true, excessLimit, options, progress, result.rounds);
      if (held.check.foldCount < moved.check.foldCount) moved = std::move(held);
    }
    kept = std::move(moved);
  }
  result.keptRound = kept->round;
  result.mesh = std::move(kept->mesh);
  result.fit = std::move(kept->fit);
  result.reachedTolerance = kept->reachedTolerance();
  result.parameters.assign(kept->at.begin(), kept->at.begin() + std::ptrdiff_t(parameters.size()));
  return result;
}

}  // namespace mspline::spline
