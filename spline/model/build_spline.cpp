#include "mspline/spline/model/build_spline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <optional>

#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/spline/tribspline/tri_bspline_fit_space.h"
#include "mspline/spline/tspline/layout_tmesh.h"
#include "mspline/spline/tspline/torus_tmesh.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_fit_space.h"
#include "mspline/spline/tspline/tspline_refine.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/layout/coarse_triangulation.h"
#include "mspline/structure/layout/motorcycle_layout.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::spline {

namespace {

using namespace structure;

// The surface mesh as the model stores it.
void copySurface(const TriMesh& surface, SplineModel& model) {
  model.surfaceVertices.resize(Eigen::Index(surface.n_vertices()), 3);
  for (const auto v : surface.vertices()) {
    const auto& p = surface.point(v);
    model.surfaceVertices.row(v.idx()) << p[0], p[1], p[2];
  }
  for (const auto f : surface.faces()) {
    std::array<int, 3> corners{};
    int k = 0;
    for (const auto v : surface.fv_range(f)) corners[std::size_t(k++)] = v.idx();
    model.surfaceFaces.push_back(corners);
  }
}

// Barycentric coordinates of the points of a square lattice of spacing `spacing` that fall inside
// the triangle whose edge from corner k to corner k + 1 has length `lengths[k]`, the lattice
// aligned with the longest edge and shifted from its first corner by `shift` (in [0, 1)^2) times
// the spacing. A lattice, unlike a barycentric grid, is as dense across a long thin triangle as
// along it; over shifts spread evenly, a triangle gets area / spacing^2 points on average, however
// small it is.
std::vector<Eigen::Vector3d> latticeSamples(const std::array<double, 3>& lengths, double spacing,
                                            const Eigen::Vector2d& shift) {
  std::vector<Eigen::Vector3d> samples;
  const int longest = int(std::max_element(lengths.begin(), lengths.end()) - lengths.begin());
  // Corners a, b on the longest edge, c opposite; a at the origin, b on the x axis.
  const int a = longest, b = (longest + 1) % 3, c = (longest + 2) % 3;
  const double ab = lengths[std::size_t(a)], bc = lengths[std::size_t(b)],
               ca = lengths[std::size_t(c)];
  if (!(ab > 0.0) || !(spacing > 0.0)) return samples;
  const double cx = (ab * ab + ca * ca - bc * bc) / (2.0 * ab);
  const double cy = std::sqrt(std::max(0.0, ca * ca - cx * cx));
  const double area = 0.5 * ab * cy;
  if (!(area > 0.0)) return samples;
  for (double y = shift.y() * spacing; y < cy; y += spacing)
    for (double x = shift.x() * spacing; x < ab; x += spacing) {
      // Barycentric weights from the signed areas opposite each corner.
      const double wc = 0.5 * ab * y / area;
      const double wb = 0.5 * (x * cy - y * cx) / area;
      const double wa = 1.0 - wb - wc;
      if (wa <= 0.0 || wb <= 0.0 || wc <= 0.0) continue;
      Eigen::Vector3d point;
      point[a] = wa;
      point[b] = wb;
      point[c] = wc;
      samples.push_back(point);
    }
  return samples;
}

// The surface's faces in the flat metric `flatLengths` (per edge): per face of the model, the
// length of its edge from corner k to corner k + 1, and its area.
struct FlatFaces {
  std::vector<std::array<double, 3>> lengths;
  std::vector<double> areas;
};

FlatFaces flatFaces(const TriMesh& surface, const Eigen::VectorXd& flatLengths,
                    const SplineModel& model) {
  FlatFaces flat;
  flat.lengths.resize(surface.n_faces());
  flat.areas.resize(surface.n_faces());
  for (const auto f : surface.faces()) {
    const auto& corners = model.surfaceFaces[std::size_t(f.idx())];
    auto& l = flat.lengths[std::size_t(f.idx())];
    for (const auto h : surface.fh_range(f)) {
      const auto k =
          std::find(corners.begin(), corners.end(), surface.from_vertex_handle(h).idx()) -
          corners.begin();
      l[std::size_t(k)] = flatLengths[surface.edge_handle(h).idx()];
    }
    flat.areas[std::size_t(f.idx())] = 0.25 * fourTimesArea(l[0], l[1], l[2]);
  }
  return flat;
}

// Points inside the faces and their 3D positions appended to `targets`, so that with the
// vertices there is about one sample per `faceSpacing[f]`^2 of flat area in face f; `locate` gives
// each its parameter. Each face takes its share of its corners (one per face around a vertex) as
// samples already there and gets the rest on a square lattice in its flat shape. Counted per face,
// as they were, a scan's faces far apart in flat area, or long and thin, left basis functions
// without samples; counted only where the vertices were fewer than the samples wanted in all, a
// dense scan's vertices were the only samples even where the flat metric spreads them thin.
template <class Locate>
void addFaceSamples(const SplineModel& model, const FlatFaces& flat,
                    const std::vector<double>& faceSpacing, std::vector<int>& sampleFaces,
                    std::vector<Eigen::RowVector3d>& targets, Locate&& locate) {
  std::vector<int> facesAround(std::size_t(model.surfaceVertices.rows()), 0);
  for (const auto& corners : model.surfaceFaces)
    for (const int v : corners) ++facesAround[std::size_t(v)];
  for (std::size_t f = 0; f < model.surfaceFaces.size(); ++f) {
    const auto& corners = model.surfaceFaces[f];
    double vertexShare = 0.0;
    for (const int v : corners) vertexShare += 1.0 / facesAround[std::size_t(v)];
    const double missing = flat.areas[f] / (faceSpacing[f] * faceSpacing[f]) - vertexShare;
    if (!(missing > 0.0)) continue;
    // A face that misses a point or more gets its lattice centred, half a spacing from its
    // sides; a smaller one gets it shifted by the R2 sequence (Roberts 2018), spread evenly over
    // the unit square, so that it has its fraction of a point on average.
    const Eigen::Vector2d shift =
        missing >= 1.0 ? Eigen::Vector2d(0.5, 0.5)
                       : Eigen::Vector2d(std::fmod(0.5 + 0.7548776662466927 * double(f), 1.0),
                                         std::fmod(0.5 + 0.5698402909980532 * double(f), 1.0));
    for (const Eigen::Vector3d& b :
         latticeSamples(flat.lengths[f], std::sqrt(flat.areas[f] / missing), shift)) {
      locate(int(f), b);
      sampleFaces.push_back(int(f));
      targets.push_back(b[0] * model.surfaceVertices.row(corners[0]) +
                        b[1] * model.surfaceVertices.row(corners[1]) +
                        b[2] * model.surfaceVertices.row(corners[2]));
    }
  }
}

// Per surface face, how many times splitCellsAroundCones will halve the cells at its corners
// (`vertexSites`: the vertices on `tmesh`), the most of the three.
std::vector<int> coneSplitLevels(const TMesh& tmesh, const std::vector<FacePoint>& vertexSites,
                                 const std::vector<std::array<int, 3>>& surfaceFaces) {
  TMesh split = tmesh;
  std::vector<FacePoint> sites = vertexSites;
  if (refineAroundCones(split, sites) == 0) return {};
  const auto area = [](const TMeshFace& face) { return face.width * face.height; };
  std::vector<int> faceLevel(surfaceFaces.size(), 0);
  for (std::size_t f = 0; f < surfaceFaces.size(); ++f)
    for (const int v : surfaceFaces[f]) {
      const double ratio = area(tmesh.faces[std::size_t(vertexSites[std::size_t(v)].face)]) /
                           area(split.faces[std::size_t(sites[std::size_t(v)].face)]);
      faceLevel[f] = std::max(faceLevel[f], int(std::lround(0.5 * std::log2(ratio))));
    }
  return faceLevel;
}

Eigen::MatrixX3d toMatrix(const std::vector<Eigen::RowVector3d>& rows) {
  Eigen::MatrixX3d matrix(Eigen::Index(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k) matrix.row(Eigen::Index(k)) = rows[k];
  return matrix;
}

// The T-spline branch: a seamless grid of the flat structure (the lattice's grid on a flat torus,
// the whole-cell rectangle layout with cones).
void buildTSpline(const BuildSplineOptions& s, const Flattening& flattening,
                  SplineSpaceBuild& setup, Stopwatch& clock, const Progress& progress) {
  const TriMesh& surface = flattening.surface();
  std::optional<TorusTMesh> torus;
  std::optional<structure::MotorcycleLayout> layout;
  std::optional<LayoutTMesh> quads;
  if (flattening.layout.hasPeriods) {
    TorusTMeshOptions gridOptions;
    gridOptions.targetCells = s.control;
    if (s.grid > 0.0)
      gridOptions.targetCells = std::max(16, int(std::lround(1.0 / (s.grid * s.grid))));
    torus = torusTMesh(flattening.layout, gridOptions);
    setup.grid.torus = true;
    setup.grid.cellsAlongFirst = torus->cellsAlongFirst;
    setup.grid.cellsAlongSecond = torus->cellsAlongSecond;
    setup.grid.anisotropy = torus->anisotropy;
    setup.grid.anisotropyP99 = torus->anisotropy;
  } else {
    report(progress, "tracing the rectangle layout from " +
                         std::to_string(flattening.layout.cones.size()) + " cones");
    // The field aligned with face 0 first; on symmetric surfaces (polyhedra) its traces can run
    // exactly through cones and other traces' ends, which the floating tracing misses: the field
    // turned by other fractions of a quarter turn moves every trace off them.
    LayoutTMeshOptions quadOptions;
    std::string firstFailure;
    for (const double turn : {0.0, 0.618, 0.236, 0.854}) {
      MotorcycleLayoutOptions traceOptions;
      traceOptions.frameAngle = turn * 0.5 * kPi;
      try {
        layout.emplace(surface, flattening.flatLengths, traceOptions);
        double flatArea = 0.0;
        for (const auto& r : layout->rectangles()) flatArea += r.width() * r.height();
        quadOptions.cellSize =
            s.grid > 0.0 ? s.grid * std::sqrt(flatArea) : std::sqrt(flatArea / double(s.control));
        quads = layoutTMesh(*layout, quadOptions);
        setup.grid.frameAngle = traceOptions.frameAngle;
        setup.grid.frameTurnedBecause = firstFailure;
        break;
      } catch (const SolverError& failure) {
        if (firstFailure.empty()) firstFailure = failure.what();
        layout.reset();
        report(progress, std::string("layout failed (") + failure.what() +
                             "); the cross field turned by another fraction of a quarter turn");
      }
    }
    if (!quads) throw SolverError(firstFailure);
    setup.grid.traces = layout->numTraces();
    setup.grid.rectangles = int(layout->rectangles().size());
    setup.grid.cellSize = quadOptions.cellSize;
    setup.grid.maxRoundingError = quads->maxRoundingError;
    setup.grid.collapsedSegments = quads->collapsedSegments;
    setup.grid.collapsedRectangles = quads->collapsedRectangles;
    setup.grid.quantizationOptimal = quads->quantizationOptimal;
    setup.grid.quantizations = quads->quantizations;
    setup.grid.quantizationSeconds = quads->quantizationSeconds;
    setup.grid.anisotropy = quads->maxAnisotropy;
    setup.grid.anisotropyP99 = quads->anisotropyP99;
  }
  addStageSeconds(setup.stageSeconds, "grid", clock.lap());
  const auto locate = [&](int face, const Eigen::Vector3d& barycentric) {
    if (torus) {
      const Eigen::MatrixXd& uv = flattening.layout.cornerUV;
      const Eigen::Vector2d point =
          barycentric[0] * uv.row(Eigen::Index(3 * face)).transpose() +
          barycentric[1] * uv.row(Eigen::Index(3 * face + 1)).transpose() +
          barycentric[2] * uv.row(Eigen::Index(3 * face + 2)).transpose();
      return gridPoint(*torus, torus->layoutToGrid * point);
    }
    return layoutPoint(*layout, *quads, layout->locate(face, barycentric));
  };
  SplineModel& model = setup.model;
  model.kind = SplineKind::TSpline;
  model.degree = 3;
  model.tmesh = torus ? torus->mesh : quads->mesh;
  setup.grid.extraordinaryPoints = model.tmesh.numExtraordinary();
  copySurface(surface, model);
  const Eigen::Index vertexCount = model.surfaceVertices.rows();
  model.surfaceVertexTMeshPoints.assign(std::size_t(vertexCount), FacePoint{});
  std::vector<Eigen::RowVector3d> targets;
  for (std::size_t f = 0; f < model.surfaceFaces.size(); ++f)
    for (std::size_t k = 0; k < 3; ++k) {
      const int v = model.surfaceFaces[f][k];
      if (model.surfaceVertexTMeshPoints[std::size_t(v)].face >= 0) continue;
      Eigen::Vector3d corner = Eigen::Vector3d::Zero();
      corner[Eigen::Index(k)] = 1.0;
      model.surfaceVertexTMeshPoints[std::size_t(v)] = locate(int(f), corner);
    }
  // Sample k < V is vertex k.
  setup.tmeshSites = model.surfaceVertexTMeshPoints;
  for (Eigen::Index v = 0; v < vertexCount; ++v) targets.push_back(model.surfaceVertices.row(v));
  // About one control point per cell, even over the flat metric, and 4^L times as many where the
  // cells around cones will be split L times.
  const FlatFaces flat = flatFaces(surface, flattening.flatLengths, model);
  const double spacing = std::sqrt(std::accumulate(flat.areas.begin(), flat.areas.end(), 0.0) /
                                   (s.samplesPerControlPoint * model.tmesh.numFaces()));
  std::vector<double> faceSpacing(flat.areas.size(), spacing);
  if (s.denserWhereSplit) {
    const std::vector<int> faceLevel =
        coneSplitLevels(model.tmesh, model.surfaceVertexTMeshPoints, model.surfaceFaces);
    for (std::size_t f = 0; f < faceLevel.size(); ++f)
      faceSpacing[f] = std::ldexp(spacing, -faceLevel[f]);
  }
  addFaceSamples(
      model, flat, faceSpacing, setup.sampleFaces, targets,
      [&](int f, const Eigen::Vector3d& b) { setup.tmeshSites.push_back(locate(f, b)); });
  setup.targets = toMatrix(targets);
  addStageSeconds(setup.stageSeconds, "locate", clock.lap());
}

void buildTriBSpline(const BuildSplineOptions& s, const Flattening& flattening,
                     SplineSpaceBuild& setup, Stopwatch& clock, const Progress& progress) {
  const TriMesh& surface = flattening.surface();
  const int perFace = (s.degree + 1) * (s.degree + 2) / 2;
  // A closed surface of genus g has F = 2 V + 4 g - 4 faces.
  const int genus = analyzeTopology(surface).genus;
  CoarseningOptions coarsening;
  coarsening.separateCones = true;
  coarsening.targetVertices = std::max(4, int((s.control / perFace + 4 - 4 * genus) / 2));
  coarsening.density = s.density;
  report(progress, "coarsening to " + std::to_string(coarsening.targetVertices) + " vertices");
  const CoarseTriangulation coarse = coarsenFlatMetric(surface, flattening.flatLengths, coarsening);
  addStageSeconds(setup.stageSeconds, "coarsen", clock.lap());

  report(progress, std::to_string(coarse.faces.size()) + " domain faces; placing knot clouds");
  SplineModel& model = setup.model;
  model.kind = SplineKind::TriangularBSpline;
  model.domain = domainFromCoarse(coarse);
  const DomainPolish polish = polishDomainMetric(model.domain);
  model.domainVertexSource = coarse.vertices;
  model.degree = s.degree;
  KnotCloudOptions clouds;
  clouds.radiusFraction = s.cloudRadius;
  clouds.seed = s.seed;
  model.knots = placeKnotClouds(model.domain, buildHomeCharts(model.domain), s.degree, clouds);
  addStageSeconds(setup.stageSeconds, "basis", clock.lap());
  copySurface(surface, model);
  for (const auto& location : coarse.fineVertices)
    model.surfaceVertexLocations.push_back({location.face, location.barycentric});
  setup.domainSites = model.surfaceVertexLocations;
  std::vector<Eigen::RowVector3d> targets;
  for (Eigen::Index v = 0; v < model.surfaceVertices.rows(); ++v)
    targets.push_back(model.surfaceVertices.row(v));
  // Each domain face carries perFace basis functions: as many samples per domain face, over the
  // surface faces whose centroids it holds.
  const FlatFaces flat = flatFaces(surface, flattening.flatLengths, model);
  std::vector<int> domainFace(flat.areas.size());
  std::vector<double> domainArea(std::size_t(model.domain.faceCount()), 0.0);
  for (std::size_t f = 0; f < domainFace.size(); ++f) {
    domainFace[f] =
        locateOnCoarse(surface, coarse, int(f), Eigen::Vector3d::Constant(1.0 / 3.0)).face;
    domainArea[std::size_t(domainFace[f])] += flat.areas[f];
  }
  std::vector<double> faceSpacing(flat.areas.size());
  for (std::size_t f = 0; f < domainFace.size(); ++f) {
    const auto d = std::size_t(domainFace[f]);
    faceSpacing[f] = std::sqrt(domainArea[d] / (s.samplesPerControlPoint * perFace));
  }
  addFaceSamples(model, flat, faceSpacing, setup.sampleFaces, targets,
                 [&](int f, const Eigen::Vector3d& b) {
                   const auto location = locateOnCoarse(surface, coarse, f, b);
                   setup.domainSites.push_back({location.face, location.barycentric});
                 });
  setup.targets = toMatrix(targets);
  int cones = 0;
  for (char c : model.domain.cone) cones += c;
  DomainFigures& figures = setup.domain;
  figures.vertices = model.domain.vertexCount();
  figures.faces = model.domain.faceCount();
  figures.cones = cones;
  figures.unremovedVertices = int(coarse.unremovedVertices.size());
  figures.coneSeparatingVertices = coarse.separatingVertices;
  figures.coneSides = coarse.coneSides;
  figures.trackingError = coarse.maxTrackingError;
  figures.flatnessBefore = polish.initialError;
  figures.flatnessAfter = polish.finalError;
  addStageSeconds(setup.stageSeconds, "locate", clock.lap());
}

}  // namespace

void addStageSeconds(StageSeconds& stages, const std::string& name, double seconds) {
  const auto stage = std::find_if(stages.begin(), stages.end(),
                                  [&](const auto& entry) { return entry.first == name; });
  if (stage == stages.end())
    stages.emplace_back(name, seconds);
  else
    stage->second += seconds;
}

SplineSpaceBuild buildSpline(const Flattening& flattening, const BuildSplineOptions& options,
                             const Progress& progress) {
  if (!flattening.converged)
    throw InputError("buildSpline: the surface is not flattened (" + flattening.message + ")");
  SplineSpaceBuild build;
  Stopwatch clock;
  if (options.kind == SpaceKind::TriBSpline)
    buildTriBSpline(options, flattening, build, clock, progress);
  else
    buildTSpline(options, flattening, build, clock, progress);
  return build;
}

void splitCellsAroundCones(SplineSpaceBuild& build) {
  refineAroundCones(build.model.tmesh, build.tmeshSites);
  std::copy_n(build.tmeshSites.begin(), build.model.surfaceVertexTMeshPoints.size(),
              build.model.surfaceVertexTMeshPoints.begin());
}

std::vector<FacePoint> tmeshFitParameters(const SplineSpaceBuild& build) {
  std::vector<FacePoint> parameters;
  parameters.reserve(build.tmeshSites.size());
  for (const auto& p : build.tmeshSites) parameters.push_back({p.face, p.position});
  return parameters;
}

ControlPointFit fitControlPoints(SplineSpaceBuild& build, const SurfaceFitOptions& options,
                                 const Progress& progress) {
  ControlPointFit result;
  Stopwatch clock;
  SplineModel& model = build.model;
  SurfaceFitResult fit;
  if (model.kind == SplineKind::TriangularBSpline) {
    const TriBSplineSpace space(model.domain, model.knots);
    const TriBSplineFitSpace fitSpace(space);
    addStageSeconds(result.stageSeconds, "basis", clock.lap());
    std::vector<FacePoint> parameters;
    parameters.reserve(build.domainSites.size());
    for (const auto& p : build.domainSites) parameters.push_back(toFitParameter(space, p));
    report(progress, "fitting " + std::to_string(space.numBasis()) + " control points to " +
                         std::to_string(parameters.size()) + " samples");
    fit = fitSurface(fitSpace, parameters, build.targets, options, progress);
    for (std::size_t v = 0; v < model.surfaceVertexLocations.size(); ++v)
      model.surfaceVertexLocations[v] = toDomainPoint(space, fit.parameters[v]);
  } else {
    report(progress,
           std::to_string(model.tmesh.numFaces()) + " cells; inferring the blending functions");
    splitCellsAroundCones(build);
    const TSplineSpace space(model.tmesh);
    result.missingAnchors = int(space.missingAnchors().size());
    model.weights = Eigen::VectorXd::Ones(space.numBasis());
    const TSplineFitSpace fitSpace(space, model.weights);
    report(progress, "fitting " + std::to_string(space.numBasis()) + " control points to " +
                         std::to_string(build.tmeshSites.size()) + " samples");
    fit = fitSurface(fitSpace, tmeshFitParameters(build), build.targets, options, progress);
    for (std::size_t v = 0; v < model.surfaceVertexTMeshPoints.size(); ++v)
      model.surfaceVertexTMeshPoints[v] = {fit.parameters[v].face, fit.parameters[v].position};
  }
  model.controlPoints = std::move(fit.controlPoints);
  result.rmsError = fit.rmsError;
  result.maxError = fit.maxError;
  result.smoothing = fit.smoothing;
  result.correctionRounds = fit.rounds;
  result.basisWithoutSamples = fit.basisWithoutSamples;
  result.samplesOutside = fit.samplesOutside;
  addStageSeconds(result.stageSeconds, "fit", clock.lap());
  return result;
}

}  // namespace mspline::spline
