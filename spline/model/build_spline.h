#pragma once
// From a flattened surface to a spline space on it, as `spline` and `fit` build it: the T-mesh
// of a seamless quad grid (T-splines, and subdivision surfaces on the same net) or the domain
// triangulation with knot clouds (triangular B-splines); the surface copied into the model; and
// the samples (the surface's vertices, then points inside its faces) with their parameters.
// fitControlPoints then fits the control points to the samples, faired, with parameter correction.
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/fitting/surface_fit.h"
#include "mspline/structure/core/progress.h"
#include "mspline/structure/flatten/flatten_surface.h"

namespace mspline::spline {

/// Wall-clock seconds per stage, in the order the stages first ran.
using StageSeconds = std::vector<std::pair<std::string, double>>;

/// Adds `seconds` to the stage `name` (appended when new): a stage that runs several times (a
/// space rebuilt while refining) reports its total.
void addStageSeconds(StageSeconds& stages, const std::string& name, double seconds);

enum class SpaceKind {
  /// Manifold triangular B-spline on a coarsening of the flat metric.
  TriBSpline,
  /// Cubic T-spline on a seamless quad grid; subdivision surfaces use the same net.
  TSpline,
};

struct BuildSplineOptions {
  SpaceKind kind = SpaceKind::TriBSpline;
  /// Triangular B-splines: polynomial degree (T-splines are cubic).
  int degree = 3;
  /// Control points wanted, about.
  int control = 6000;
  /// Triangular B-splines: knot cloud radius as a fraction of the smallest inradius at each
  /// vertex, and the clouds' seed.
  double cloudRadius = 0.3;
  unsigned seed = 1;
  /// T-splines: grid cell side as a fraction of sqrt(flat area); 0: from `control`, about one
  /// cell per control point.
  double grid = 0.0;
  /// Wanted samples per control point: points inside the surface's faces are added where the
  /// vertices alone give fewer (0: vertices only).
  double samplesPerControlPoint = 3.0;
  /// T-splines: the cells that splitCellsAroundCones will split around cones get as many more
  /// samples per area as they will have control points (false where the grid is fitted unsplit,
  /// as by the Catmull-Clark fit).
  bool denserWhereSplit = true;
  /// T-splines and subdivision surfaces, with corners of valence 3: the quad layout's cones at
  /// least this many cells apart on the surface (quadLayoutFlattening). A T-spline cone's cap
  /// needs its cells around it free of other cones, or the cells there are split until they are
  /// (man's 61 cones a cell apart: 8,000 of 10,500 control points went to those splits), and the
  /// traces of cones a fraction of a cell apart run side by side, leaving strips that quantization
  /// stretches to a cell or crushes (man's cells up to 25.7 times longer than wide; 4.0 at three
  /// cells). The Catmull-Clark fit, which splits nothing, keeps cones one cell apart: over the data
  /// set it folds more at three (README).
  double coneSeparationCells = 3.0;
  /// Triangular B-splines: per surface vertex, how densely the domain should sample it (empty:
  /// uniformly in the flat metric; structure::CoarseningOptions::density).
  Eigen::VectorXd density;
};

/// The quad grid of a T-spline space.
struct GridFigures {
  /// A flat torus's lattice grid (cells along both periods), else the motorcycle graph's
  /// rectangle layout with cones (traces, rectangles, cell size, rounding).
  bool torus = false;
  int cellsAlongFirst = 0, cellsAlongSecond = 0;
  int traces = 0, rectangles = 0;
  /// The cross field's turn in face 0 (radians; structure::MotorcycleLayoutOptions::frameAngle),
  /// and why the field aligned with face 0 was not laid out (empty when it was).
  double frameAngle = 0.0;
  std::string frameTurnedBecause;
  /// Cell side in the flat metric, and the largest rounding of a rectangle side to whole cells
  /// (motorcycle layouts).
  double cellSize = 0.0, maxRoundingError = 0.0;
  /// Segments shorter than a quarter of a cell given none, and rectangles left without area
  /// (layout_tmesh.h: collapse).
  int collapsedSegments = 0, collapsedRectangles = 0;
  /// The whole numbers of cells are a proven optimum (layout_tmesh.h: rounding), found by this
  /// many integer programs (one more per undone collapse) in this many seconds.
  bool quantizationOptimal = false;
  int quantizations = 0;
  double quantizationSeconds = 0.0;
  /// Largest ratio of a cell's sides on the surface, and its 99th percentile over the cells.
  double anisotropy = 1.0;
  double anisotropyP99 = 1.0;
  /// T-mesh vertices whose valence is not 4 (the cones that kept a vertex of their own).
  int extraordinaryPoints = 0;
};

/// The domain triangulation of a triangular B-spline space.
struct DomainFigures {
  int vertices = 0, faces = 0, cones = 0;
  /// Surface vertices the coarsening could not remove, vertices kept to separate cones, and
  /// domain edges still joining two cones.
  int unremovedVertices = 0, coneSeparatingVertices = 0, coneSides = 0;
  /// structure::CoarseTriangulation::maxTrackingError.
  double trackingError = 0.0;
  /// The domain metric's largest deviation from flatness before and after polishing
  /// (spline::polishDomainMetric).
  double flatnessBefore = 0.0, flatnessAfter = 0.0;
};

struct SplineSpaceBuild {
  /// The model without control points: kind, surface, and the T-mesh with the surface vertices'
  /// T-mesh points, or the domain, knots and the surface vertices' domain points.
  SplineModel model;
  /// Samples: the parameters (T-mesh points or domain points by kind) and the 3D points; sample
  /// k < V is surface vertex k, points inside faces follow.
  std::vector<FacePoint> tmeshSites;
  std::vector<SurfacePoint> domainSites;
  Eigen::MatrixX3d targets;
  /// Per sample after the vertices, the surface face it lies in.
  std::vector<int> sampleFaces;
  /// The space's figures: `grid` for T-splines, `domain` for triangular B-splines.
  GridFigures grid;
  DomainFigures domain;
  /// "grid", "locate" (T-splines) or "coarsen", "basis", "locate" (triangular B-splines).
  StageSeconds stageSeconds;
};

/// Builds the space of `options.kind` on the flattened closed surface. Throws InputError when the
/// flattening did not converge, InputError / SolverError when the grid or domain cannot be built.
SplineSpaceBuild buildSpline(const structure::Flattening& flattening,
                             const BuildSplineOptions& options = {},
                             const structure::Progress& progress = {});

/// The samples' parameters as the fitting engine takes them, for a T-spline or subdivision space
/// built on `build.model.tmesh`.
std::vector<FacePoint> tmeshFitParameters(const SplineSpaceBuild& build);

/// T-splines (not subdivision surfaces, which keep the net): splits the cells around cones closer
/// together than caps need (spline/tspline/tspline_refine.h, refineAroundCones); the sites and
/// the surface vertices' T-mesh points follow.
void splitCellsAroundCones(SplineSpaceBuild& build);

/// One fit of the control points of a built space to its samples, as `spline` makes a model from
/// its mesh: the fitting engine (spline/fitting/surface_fit.h) with fairing and parameter
/// correction; no refinement.
struct ControlPointFit {
  /// RMS and maximum distance between the samples and the spline at their parameters after the
  /// last projection (absolute).
  double rmsError = 0.0, maxError = 0.0;
  /// The relative fairing weight used and the parameter correction rounds done.
  double smoothing = 0.0;
  int correctionRounds = 0;
  /// Basis functions that no sample lies under (held by the pull towards the quasi-interpolant).
  int basisWithoutSamples = 0;
  /// Samples where the spline is undefined (cone points, holes of a T-mesh), left out.
  int samplesOutside = 0;
  /// T-splines: anchors that could not be inferred (tspline.h, missingAnchors).
  int missingAnchors = 0;
  /// "fit" (and, for triangular B-splines, "basis": the space's set-up).
  StageSeconds stageSeconds;
};

/// Sets build.model's control points (and unit weights for a T-spline) fitted to its samples with
/// `options` (fairing weighted by hold-out validation and parameter correction by default), and
/// the surface vertices' parameters to where parameter correction moved them. Throws SolverError
/// when the system cannot be factored. Fairing is what keeps the surface from folding between the
/// samples: a T-spline on a coarse mesh has about as many control points as samples (femur: 18,064
/// for 38,036), and fitted without it the surface shot sheets far out of the body (femur: 37,433
/// folded triangle pairs at export resolution 4).
ControlPointFit fitControlPoints(SplineSpaceBuild& build, const SurfaceFitOptions& options = {},
                                 const structure::Progress& progress = {});

}  // namespace mspline::spline
