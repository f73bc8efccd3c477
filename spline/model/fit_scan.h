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
  /// The flattening (fitScan sets quantize and maxConeQuarterTurns = 2 for tspline and subd).
  structure::FlattenOptions flatten;
};

struct FitResult {
  /// The fitted model (control points set), ready to save or evaluate.
  SplineModel model;
  // ... errors both ways (relative to the diagonal), rounds, reachedTolerance, withinBudget,
  // warnings, per-stage seconds: see the implementation.
};

/// Fits `scan` (a validated mesh; `name` in FitOptions::flatten.name names it in messages).
/// Throws InputError / SolverError (naming the scan) when the surface cannot be flattened or the
/// space not built; a tolerance not reached is reported in the result, not thrown.
FitResult fitScan(const structure::TriMesh& scan, const FitOptions& options = {},
                  const structure::Progress& progress = {});

}  // namespace mspline::spline
