#pragma once
// Adaptive T-spline fitting: fit (surface_fit.h), then where samples are farther from the surface
// than the tolerance, split their T-mesh faces into four (local refinement: the cuts end in
// T-junctions), fit again, until the RMS distance is within the tolerance, the maximum within
// maxErrorFactor times it, or the control point budget is spent.
//
// The samples alone cannot see what the surface does between them. With a measurement of the
// surface (TSplineAdaptiveFitOptions::measure: fit_scan.cpp measures it against the scan), the
// loop also acts on it: points of the surface that stray from the scan become samples (their
// closest scan points) and their faces are refined like the samples'; faces where the surface
// folds get a stiffer fairing term instead (more freedom would not unfold them); and the
// tolerance is reached only when the measurement accepts the surface too. A split that touches a
// cone's cap region (tspline_cap.h) splits the cells around the cone too, so that the cap comes
// back at half the size instead of a T-junction entering it.
//
// The loop returns its best round, not always its last: of the rounds whose samples and measured
// distances are within the tolerance, the one with the fewest folds (the latest of equals).
// Refinement that brings strays in can add folds elsewhere (elk: 19 folds after the fourth fit,
// 22 after the fifth; lion-head 23 after the third, 37 after the fifth), and a user is better
// served by the round that folds least, but not at the price of distances: a round without folds
// whose surface strays (pipe: 1.5% RMS after the first fit) is worse than one with a few folds.
// When no round is within, the distances decide only up to excessSlack: of the rounds whose excess
// (RMS over the tolerance, maximum over the maximum wanted, the larger) is within that factor of
// the least met, the one with the fewest folds. On a coarse polyhedron the rounds after the first
// stay about as far off and fold more as their cells follow its sharp edges more tightly (joint:
// 2.3 times the tolerance and 473 folds after the first fit, 2.6 and 1,373 after the seventh).
//
// Then the best round is repaired when it folds (adjacent triangles, or triangles facing away
// from the scan). Each step fits every remedy (FoldRemedy: split the faces where it folds or
// stiffen their fairing, those faces alone or with their neighbours) from the round kept, and
// keeps the remedied fit that folds least when it folds less and is within the tolerance (when
// the best round is not: its excess within excessSlack of the least the rounds met); and again
// from there. Two such searches start from the best round:
// one whose fits correct the samples' parameters as the refinement rounds do (the surface may
// move everywhere), one whose fits hold them (one solve at the parameters of the round repaired,
// so a remedy changes the surface only near the faces it acts on); the end that folds less is
// returned. A search stops at a fit without folds (the second does not start). Which remedy unfolds
// a surface depends on why it folds: more freedom where a face is too coarse to follow the scan (a
// box corner), a stiffer fairing where the fit overshoots a crease sharper than the cells can
// follow (lion's mane); and the folds of a round move when its parameters are corrected. Each
// remedy alone, as a rule in the refinement rounds, gained some meshes and lost others; tried from
// the best round and kept only where it helps, none can make the surface returned worse.

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/fitting/surface_fit.h"
#include "mspline/spline/tspline/tmesh.h"

namespace mspline::spline {

/// What a measurement of a fitted surface beyond its samples found.
struct TSplineSurfaceCheck {
  /// Points of the surface farther from the scan than strayDistance: their parameters on the
  /// T-mesh measured, and per row the closest scan point.
  std::vector<FacePoint> strays;
  Eigen::MatrixX3d strayTargets;
  /// The distance beyond which surface points are strays (absolute units); their faces are split
  /// beyond it too.
  double strayDistance = 0.0;
  /// Parameters where adjacent triangles of the surface fold (stiffened), and of triangles that
  /// face away from the scan.
  std::vector<FacePoint> folds;
  std::vector<FacePoint> facingAway;
  /// Every fold the measurement counted (also those not in `folds`).
  int foldCount = 0;
  /// The measured RMS and maximum distances, the larger of the two ways (absolute units).
  double rms = 0.0, max = 0.0;
  /// The measured distances are within the tolerance both ways (folds aside).
  bool distancesWithin = true;
  /// The surface is within the tolerance both ways and has no folds.
  bool accepted = true;
};

/// What the repair does to the faces where the round it starts from folds.
enum class FoldRemedy {
  /// Split them into four (with the cells around cones whose caps they touch), within the control
  /// point budget.
  Split,
  /// Multiply their fairing factor by foldFairing, up to maxFoldFairing.
  Stiffen,
  /// The same for them and every face sharing a vertex with one of them.
  SplitAround,
  StiffenAround,
};

/// "split", "stiffen", "split around", "stiffen around".
const char* foldRemedyName(FoldRemedy remedy);

/// Measures the surface of `fit` (control points, samples' parameters) on `mesh`.
using TSplineSurfaceMeasure =
    std::function<TSplineSurfaceCheck(const TMesh& mesh, const SurfaceFitResult& fit)>;

struct TSplineAdaptiveFitOptions {
  /// Wanted RMS distance of the samples to the surface (absolute units).
  double tolerance = 1e-3;
  /// The maximum distance wanted is maxErrorFactor * tolerance.
  double maxErrorFactor = 10.0;
  /// Refinement stops before the blending functions would exceed this.
  int maxControlPoints = 8000;
  /// At most this many refinement rounds.
  int maxRefinements = 6;
  /// The fairing factor of a face where the surface folded is multiplied by this each round, up
  /// to maxFoldFairing (without a bound, folds the fairing cannot remove flattened the surface
  /// away from its samples on 3torus: a sample 18% of the diagonal off).
  double foldFairing = 10.0;
  double maxFoldFairing = 1000.0;
  /// At most this many steps in each repair search (a step fits every remedy once).
  int maxRepairSteps = 4;
  /// When no round is within the tolerance: fits whose excess (see above) is at most this factor
  /// times the least met count as equally close, and the one that folds least is kept.
  double excessSlack = 1.25;
  /// Optional: measures the surface after every fit (see above).
  TSplineSurfaceMeasure measure;
  SurfaceFitOptions fit;
};

/// One fit of the refinement sequence.
struct TSplineFitRound {
  int controlPoints = 0;
  int faces = 0;
  double rmsError = 0.0;
  double maxError = 0.0;
  /// Faces split after this round (0 for the last).
  int splitFaces = 0;
  /// With a measurement: the stray surface points added as samples and the faces whose fairing
  /// was raised for folds after this round.
  int addedSamples = 0;
  int stiffenedFaces = 0;
  /// With a measurement: the folds it counted, and its RMS and maximum distances (the larger
  /// way, absolute units).
  int folds = 0;
  double measuredRms = 0.0, measuredMax = 0.0;
  /// A repair's fit (after the refinement rounds): the round it started from (-1 for a refinement
  /// round), the remedy applied to that round's T-mesh and fairing, and the faces it split or
  /// stiffened.
  int repairOf = -1;
  FoldRemedy remedy = FoldRemedy::Split;
  int remediedFaces = 0;
  /// A repair's fit that held the samples' parameters (see above).
  bool parametersHeld = false;
  double seconds = 0.0;
};

struct TSplineAdaptiveFitResult {
  /// The T-mesh of the round kept (input faces keep their ids; split faces' parts follow) and its
  /// fit.
  TMesh mesh;
  SurfaceFitResult fit;
  /// The samples' parameters on `mesh` (after parameter correction); `fit` also holds the stray
  /// surface points' samples, after these.
  std::vector<FacePoint> parameters;
  /// Every fit made: the refinement rounds in order, then the repair searches' fits (the one
  /// that corrects parameters first).
  std::vector<TSplineFitRound> rounds;
  /// The round returned (index into rounds; the last refinement round without a measurement).
  int keptRound = 0;
  /// RMS <= tolerance and max <= maxErrorFactor * tolerance, and the measurement (when given)
  /// accepted the surface.
  bool reachedTolerance = false;
};

/// Fits a T-spline with unit weights on `mesh` (refined as described) to `targets` (one row per
/// sample) from the samples' initial `parameters`. With sample weights (options.fit), faces are
/// refined by sqrt(weight) * distance.
TSplineAdaptiveFitResult fitTSplineAdaptively(const TMesh& mesh,
                                              const std::vector<FacePoint>& parameters,
                                              const Eigen::MatrixX3d& targets,
                                              const TSplineAdaptiveFitOptions& options = {},
                                              const FitProgress& progress = {});

}  // namespace mspline::spline
