#pragma once
// The main job as one function: a spline surface fitted to a scan. Holes are closed by fill
// patches, the surface is flattened (structure/flatten/flatten_surface.h), the spline space is
// built on its flat structure (build_spline.h), then least squares with fairing, parameter
// correction and adaptive refinement (spline/fitting/surface_fit.h) until the RMS distance is
// within the tolerance or the control point budget is spent; the errors are measured both ways.
// CONTRACT (written before the implementation; the implementer may add fields and refine
// comments, but keeps these names): FitKind, FitOptions, FitResult, fitScan.
#include <string>
#include <vector>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/model/build_spline.h"
#include "mspline/spline/quality/surface_quality.h"
#include "mspline/structure/core/progress.h"
#include "mspline/structure/flatten/flatten_surface.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::spline {

enum class FitKind { TSpline, TriBSpline, Subd };

struct FitOptions {
  FitKind kind = FitKind::TSpline;
  /// Wanted RMS distance from the scan's vertices to the surface, relative to the scan's
  /// bounding-box diagonal; the maximum wanted is maxErrorFactor times it.
  double tolerance = 1e-3;
  double maxErrorFactor = 10.0;
  /// Control point budget, and the control points to start with (0: 3/4 of the budget).
  int maxControl = 8000;
  int control = 0;
  /// Fairing weight relative to the data term; < 0: chosen by hold-out validation.
  double smoothing = -1.0;
  /// Parameter correction rounds per fit, refinement rounds at most.
  int correctionRounds = 3;
  int maxRefinements = 6;
  /// Samples on fill patches (their vertices and points inside their faces) only keep the
  /// surface near the patch where there is no scan: this weight, and they are not measured.
  double fillWeight = 0.01;
  /// tspline and subd: the smallest valence of a cone's corner in the quad layout, 2 or 3 (a cone
  /// of k quarter turns of curvature is a corner of valence 4 - k). 3 makes every corner valence
  /// 3 or more (a cube's layout is its six faces) and spreads a sharp tip's curvature over
  /// several cones a few cells apart; 2 puts one cone of angle pi at a sharp tip, which folds more
  /// fits of the data set but fewer of some organic ones and flat squares (README). A mesh with too
  /// few vertices for the cones is split at its edge midpoints first (the same surface).
  int minCornerValence = 3;
  /// The flattening; for tspline and subd, fitScan sets the quad layout's cones on top of it
  /// (quadLayoutFlattening, quad_layout_flattening.h).
  structure::FlattenOptions flatten;
};

/// One fit of a refinement loop (T-splines, triangular B-splines) or the single fit (subd).
struct FitRound {
  int controlPoints = 0;
  /// RMS and maximum distance of the samples to the surface, relative to the diagonal.
  double rmsError = 0.0, maxError = 0.0;
  /// T-splines: faces split after this round (a repair: the faces its remedy split or stiffened),
  /// the folds measured against the scan, and whether this round's fit is the one returned
  /// (tspline_adaptive_fit.h: the best round, repaired).
  int refinedFaces = 0;
  int folds = 0;
  /// T-splines: the surface's RMS and maximum distance to the scan measured as the quality does,
  /// the larger of the two ways, relative to the diagonal.
  double measuredRms = 0.0, measuredMax = 0.0;
  bool kept = false;
  double seconds = 0.0;
  /// A repair's fit: the round it started from (-1 for a refinement round), its remedy ("split",
  /// "stiffen", "split around", "stiffen around") and whether it held the samples' parameters.
  int repairOf = -1;
  std::string remedy;
  bool parametersHeld = false;
};

/// What the flattening reported (Flattening's figures that fit reports).
struct FitFlattenFigures {
  bool converged = false;
  double maxCurvatureError = 0.0;
  int flips = 0;
  /// Cones of the flat metric, and the sizes of the automatic cone sets rejected before them
  /// (Flattening::rejectedConeCounts).
  int cones = 0;
  std::vector<int> rejectedConeCounts;
  /// The automatic placement's outcome, and whether it stopped at its maximum number of cones
  /// (Flattening::conePlacement, reachedMaxCones; the flattening's progress warns of it).
  std::string conePlacement;
  bool reachedMaxCones = false;
};

struct FitResult {
  /// The fitted model (control points set), ready to save or evaluate.
  SplineModel model;
  /// The fitted surface measured against the scan (measureQuality of the model): the errors both
  /// ways relative to the scan's diagonal, folds, smoothness, regularity.
  SurfaceQuality quality;
  /// The scan's holes closed by fill patches (0 for a closed scan).
  int filledHoles = 0;
  /// Rounds of midpoint subdivision before flattening: a coarse polyhedron has too few vertices
  /// for a quad layout's cones (4 chi of them; 0 otherwise).
  int midpointSubdivisions = 0;
  /// The fits made, in order.
  std::vector<FitRound> rounds;
  /// The last fit's parameter correction rounds, smoothing weight (relative), samples where the
  /// surface is undefined, and RMS before parameter correction (relative to the diagonal).
  int correctionRounds = 0;
  double smoothing = 0.0;
  int samplesUndefined = 0;
  double rmsBeforeCorrection = 0.0;
  /// The space's figures: `grid` for tspline and subd, `domain` for tribspline.
  GridFigures grid;
  DomainFigures domain;
  FitFlattenFigures flatten;
  /// reachedTolerance: the RMS and maximum errors both ways (quality.distances) are within
  /// tolerance and maxErrorFactor * tolerance and the surface has no folds (quality.folds);
  /// withinBudget: the control points are within the budget (a quad layout can need more).
  bool reachedTolerance = false;
  bool withinBudget = false;
  /// Why the result is weaker than asked (over the budget, tolerance not reached).
  std::vector<std::string> warnings;
  /// Wall-clock seconds per stage: holes (when closed), the flattening's stages and "atlas" (the
  /// whole flattening, its stages included), the space's (grid or coarsen, basis, locate), fit,
  /// measure.
  StageSeconds stageSeconds;
};

/// "tspline", "tribspline" or "subd"; parseFitKind throws InputError for another name.
std::string fitKindName(FitKind kind);
FitKind parseFitKind(const std::string& name);

/// Fits `scan` (a validated mesh; `name` in FitOptions::flatten.name names it in messages).
/// Throws InputError / SolverError (naming the scan) when the surface cannot be flattened or the
/// space not built; a tolerance not reached is reported in the result, not thrown.
FitResult fitScan(const structure::TriMesh& scan, const FitOptions& options = {},
                  const structure::Progress& progress = {});

}  // namespace mspline::spline
