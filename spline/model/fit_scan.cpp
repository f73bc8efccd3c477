#include "mspline/spline/model/fit_scan.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "mspline/spline/fitting/surface_fit.h"
#include "mspline/spline/model/model_surface.h"
#include "mspline/spline/model/quad_layout_flattening.h"
#include "mspline/spline/quality/surface_quality.h"
#include "mspline/spline/subd/subd_fit_space.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/spline/tribspline/tri_bspline_fit_space.h"
#include "mspline/spline/tspline/tspline_adaptive_fit.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/cap_holes.h"
#include "mspline/structure/mesh/closest_point.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/mesh/subdivide.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::spline {

namespace {

using namespace structure;

// Per sample of `build`, its scan vertex or -1 (points inside faces, fill patch vertices), and
// the samples' weights: `fillWeight` on fill patches.
std::vector<int> scanSampleVertices(const SplineSpaceBuild& build,
                                    const std::vector<char>& scanVertex,
                                    const std::vector<char>& filledFace, double fillWeight,
                                    Eigen::VectorXd& weights) {
  const std::size_t count = std::size_t(build.targets.rows());
  std::vector<int> sampleVertex(count, -1);
  weights = Eigen::VectorXd::Ones(Eigen::Index(count));
  for (std::size_t k = 0; k < count; ++k) {
    const bool vertex = k < scanVertex.size();
    const bool filled =
        vertex ? !scanVertex[k] : filledFace[std::size_t(build.sampleFaces[k - scanVertex.size()])];
    if (filled) weights[Eigen::Index(k)] = fillWeight;
    if (vertex && !filled) sampleVertex[k] = int(k);
  }
  return sampleVertex;
}

// Per surface vertex, the mean over its one-ring of how densely the domain should sample it:
// (distance / tolerance)^2 of the samples at scan vertices, between 1 and 64.
Eigen::VectorXd refinementDensity(const TriMesh& surface, const std::vector<int>& sampleVertex,
                                  const Eigen::VectorXd& distances, double tolerance) {
  Eigen::VectorXd pointDensity = Eigen::VectorXd::Ones(Eigen::Index(surface.n_vertices()));
  for (std::size_t k = 0; k < sampleVertex.size(); ++k) {
    const double d = distances[Eigen::Index(k)] / tolerance;
    if (sampleVertex[k] >= 0 && std::isfinite(d))
      pointDensity[sampleVertex[k]] = std::clamp(d * d, 1.0, 64.0);
  }
  Eigen::VectorXd density = Eigen::VectorXd::Zero(Eigen::Index(surface.n_vertices()));
  for (const auto v : surface.vertices()) {
    double sum = pointDensity[v.idx()];
    int count = 1;
    for (const auto w : surface.vv_range(v)) {
      sum += pointDensity[w.idx()];
      ++count;
    }
    density[v.idx()] = sum / count;
  }
  return density;
}

// The T-spline of `fit` on `mesh` measured against the scan as a user sees it
// (surface_quality.h): per T-mesh face the surface point farthest from the scan beyond the stray
// distance, with its closest scan point, and the folds. `model` carries the scan's surface
// and fills. A closest scan point is only trusted as a target when it faces the same way as the
// surface and lies along the surface's normal: not on another sheet of a thin part, not on the
// rim of a hole beside the surface over its fill (such targets folded the surface on head, elk,
// mushroom).
TSplineSurfaceCheck checkAgainstScan(SplineModel model, const TMesh& mesh,
                                     const SurfaceFitResult& fit, const TriMesh& scan,
                                     const TriangleMeshDistance& scanDistance,
                                     const FitOptions& options) {
  model.tmesh = mesh;
  model.controlPoints = fit.controlPoints;
  model.weights = Eigen::VectorXd::Ones(fit.controlPoints.rows());
  for (std::size_t v = 0; v < model.surfaceVertexTMeshPoints.size(); ++v)
    model.surfaceVertexTMeshPoints[v] = fit.parameters[v];
  const ModelSurface surface(model, options.flatten.name);
  QualityOptions measure;
  measure.name = options.flatten.name;
  measure.scanName = options.flatten.name;
  measure.details = true;
  const SurfaceQuality quality = measureQuality(model, surface, fit.controlPoints, &scan, measure);
  const SurfaceDistances& d = quality.distances;
  TSplineSurfaceCheck check;
  check.distancesWithin = std::max(d.scanToSurface.rms, d.surfaceToScan.rms) <= options.tolerance &&
                          std::max(d.scanToSurface.max, d.surfaceToScan.max) <=
                              options.maxErrorFactor * options.tolerance;
  check.accepted = check.distancesWithin && quality.folds.total() == 0;
  check.foldCount = quality.folds.total();
  check.rms = std::max(d.scanToSurface.rms, d.surfaceToScan.rms) * d.diagonal;
  check.max = std::max(d.scanToSurface.max, d.surfaceToScan.max) * d.diagonal;
  const auto scanNormal = [&](int face) {
    const auto& corners = scanDistance.triangles()[std::size_t(face)];
    const auto corner = [&](int i) {
      return Eigen::Vector3d(scanDistance.positions().row(corners[std::size_t(i)]).transpose());
    };
    return Eigen::Vector3d((corner(1) - corner(0)).cross(corner(2) - corner(0)).normalized());
  };
  // Stiffened in the refinement rounds: only the folds between adjacent triangles (details.folds
  // lists them first): they are the surface's own, while a triangle against the scan's normal can
  // be the scan's doing (3torus's subd fit has 8,648) and stiffening there pulled the surface 7%
  // of the diagonal off. Those facing away are remedied only by the repair, which keeps a remedy
  // only where it helps.
  check.folds.assign(quality.details.folds.begin(),
                     quality.details.folds.begin() + quality.folds.adjacentPairs);
  check.facingAway.assign(quality.details.folds.begin() + quality.folds.adjacentPairs,
                          quality.details.folds.end());
  // Strays beyond half the maximum wanted; beyond the tolerance when the RMS is off (a
  // polyhedron's edges rounded over too wide a band).
  const bool rmsOff = std::max(d.scanToSurface.rms, d.surfaceToScan.rms) > options.tolerance;
  check.strayDistance =
      (rmsOff ? 1.0 : 0.5 * options.maxErrorFactor) * options.tolerance * d.diagonal;
  std::vector<int> worst(std::size_t(mesh.numFaces()), -1);
  const auto& samples = quality.details.surfaceSamples;
  const Eigen::VectorXd& distances = quality.details.surfaceDistances;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    int& w = worst[std::size_t(samples[k].face)];
    if (distances[Eigen::Index(k)] > check.strayDistance &&
        (w < 0 || distances[Eigen::Index(k)] > distances[w]))
      w = int(k);
  }
  std::vector<Eigen::Vector3d> targets;
  std::vector<FitBasisTerm> terms;
  for (const int k : worst) {
    if (k < 0) continue;
    const FacePoint& p = samples[std::size_t(k)];
    Eigen::Vector3d ds, dt;
    if (!evaluateFitTangents(surface.fitSpace(), fit.controlPoints, p, terms, ds, dt)) continue;
    const Eigen::Vector3d normal = ds.cross(dt).normalized();
    const Eigen::Vector3d point = evaluateFitSurface(surface.fitSpace(), fit.controlPoints, p);
    const ClosestPoint closest = scanDistance.query(point);
    const Eigen::Vector3d offset = (closest.closest - point).normalized();
    if (normal.dot(scanNormal(closest.face)) > 0.5 && std::abs(offset.dot(normal)) > 0.8) {
      check.strays.push_back(p);
      targets.push_back(closest.closest);
    }
  }
  check.strayTargets.resize(Eigen::Index(targets.size()), 3);
  for (std::size_t k = 0; k < targets.size(); ++k)
    check.strayTargets.row(Eigen::Index(k)) = targets[k].transpose();
  return check;
}

// The space built within the control point budget.
SplineSpaceBuild buildWithinBudget(const Flattening& flattening, const FitOptions& options,
                                   BuildSplineOptions& build, StageSeconds& stages,
                                   const Progress& progress) {
  const auto buildOnce = [&] {
    SplineSpaceBuild built = buildSpline(flattening, build, progress);
    if (options.kind == FitKind::TSpline) splitCellsAroundCones(built);  // counts for the budget
    for (const auto& [name, seconds] : built.stageSeconds) addStageSeconds(stages, name, seconds);
    return built;
  };
  SplineSpaceBuild built = buildOnce();
  // Cones kept apart add domain vertices to triangular B-splines: the target shrinks until the
  // budget holds, or until three smaller targets in a row give no smaller domain (the coarsening
  // cannot go further; the result is then reported over budget).
  const int perFace = (build.degree + 1) * (build.degree + 2) / 2;
  for (int stuck = 0; options.kind == FitKind::TriBSpline && stuck < 3 &&
                      perFace * built.model.domain.faceCount() > options.maxControl;) {
    const int faces = built.model.domain.faceCount();
    build.control = int(0.98 * build.control * options.maxControl / double(perFace * faces));
    built = buildOnce();
    stuck = built.model.domain.faceCount() < faces ? 0 : stuck + 1;
  }
  // A quad layout can come out far above the budget (segments shorter than a cell that may not
  // collapse still get whole cells, and cells are split around close cones): coarser targets, a
  // few times, keeping the smallest grid, which can also be the most stretched (turbine).
  if (options.kind == FitKind::TriBSpline) return built;
  int smallestControl = build.control;
  for (int attempt = 0; attempt < 3 && built.model.tmesh.numVertices > options.maxControl;
       ++attempt) {
    report(progress, std::to_string(built.model.tmesh.numVertices) +
                         " control points are over the budget; a coarser grid");
    build.control =
        int(0.9 * build.control * options.maxControl / double(built.model.tmesh.numVertices));
    try {
      SplineSpaceBuild coarser = buildOnce();
      if (coarser.model.tmesh.numVertices < built.model.tmesh.numVertices) {
        built = std::move(coarser);
        smallestControl = build.control;
      }
    } catch (const SolverError& e) {
      report(progress, std::string("no coarser grid (") + e.what() + ")");
      break;
    }
  }
  build.control = smallestControl;
  return built;
}

}  // namespace

std::string fitKindName(FitKind kind) {
  switch (kind) {
    case FitKind::TSpline:
      return "tspline";
    case FitKind::TriBSpline:
      return "tribspline";
    case FitKind::Subd:
      return "subd";
  }
  return "tspline";
}

FitKind parseFitKind(const std::string& name) {
  for (const FitKind kind : {FitKind::TSpline, FitKind::TriBSpline, FitKind::Subd})
    if (fitKindName(kind) == name) return kind;
  throw InputError("unknown fit kind '" + name + "' (tspline, tribspline or subd)");
}

FitResult fitScan(const TriMesh& scan, const FitOptions& options, const Progress& progress) {
  FitResult result;
  Stopwatch clock;
  const std::string& name = options.flatten.name;
  const TopologyReport scanTopology = analyzeTopology(scan);
  // Holes are closed by fill patches: the spline spans them (fairing, no data) and export trims
  // them away again.
  std::optional<CappedSurface> capped;
  // No progress before flattenSurface has checked the cones and the boundary options: the first
  // line a user sees about bad input is its error.
  if (!scanTopology.closed) {
    capped = capHoles(scan);
    result.filledHoles = int(capped->caps);
    addStageSeconds(result.stageSeconds, "holes", clock.lap());
  }
  BuildSplineOptions build;
  build.kind = options.kind == FitKind::TriBSpline ? SpaceKind::TriBSpline : SpaceKind::TSpline;
  build.control = options.control > 0 ? options.control : options.maxControl * 3 / 4;
  build.denserWhereSplit = options.kind == FitKind::TSpline;
  // The Catmull-Clark fit splits no cells around cones: its cones may come a cell apart.
  if (options.kind == FitKind::Subd) build.coneSeparationCells = 1.0;
  FlattenOptions flattenOptions = options.flatten;
  // A coarse polyhedron split at its edge midpoints (the same surface) when its vertices are too
  // few for the quad layout's cones.
  std::optional<TriMesh> subdivided;
  if (options.kind != FitKind::TriBSpline) {
    const QuadLayoutFlattening quad = quadLayoutFlattening(
        capped ? capped->mesh : scan, options.minCornerValence, build, flattenOptions);
    flattenOptions = quad.options;
    result.midpointSubdivisions = quad.midpointSubdivisions;
    for (int level = 0; level < quad.midpointSubdivisions; ++level) {
      if (capped)
        capped = subdivideMidpoint(*capped);
      else
        subdivided = subdivideMidpoint(subdivided ? *subdivided : scan);
    }
  }
  const TriMesh& mesh = capped ? capped->mesh : subdivided ? *subdivided : scan;
  const Flattening flattening = flattenSurface(mesh, flattenOptions, progress);
  result.flatten = {
      flattening.converged,         flattening.flow.maxCurvatureError, flattening.flips,
      int(flattening.cones.size()), flattening.rejectedConeCounts,     flattening.conePlacement,
      flattening.reachedMaxCones};
  for (const auto& [stage, seconds] : flattening.stageSeconds)
    addStageSeconds(result.stageSeconds, stage, seconds);
  addStageSeconds(result.stageSeconds, "atlas", clock.lap());
  if (!flattening.converged) throw SolverError(flattening.message);

  // Per vertex and face of the flattened surface (the mesh, or its common subdivision with the
  // intrinsic triangulation): whether it is the scan's.
  const TriMesh& surface = flattening.surface();
  std::vector<char> scanVertex(surface.n_vertices(), 1), filledFace(surface.n_faces(), 0);
  if (capped) {
    for (std::size_t v = 0; v < scanVertex.size(); ++v)
      scanVertex[v] = v < capped->capVertex.size() && !capped->capVertex[v];
    for (std::size_t f = 0; f < filledFace.size(); ++f)
      filledFace[f] = capped->capFace[std::size_t(
          flattening.overlay ? flattening.overlay->inputFace[f] : int(f))];
  }

  // The model knows its fills from the start: the T-spline loop measures it against the scan
  // without them (measuring the fills made head's surface-to-scan RMS 0.024 instead of 2.5e-4).
  const auto buildSpace = [&] {
    SplineSpaceBuild built =
        buildWithinBudget(flattening, options, build, result.stageSeconds, progress);
    if (capped) built.model.surfaceFaceFilled = filledFace;
    return built;
  };
  SplineSpaceBuild setup = buildSpace();
  clock.lap();
  SurfaceFitOptions fitOptions;
  fitOptions.smoothing = options.smoothing;
  fitOptions.correctionRounds = options.correctionRounds;
  std::vector<int> sampleVertex = scanSampleVertices(setup, scanVertex, filledFace,
                                                     options.fillWeight, fitOptions.sampleWeights);
  const double diagonal = boundingBoxDiagonal(scan);
  const double tolerance = options.tolerance * diagonal;
  const auto withinTolerance = [&](double rms, double max) {
    return rms <= tolerance && max <= options.maxErrorFactor * tolerance;
  };

  SurfaceFitResult fit;
  bool reached = false;
  if (options.kind == FitKind::TSpline) {
    TSplineAdaptiveFitOptions adaptiveOptions;
    adaptiveOptions.tolerance = tolerance;
    adaptiveOptions.maxErrorFactor = options.maxErrorFactor;
    adaptiveOptions.maxControlPoints = options.maxControl;
    adaptiveOptions.maxRefinements = options.maxRefinements;
    adaptiveOptions.fit = fitOptions;
    const PolygonSoup scanSoup = toSoup(scan, name);
    const TriangleMeshDistance scanDistance(pointMatrix(scanSoup.positions),
                                            triangleIndices(scanSoup));
    adaptiveOptions.measure = [&](const TMesh& refined, const SurfaceFitResult& roundFit) {
      return checkAgainstScan(setup.model, refined, roundFit, scan, scanDistance, options);
    };
    TSplineAdaptiveFitResult adaptive = fitTSplineAdaptively(
        setup.model.tmesh, setup.tmeshSites, setup.targets, adaptiveOptions, progress);
    setup.model.tmesh = std::move(adaptive.mesh);
    fit = std::move(adaptive.fit);
    reached = adaptive.reachedTolerance;
    for (std::size_t k = 0; k < adaptive.rounds.size(); ++k) {
      const TSplineFitRound& r = adaptive.rounds[k];
      FitRound round;
      round.controlPoints = r.controlPoints;
      round.rmsError = r.rmsError / diagonal;
      round.maxError = r.maxError / diagonal;
      round.refinedFaces = r.repairOf >= 0 ? r.remediedFaces : r.splitFaces;
      round.folds = r.folds;
      round.measuredRms = r.measuredRms / diagonal;
      round.measuredMax = r.measuredMax / diagonal;
      round.kept = int(k) == adaptive.keptRound;
      round.seconds = r.seconds;
      round.repairOf = r.repairOf;
      if (r.repairOf >= 0) round.remedy = foldRemedyName(r.remedy);
      round.parametersHeld = r.parametersHeld;
      result.rounds.push_back(round);
    }
    // Every surface vertex (fill patches' too) on the refined T-mesh: sample k < V is vertex k.
    for (std::size_t v = 0; v < setup.model.surfaceVertexTMeshPoints.size(); ++v)
      setup.model.surfaceVertexTMeshPoints[v] = adaptive.parameters[v];
    setup.model.weights = Eigen::VectorXd::Ones(Eigen::Index(fit.controlPoints.rows()));
  } else if (options.kind == FitKind::Subd) {
    setup.model.kind = SplineKind::Subdivision;
    const SubdSpace space(setup.model.tmesh);
    const SubdFitSpace fitSpace(space);
    fit = fitSurface(fitSpace, tmeshFitParameters(setup), setup.targets, fitOptions, progress);
    reached = withinTolerance(fit.rmsError, fit.maxError);
    for (std::size_t v = 0; v < setup.model.surfaceVertexTMeshPoints.size(); ++v)
      setup.model.surfaceVertexTMeshPoints[v] = {fit.parameters[v].face,
                                                 fit.parameters[v].position};
    FitRound round;
    round.controlPoints = int(fit.controlPoints.rows());
    round.rmsError = fit.rmsError / diagonal;
    round.maxError = fit.maxError / diagonal;
    round.kept = true;
    result.rounds.push_back(round);
  } else {
    // Adaptive refinement of the domain: the next domain is coarsened with more vertices where
    // the samples are far from the surface (refinementDensity), with the whole budget.
    for (int round = 0;; ++round) {
      Stopwatch roundClock;
      const TriBSplineSpace space(setup.model.domain, setup.model.knots);
      const TriBSplineFitSpace fitSpace(space);
      std::vector<FacePoint> parameters;
      for (const auto& p : setup.domainSites) parameters.push_back(toFitParameter(space, p));
      const auto roundProgress = [&](const std::string& stage, double fraction) {
        report(progress, "round " + std::to_string(round + 1) + ": " + stage, fraction);
      };
      fit = fitSurface(fitSpace, parameters, setup.targets, fitOptions, roundProgress);
      reached = withinTolerance(fit.rmsError, fit.maxError);
      FitRound summary;
      summary.controlPoints = int(fit.controlPoints.rows());
      summary.rmsError = fit.rmsError / diagonal;
      summary.maxError = fit.maxError / diagonal;
      summary.seconds = roundClock.lap();
      result.rounds.push_back(summary);
      const bool last = reached || round >= options.maxRefinements ||
                        (round > 0 && build.control >= options.maxControl);
      if (last) {
        result.rounds.back().kept = true;
        for (std::size_t v = 0; v < setup.model.surfaceVertexLocations.size(); ++v)
          setup.model.surfaceVertexLocations[v] = toDomainPoint(space, fit.parameters[v]);
        break;
      }
      build.density = refinementDensity(surface, sampleVertex, fit.distances, tolerance);
      build.control = options.maxControl;
      report(progress, "refining the domain where the error is above the tolerance");
      setup = buildSpace();
      sampleVertex = scanSampleVertices(setup, scanVertex, filledFace, options.fillWeight,
                                        fitOptions.sampleWeights);
    }
  }
  SplineModel& model = setup.model;
  model.controlPoints = std::move(fit.controlPoints);
  addStageSeconds(result.stageSeconds, "fit", clock.lap());

  // Honest errors: the scan's vertices to their closest points on the surface, points all over
  // the surface to the scan, and folds.
  report(progress, "measuring the surface against the scan");
  QualityOptions measure;
  measure.name = name;
  measure.scanName = name;
  result.quality = measureQuality(model, &scan, measure);
  addStageSeconds(result.stageSeconds, "measure", clock.lap());

  const SurfaceDistances& d = result.quality.distances;
  const double maxError = std::max(d.scanToSurface.max, d.surfaceToScan.max);
  const double rmsError = std::max(d.scanToSurface.rms, d.surfaceToScan.rms);
  const int folds = result.quality.folds.total();
  result.reachedTolerance = reached && rmsError <= options.tolerance &&
                            maxError <= options.maxErrorFactor * options.tolerance && folds == 0;
  result.withinBudget = model.controlPoints.rows() <= options.maxControl;
  if (!result.withinBudget)
    result.warnings.push_back(
        std::to_string(model.controlPoints.rows()) + " control points, over the budget of " +
        std::to_string(options.maxControl) +
        (options.kind == FitKind::TriBSpline ? " (the domain could not be coarser)"
                                             : " (the quad layout needed smaller cells)"));
  if (!result.reachedTolerance)
    result.warnings.push_back("the tolerance was not reached (RMS " + std::to_string(rmsError) +
                              ", max " + std::to_string(maxError) +
                              " of the diagonal, the larger way, wanted " +
                              std::to_string(options.tolerance) + " and " +
                              std::to_string(options.maxErrorFactor * options.tolerance) + "; " +
                              std::to_string(folds) + " folds)");
  result.correctionRounds = fit.rounds;
  result.smoothing = fit.smoothing;
  result.samplesUndefined = fit.samplesOutside;
  result.rmsBeforeCorrection = fit.initialRmsError / diagonal;
  result.grid = setup.grid;
  result.domain = setup.domain;
  result.model = std::move(model);
  return result;
}

}  // namespace mspline::spline
