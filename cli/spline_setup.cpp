#include "cli/spline_setup.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "mspline/spline/tspline/layout_tmesh.h"
#include "mspline/spline/tspline/torus_tmesh.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/structure/layout/coarse_triangulation.h"
#include "mspline/structure/layout/motorcycle_layout.h"

namespace mspline::cli {

namespace {

using namespace structure;

// Set-up may run several times (adaptive refinement of a domain): stage times add up.
void addStage(Json& stages, const char* name, double seconds) {
  stages[name] = (stages.contains(name) ? stages[name].get<double>() : 0.0) + seconds;
}

// The surface mesh as the model stores it.
void copySurface(const TriMesh& surface, spline::SplineModel& model) {
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

// Interior points of a barycentric grid with enough intervals per side for `perTriangle` points.
std::vector<Eigen::Vector3d> barycentricSamples(int perTriangle) {
  std::vector<Eigen::Vector3d> samples;
  if (perTriangle <= 0) return samples;
  const int steps = int(std::ceil((std::sqrt(8.0 * perTriangle + 1.0) - 1.0) / 2.0)) + 2;
  for (int i = 1; i < steps; ++i)
    for (int j = 1; i + j < steps; ++j)
      samples.emplace_back(double(steps - i - j) / steps, double(i) / steps, double(j) / steps);
  return samples;
}

// Points inside every face (enough for the wanted samples per basis function) and their 3D
// positions appended to `targets`; `locate` gives each its parameter.
template <class Locate>
void addFaceSamples(const spline::SplineModel& model, int numBasis, double perBasis,
                    std::vector<int>& sampleFaces, std::vector<Eigen::RowVector3d>& targets,
                    Locate&& locate) {
  const double faces = double(model.surfaceFaces.size());
  const auto inside = barycentricSamples(
      int(std::ceil((perBasis * numBasis - double(model.surfaceVertices.rows())) / faces)));
  for (std::size_t f = 0; f < model.surfaceFaces.size(); ++f) {
    const auto& corners = model.surfaceFaces[f];
    for (const Eigen::Vector3d& b : inside) {
      locate(int(f), b);
      sampleFaces.push_back(int(f));
      targets.push_back(b[0] * model.surfaceVertices.row(corners[0]) +
                        b[1] * model.surfaceVertices.row(corners[1]) +
                        b[2] * model.surfaceVertices.row(corners[2]));
    }
  }
}

Eigen::MatrixX3d toMatrix(const std::vector<Eigen::RowVector3d>& rows) {
  Eigen::MatrixX3d matrix(Eigen::Index(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k) matrix.row(Eigen::Index(k)) = rows[k];
  return matrix;
}

// The T-spline branch: a seamless grid of the flat structure (the lattice's grid on a flat torus,
// the whole-cell rectangle layout with cones).
void setUpTSpline(const SplineSetupSettings& s, const Flattening& flattening, SplineSetup& setup,
                  Json& stages, Stopwatch& clock,
                  const std::function<void(const std::string&)>& progress) {
  const TriMesh& surface = flattening.surface();
  std::optional<spline::TorusTMesh> torus;
  std::optional<structure::MotorcycleLayout> layout;
  std::optional<spline::LayoutTMesh> quads;
  if (flattening.layout.hasPeriods) {
    spline::TorusTMeshOptions gridOptions;
    gridOptions.targetCells = s.control;
    if (s.grid > 0.0)
      gridOptions.targetCells = std::max(16, int(std::lround(1.0 / (s.grid * s.grid))));
    torus = spline::torusTMesh(flattening.layout, gridOptions);
    setup.report = {{"layout", "torus lattice"},
                    {"cells", {torus->cellsAlongFirst, torus->cellsAlongSecond}},
                    {"anisotropy", torus->anisotropy}};
  } else {
    progress("tracing the rectangle layout from " + std::to_string(flattening.layout.cones.size()) +
             " cones");
    layout.emplace(surface, flattening.flatLengths);
    double flatArea = 0.0;
    for (const auto& r : layout->rectangles()) flatArea += r.width() * r.height();
    spline::LayoutTMeshOptions quadOptions;
    quadOptions.cellSize =
        s.grid > 0.0 ? s.grid * std::sqrt(flatArea) : std::sqrt(flatArea / double(s.control));
    quads = spline::layoutTMesh(*layout, quadOptions);
    setup.report = {{"layout", "motorcycle graph"},
                    {"traces", layout->numTraces()},
                    {"rectangles", layout->rectangles().size()},
                    {"cell_size", quadOptions.cellSize},
                    {"max_rounding_error", quads->maxRoundingError},
                    {"anisotropy", quads->maxAnisotropy}};
  }
  addStage(stages, "grid", clock.lap());
  const auto locate = [&](int face, const Eigen::Vector3d& barycentric) {
    if (torus) {
      const Eigen::MatrixXd& uv = flattening.layout.cornerUV;
      const Eigen::Vector2d point =
          barycentric[0] * uv.row(Eigen::Index(3 * face)).transpose() +
          barycentric[1] * uv.row(Eigen::Index(3 * face + 1)).transpose() +
          barycentric[2] * uv.row(Eigen::Index(3 * face + 2)).transpose();
      return spline::gridPoint(*torus, torus->layoutToGrid * point);
    }
    return spline::layoutPoint(*layout, *quads, layout->locate(face, barycentric));
  };
  spline::SplineModel& model = setup.model;
  model.kind = spline::SplineKind::TSpline;
  model.degree = 3;
  model.tmesh = torus ? torus->mesh : quads->mesh;
  copySurface(surface, model);
  const Eigen::Index vertexCount = model.surfaceVertices.rows();
  model.surfaceVertexTMeshPoints.assign(std::size_t(vertexCount), spline::TMeshPoint{});
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
  // About one control point per cell.
  addFaceSamples(
      model, model.tmesh.numFaces(), s.samplesPerControlPoint, setup.sampleFaces, targets,
      [&](int f, const Eigen::Vector3d& b) { setup.tmeshSites.push_back(locate(f, b)); });
  setup.targets = toMatrix(targets);
  addStage(stages, "locate", clock.lap());
}

void setUpTriBSpline(const SplineSetupSettings& s, const Flattening& flattening, int genus,
                     SplineSetup& setup, Json& stages, Stopwatch& clock,
                     const std::function<void(const std::string&)>& progress) {
  const TriMesh& surface = flattening.surface();
  const int perFace = (s.degree + 1) * (s.degree + 2) / 2;
  // A closed surface of genus g has F = 2 V + 4 g - 4 faces.
  CoarseningOptions coarsening;
  coarsening.separateCones = true;
  coarsening.targetVertices = std::max(4, int((s.control / perFace + 4 - 4 * genus) / 2));
  coarsening.density = s.density;
  progress("coarsening to " + std::to_string(coarsening.targetVertices) + " vertices");
  const CoarseTriangulation coarse = coarsenFlatMetric(surface, flattening.flatLengths, coarsening);
  addStage(stages, "coarsen", clock.lap());

  progress(std::to_string(coarse.faces.size()) + " domain faces; placing knot clouds");
  spline::SplineModel& model = setup.model;
  model.kind = spline::SplineKind::TriangularBSpline;
  model.domain = spline::domainFromCoarse(coarse);
  const spline::DomainPolish polish = spline::polishDomainMetric(model.domain);
  model.domainVertexSource = coarse.vertices;
  model.degree = s.degree;
  spline::KnotCloudOptions clouds;
  clouds.radiusFraction = s.cloudRadius;
  clouds.seed = s.seed;
  model.knots = spline::placeKnotClouds(model.domain, spline::buildHomeCharts(model.domain),
                                        s.degree, clouds);
  addStage(stages, "basis", clock.lap());
  copySurface(surface, model);
  for (const auto& location : coarse.fineVertices)
    model.surfaceVertexLocations.push_back({location.face, location.barycentric});
  setup.domainSites = model.surfaceVertexLocations;
  std::vector<Eigen::RowVector3d> targets;
  for (Eigen::Index v = 0; v < model.surfaceVertices.rows(); ++v)
    targets.push_back(model.surfaceVertices.row(v));
  addFaceSamples(model, perFace * model.domain.faceCount(), s.samplesPerControlPoint,
                 setup.sampleFaces, targets, [&](int f, const Eigen::Vector3d& b) {
                   const auto location = locateOnCoarse(surface, coarse, f, b);
                   setup.domainSites.push_back({location.face, location.barycentric});
                 });
  setup.targets = toMatrix(targets);
  int cones = 0;
  for (char c : model.domain.cone) cones += c;
  setup.report = {
      {"domain_vertices", model.domain.vertexCount()},
      {"domain_faces", model.domain.faceCount()},
      {"cones", cones},
      {"unremoved_vertices", coarse.unremovedVertices.size()},
      {"cone_separating_vertices", coarse.separatingVertices},
      {"cone_sides", coarse.coneSides},
      {"tracking_error", coarse.maxTrackingError},
      {"domain_flatness", {{"before", polish.initialError}, {"after", polish.finalError}}}};
  addStage(stages, "locate", clock.lap());
}

}  // namespace

double boxDiagonal(const Eigen::MatrixX3d& points) {
  return (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
}

SplineSetup setUpSpline(const SplineSetupSettings& settings, const Flattening& flattening,
                        int genus, Json& stages, Stopwatch& clock,
                        const std::function<void(const std::string&)>& progress) {
  SplineSetup setup;
  if (settings.kind == "tribspline")
    setUpTriBSpline(settings, flattening, genus, setup, stages, clock, progress);
  else
    setUpTSpline(settings, flattening, setup, stages, clock, progress);
  return setup;
}

}  // namespace mspline::cli
