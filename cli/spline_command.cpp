// mspline spline: a manifold spline on a mesh, saved as a model file (.msp). The flat metric
// (as flatten computes it) is coarsened into the domain triangulation; the basis lives in its
// charts, and the control points are fitted to the mesh's vertices.
#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <optional>

#include "cli/command.h"
#include "cli/flatten_pipeline.h"
#include "io/load_mesh.h"
#include "io/spline_model_file.h"
#include "spline/control_fit.h"
#include "spline/layout_tmesh.h"
#include "spline/spline_model.h"
#include "spline/torus_tmesh.h"
#include "spline/tri_bspline.h"
#include "spline/tspline.h"
#include "spline/tspline_fit.h"
#include "structure/coarse_triangulation.h"
#include "structure/errors.h"
#include "structure/motorcycle_layout.h"
#include "structure/topology.h"

namespace mspline::cli {

namespace {

using namespace structure;

struct SplineArguments {
  std::string mesh;
  std::string output;
  std::string kind = "tribspline";
  int degree = 3;
  int control = 6000;
  double cloudRadius = 0.3;
  double grid = 0.0;
  unsigned seed = 1;
  FlattenSettings settings;
};

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

double boxDiagonal(const Eigen::MatrixX3d& points) {
  return (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
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

// The T-spline branch: a seamless grid of the flat structure (the lattice's grid on a flat torus,
// the whole-cell rectangle layout with cones), control points fitted to the mesh.
int buildTSpline(const SplineArguments& a, const TriMesh& surface, const Flattening& flattening,
                 Json& flat, Json& stages, Stopwatch& clock, Command& command,
                 const std::function<void(const std::string&)>& progress) {
  std::optional<spline::TorusTMesh> torus;
  std::optional<structure::MotorcycleLayout> layout;
  std::optional<spline::LayoutTMesh> quads;
  Json gridReport;
  if (flattening.layout.hasPeriods) {
    spline::TorusTMeshOptions gridOptions;
    gridOptions.targetCells = a.control;
    if (a.grid > 0.0)
      gridOptions.targetCells = std::max(16, int(std::lround(1.0 / (a.grid * a.grid))));
    torus = spline::torusTMesh(flattening.layout, gridOptions);
    gridReport = {{"layout", "torus lattice"},
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
        a.grid > 0.0 ? a.grid * std::sqrt(flatArea) : std::sqrt(flatArea / double(a.control));
    quads = spline::layoutTMesh(*layout, quadOptions);
    gridReport = {{"layout", "motorcycle graph"},
                  {"traces", layout->numTraces()},
                  {"rectangles", layout->rectangles().size()},
                  {"cell_size", quadOptions.cellSize},
                  {"max_rounding_error", quads->maxRoundingError},
                  {"anisotropy", quads->maxAnisotropy}};
  }
  stages["grid"] = clock.lap();
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
  spline::SplineModel model;
  model.kind = spline::SplineKind::TSpline;
  model.degree = 3;
  model.tmesh = torus ? torus->mesh : quads->mesh;
  progress(std::to_string(model.tmesh.numFaces()) + " cells; inferring the blending functions");
  const spline::TSplineSpace space(model.tmesh);
  stages["basis"] = clock.lap();
  copySurface(surface, model);
  const Eigen::Index vertexCount = model.surfaceVertices.rows();
  model.surfaceVertexTMeshPoints.assign(std::size_t(vertexCount), spline::TMeshPoint{});
  std::vector<spline::TMeshPoint> sites;
  std::vector<Eigen::RowVector3d> targets;
  for (std::size_t f = 0; f < model.surfaceFaces.size(); ++f)
    for (std::size_t k = 0; k < 3; ++k) {
      const int v = model.surfaceFaces[f][k];
      if (model.surfaceVertexTMeshPoints[std::size_t(v)].face >= 0) continue;
      Eigen::Vector3d corner = Eigen::Vector3d::Zero();
      corner[Eigen::Index(k)] = 1.0;
      model.surfaceVertexTMeshPoints[std::size_t(v)] = locate(int(f), corner);
      sites.push_back(model.surfaceVertexTMeshPoints[std::size_t(v)]);
      targets.push_back(model.surfaceVertices.row(v));
    }
  // Three samples per control point, as for triangular B-splines.
  const auto inside = barycentricSamples(int(std::ceil(
      (3.0 * space.numBasis() - double(vertexCount)) / double(model.surfaceFaces.size()))));
  for (std::size_t f = 0; f < model.surfaceFaces.size(); ++f) {
    const auto& corners = model.surfaceFaces[f];
    for (const Eigen::Vector3d& b : inside) {
      sites.push_back(locate(int(f), b));
      targets.push_back(b[0] * model.surfaceVertices.row(corners[0]) +
                        b[1] * model.surfaceVertices.row(corners[1]) +
                        b[2] * model.surfaceVertices.row(corners[2]));
    }
  }
  stages["locate"] = clock.lap();
  Eigen::MatrixXd targetMatrix(Eigen::Index(targets.size()), 3);
  for (std::size_t k = 0; k < targets.size(); ++k) targetMatrix.row(Eigen::Index(k)) = targets[k];
  progress("fitting " + std::to_string(space.numBasis()) + " control points to " +
           std::to_string(sites.size()) + " samples");
  const spline::TSplineFitResult fit = spline::fitTSplineControlPoints(space, sites, targetMatrix);
  model.controlPoints = fit.controlPoints;
  model.weights = Eigen::VectorXd::Ones(space.numBasis());
  stages["fit"] = clock.lap();
  io::writeSplineModel(a.output, model);
  stages["write"] = clock.lap();

  const double diagonal = boxDiagonal(model.surfaceVertices);
  double total = 0.0;
  for (const auto& [name, seconds] : stages.items()) total += seconds.get<double>();
  const int tJunctions = model.tmesh.numTJunctions(),
            extraordinary = model.tmesh.numExtraordinary();
  Json report{{"file", a.mesh},
              {"output", a.output},
              {"kind", a.kind},
              {"degree", 3},
              {"control_points", space.numBasis()},
              {"tmesh_faces", model.tmesh.numFaces()},
              {"t_junctions", tJunctions},
              {"extraordinary_points", extraordinary},
              {"missing_anchors", space.missingAnchors().size()},
              {"grid", gridReport},
              {"fit_rms_error", fit.rmsError / diagonal},
              {"fit_max_error", fit.maxError / diagonal},
              {"basis_without_samples", fit.basisWithoutSamples},
              {"fit_samples", sites.size()},
              {"sites_in_holes", fit.sitesInHoles},
              {"flatten",
               {{"converged", flat["converged"]},
                {"max_curvature_error", flat["max_curvature_error"]},
                {"flips", flat["flips"]},
                {"holonomy", flat.contains("holonomy") ? flat["holonomy"] : Json()}}},
              {"seconds", total},
              {"stage_seconds", stages}};
  if (command.json) {
    printJson(report);
  } else {
    std::cout << space.numBasis() << " control points on " << model.tmesh.numFaces() << " cells ("
              << extraordinary << " extraordinary points), fit error rms "
              << fit.rmsError / diagonal << " max " << fit.maxError / diagonal
              << " of the diagonal\nwrote " << a.output << std::endl;
  }
  return int(kExitSuccess);
}

}  // namespace

void addSplineCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<SplineArguments>();
  auto* sub = app.add_subcommand(
      "spline",
      "Builds a manifold spline on a closed mesh: flattens it (as flatten does), coarsens the flat "
      "metric into a domain triangulation whose vertices are mesh vertices (every cone among "
      "them), places knot clouds in its charts and fits the control points to the mesh's "
      "vertices; writes a model file (.msp).");
  sub->add_option("MESH", arguments->mesh, "Mesh file (closed; must pass validation)")->required();
  sub->add_option("-o,--output", arguments->output, "Model file to write (.msp)")->required();
  sub->add_option("--kind", arguments->kind,
                  "tribspline (manifold triangular B-spline, default) or tspline (cubic T-spline "
                  "on a seamless quad grid of the flat structure; implies --quantize)")
      ->check(CLI::IsMember({"tribspline", "tspline"}));
  sub->add_option("--grid", arguments->grid,
                  "T-splines: grid cell side as a fraction of the square root of the surface's "
                  "flat area, in (0, 0.5] (default: from --control, about one cell per control "
                  "point)")
      ->check(CLI::Range(1e-4, 0.5));
  sub->add_option("--degree", arguments->degree, "Polynomial degree, 2 to 5 (default 3)")
      ->check(CLI::Range(2, 5));
  sub->add_option("--control", arguments->control,
                  "Control points wanted, about (default 6000): sets the domain's vertex count")
      ->check(CLI::Range(20, 10000000));
  sub->add_option("--cloud-radius", arguments->cloudRadius,
                  "Knot cloud radius as a fraction of the smallest inradius at each vertex, in "
                  "(0, 0.5] (default 0.3)")
      ->check(CLI::Range(1e-3, 0.5));
  sub->add_option("--seed", arguments->seed, "Seed of the knot clouds (default 1)");
  addFlattenOptions(*sub, arguments->settings);
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "spline";
    // T-spline knot lines must survive chart changes: quarter-turn cones and holonomy.
    // Quad grids also need every cone angle to be at least pi (no vertex of valence one).
    if (arguments->kind == "tspline") {
      arguments->settings.quantize = true;
      arguments->settings.maxConeQuarterTurns = 2;
    }
    command.run = [&command, arguments] {
      const SplineArguments& a = *arguments;
      auto progress = [&](const std::string& line) {
        if (!a.settings.quiet) std::cerr << "spline: " << line << std::endl;
      };
      Stopwatch clock;
      Json stages;
      io::LoadedMesh loaded = io::loadMesh(a.mesh);
      const TriMesh& mesh = *loaded.mesh;
      stages["load"] = clock.lap();
      const TopologyReport topology = analyzeTopology(mesh);
      if (!topology.closed)
        throw InputError(a.mesh + ": spline needs a closed surface; this one has " +
                         std::to_string(topology.boundaryLoops) + " boundary loops");
      progress(std::to_string(mesh.n_faces()) + " faces loaded; flattening");
      Json flat;
      const Flattening flattening =
          flattenMesh(mesh, a.mesh, a.settings, command, flat, stages, progress);
      clock.lap();
      const TriMesh& surface = flattening.surface();
      if (a.kind == "tspline")
        return buildTSpline(a, surface, flattening, flat, stages, clock, command, progress);

      const int perFace = (a.degree + 1) * (a.degree + 2) / 2;
      // A closed surface of genus g has F = 2 V + 4 g - 4 faces.
      CoarseningOptions coarsening;
      coarsening.separateCones = true;
      coarsening.targetVertices =
          std::max(4, int((a.control / perFace + 4 - 4 * topology.genus) / 2));
      progress("coarsening to " + std::to_string(coarsening.targetVertices) + " vertices");
      const CoarseTriangulation coarse =
          coarsenFlatMetric(surface, flattening.flatLengths, coarsening);
      stages["coarsen"] = clock.lap();

      progress(std::to_string(coarse.faces.size()) + " domain faces; placing knot clouds");
      spline::SplineModel model;
      model.kind = spline::SplineKind::TriangularBSpline;
      model.domain = spline::domainFromCoarse(coarse);
      const spline::DomainPolish polish = spline::polishDomainMetric(model.domain);
      model.domainVertexSource = coarse.vertices;
      model.degree = a.degree;
      spline::KnotCloudOptions clouds;
      clouds.radiusFraction = a.cloudRadius;
      clouds.seed = a.seed;
      model.knots = spline::placeKnotClouds(model.domain, spline::buildHomeCharts(model.domain),
                                            a.degree, clouds);
      const spline::TriBSplineSpace space(model.domain, model.knots);
      stages["basis"] = clock.lap();

      progress("fitting " + std::to_string(space.numBasis()) + " control points to " +
               std::to_string(surface.n_vertices()) + " vertices");
      copySurface(surface, model);
      for (const auto& location : coarse.fineVertices)
        model.surfaceVertexLocations.push_back({location.face, location.barycentric});
      // Samples: the vertices, and on a coarse mesh points inside its faces too, so that there
      // are three samples per control point and every basis function has some under it.
      std::vector<spline::DomainPoint> sites = model.surfaceVertexLocations;
      std::vector<Eigen::RowVector3d> targets;
      for (Eigen::Index v = 0; v < model.surfaceVertices.rows(); ++v)
        targets.push_back(model.surfaceVertices.row(v));
      const int perTriangle =
          std::max(0, int(std::ceil((3.0 * space.numBasis() - double(surface.n_vertices())) /
                                    double(surface.n_faces()))));
      const auto inside = barycentricSamples(perTriangle);
      for (int f = 0; f < int(surface.n_faces()); ++f) {
        const auto& corners = model.surfaceFaces[std::size_t(f)];
        for (const Eigen::Vector3d& b : inside) {
          const auto location = locateOnCoarse(surface, coarse, f, b);
          sites.push_back({location.face, location.barycentric});
          targets.push_back(b[0] * model.surfaceVertices.row(corners[0]) +
                            b[1] * model.surfaceVertices.row(corners[1]) +
                            b[2] * model.surfaceVertices.row(corners[2]));
        }
      }
      Eigen::MatrixXd targetMatrix(Eigen::Index(targets.size()), 3);
      for (std::size_t k = 0; k < targets.size(); ++k)
        targetMatrix.row(Eigen::Index(k)) = targets[k];
      const spline::ControlFitResult fit = spline::fitControlPoints(space, sites, targetMatrix);
      model.controlPoints = fit.controlPoints;
      stages["fit"] = clock.lap();
      io::writeSplineModel(a.output, model);
      stages["write"] = clock.lap();

      const double diagonal = boxDiagonal(model.surfaceVertices);
      int cones = 0;
      for (char c : model.domain.cone) cones += c;
      double total = 0.0;
      for (const auto& [name, seconds] : stages.items()) total += seconds.get<double>();
      Json report{
          {"file", a.mesh},
          {"output", a.output},
          {"kind", a.kind},
          {"degree", a.degree},
          {"control_points", space.numBasis()},
          {"domain_vertices", model.domain.vertexCount()},
          {"domain_faces", model.domain.faceCount()},
          {"cones", cones},
          {"unremoved_vertices", coarse.unremovedVertices.size()},
          {"cone_separating_vertices", coarse.separatingVertices},
          {"cone_sides", coarse.coneSides},
          {"tracking_error", coarse.maxTrackingError},
          {"domain_flatness", {{"before", polish.initialError}, {"after", polish.finalError}}},
          {"fit_rms_error", fit.rmsError / diagonal},
          {"fit_max_error", fit.maxError / diagonal},
          {"basis_without_samples", fit.basisWithoutSamples},
          {"fit_samples", sites.size()},
          {"sites_at_cones", fit.sitesAtCones},
          {"flatten",
           {{"converged", flat["converged"]},
            {"max_curvature_error", flat["max_curvature_error"]},
            {"flips", flat["flips"]}}},
          {"seconds", total},
          {"stage_seconds", stages}};
      if (command.json) {
        printJson(report);
      } else {
        std::cout << space.numBasis() << " control points on " << model.domain.faceCount()
                  << " domain faces (" << cones << " cones), fit error rms "
                  << fit.rmsError / diagonal << " max " << fit.maxError / diagonal
                  << " of the diagonal\nwrote " << a.output << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
