// mspline spline: a manifold spline on a mesh, saved as a model file (.msp). The flat metric
// (as flatten computes it) is coarsened into the domain triangulation; the basis lives in its
// charts, and the control points are fitted to the mesh's vertices.
#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_options.h"
#include "cli/spline_setup.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/fitting/control_fit.h"
#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/fitting/tspline_fit.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/topology/topology.h"

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

// The T-spline branch: a seamless grid of the flat structure (the lattice's grid on a flat torus,
// the whole-cell rectangle layout with cones), control points fitted to the mesh.
int buildTSpline(const SplineArguments& a, SplineSetup& setup, Json& flat, Json& stages,
                 Stopwatch& clock, Command& command,
                 const std::function<void(const std::string&)>& progress) {
  spline::SplineModel& model = setup.model;
  progress(std::to_string(model.tmesh.numFaces()) + " cells; inferring the blending functions");
  const spline::TSplineSpace space(model.tmesh);
  const std::vector<spline::TMeshPoint>& sites = setup.tmeshSites;
  const Eigen::MatrixXd targetMatrix = setup.targets;
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
              {"grid", setup.report},
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
      const FlattenOptions options = toFlattenOptions(a.settings, a.mesh);
      const Flattening flattening = flattenSurface(
          mesh, options, [&](const std::string& line, double) { progress(line); });
      Json flat = flatteningJson(flattening, options, stages, command);
      clock.lap();
      SplineSetupSettings settings;
      settings.kind = a.kind;
      settings.degree = a.degree;
      settings.control = a.control;
      settings.cloudRadius = a.cloudRadius;
      settings.seed = a.seed;
      settings.grid = a.grid;
      SplineSetup setup =
          setUpSpline(settings, flattening, topology.genus, stages, clock, progress);
      if (a.kind == "tspline")
        return buildTSpline(a, setup, flat, stages, clock, command, progress);
      spline::SplineModel& model = setup.model;
      const spline::TriBSplineSpace space(model.domain, model.knots);
      stages["basis"] = stages["basis"].get<double>() + clock.lap();
      const std::vector<spline::DomainPoint>& sites = setup.domainSites;
      const Eigen::MatrixXd targetMatrix = setup.targets;
      progress("fitting " + std::to_string(space.numBasis()) + " control points to " +
               std::to_string(sites.size()) + " samples");
      const spline::ControlFitResult fit = spline::fitControlPoints(space, sites, targetMatrix);
      model.controlPoints = fit.controlPoints;
      stages["fit"] = clock.lap();
      io::writeSplineModel(a.output, model);
      stages["write"] = clock.lap();

      const double diagonal = boxDiagonal(model.surfaceVertices);
      const int cones = setup.report["cones"];
      double total = 0.0;
      for (const auto& [name, seconds] : stages.items()) total += seconds.get<double>();
      Json report{{"file", a.mesh},
                  {"output", a.output},
                  {"kind", a.kind},
                  {"degree", a.degree},
                  {"control_points", space.numBasis()}};
      report.update(setup.report);
      report.update(Json{{"fit_rms_error", fit.rmsError / diagonal},
                         {"fit_max_error", fit.maxError / diagonal},
                         {"basis_without_samples", fit.basisWithoutSamples},
                         {"fit_samples", sites.size()},
                         {"sites_at_cones", fit.sitesAtCones},
                         {"flatten",
                          {{"converged", flat["converged"]},
                           {"max_curvature_error", flat["max_curvature_error"]},
                           {"flips", flat["flips"]}}},
                         {"seconds", total},
                         {"stage_seconds", stages}});
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
