// mspline spline: a manifold spline on a mesh, saved as a model file (.msp): the mesh flattened
// (structure/flatten/flatten_surface.h), the spline space built on it and its control points
// fitted to the mesh with fairing and parameter correction (spline/model/build_spline.h).
#include <iostream>
#include <optional>

#include "cli/command.h"
#include "cli/flatten_options.h"
#include "cli/spline_space_json.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/build_spline.h"
#include "mspline/spline/model/quad_layout_flattening.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/subdivide.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::cli {

namespace {

struct SplineArguments {
  std::string mesh;
  std::string output;
  std::string kind = "tribspline";
  int degree = 3;
  int control = 6000;
  double cloudRadius = 0.3;
  double grid = 0.0;
  unsigned seed = 1;
  int minCornerValence = 3;
  spline::SurfaceFitOptions fit;
  FlattenSettings settings;
};

// Adds the build's or fit's stage seconds to the command's (a stage met again adds up).
void addStages(Json& stages, const spline::StageSeconds& seconds) {
  for (const auto& [name, value] : seconds)
    stages[name] = (stages.contains(name) ? stages[name].get<double>() : 0.0) + value;
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
  addFairingOptions(*sub, arguments->fit.smoothing, arguments->fit.correctionRounds);
  addFlattenOptions(*sub, arguments->settings);
  addCornerValenceOption(*sub, arguments->minCornerValence);
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "spline";
    command.files = {arguments->mesh, arguments->output, coneFile(arguments->settings)};
    command.run = [&command, arguments] {
      const SplineArguments& a = *arguments;
      const auto progress = [&](const std::string& line, double) {
        command.stage = line;
        if (!a.settings.quiet) std::cerr << "spline: " << line << std::endl;
      };
      structure::Stopwatch clock;
      Json stages;
      io::LoadedMesh loaded = io::loadMesh(a.mesh);
      stages["load"] = clock.lap();
      const structure::TopologyReport topology = structure::analyzeTopology(*loaded.mesh);
      if (!topology.closed)
        throw structure::InputError(a.mesh + ": spline needs a closed surface; this one has " +
                                    std::to_string(topology.boundaryLoops) + " boundary loops");
      const bool tspline = a.kind == "tspline";
      spline::BuildSplineOptions options;
      options.kind = tspline ? spline::SpaceKind::TSpline : spline::SpaceKind::TriBSpline;
      options.degree = a.degree;
      options.control = a.control;
      options.cloudRadius = a.cloudRadius;
      options.seed = a.seed;
      options.grid = a.grid;
      structure::FlattenOptions flattenOptions = toFlattenOptions(a.settings, a.mesh);
      // A coarse polyhedron is split at its edge midpoints (the same surface) when its vertices
      // are too few for the quad layout's cones.
      std::optional<structure::TriMesh> subdivided;
      int subdivisions = 0;
      if (tspline) {
        const spline::QuadLayoutFlattening quad =
            spline::quadLayoutFlattening(*loaded.mesh, a.minCornerValence, options, flattenOptions);
        flattenOptions = quad.options;
        subdivisions = quad.midpointSubdivisions;
        for (int level = 0; level < subdivisions; ++level)
          subdivided = structure::subdivideMidpoint(subdivided ? *subdivided : *loaded.mesh);
      }
      const structure::TriMesh& mesh = subdivided ? *subdivided : *loaded.mesh;
      const structure::Flattening flattening =
          structure::flattenSurface(mesh, flattenOptions, progress);
      const Json flat = flatteningJson(flattening, flattenOptions, stages, command);
      spline::SplineSpaceBuild build = spline::buildSpline(flattening, options, progress);
      addStages(stages, build.stageSeconds);
      const spline::ControlPointFit fit = spline::fitControlPoints(build, a.fit, progress);
      addStages(stages, fit.stageSeconds);
      const spline::SplineModel& model = build.model;
      clock.lap();
      io::writeSplineModel(a.output, model);
      stages["write"] = clock.lap();

      const double diagonal = structure::boundingBoxDiagonal(model.surfaceVertices);
      double total = 0.0;
      for (const auto& [name, seconds] : stages.items()) total += seconds.get<double>();
      Json report{{"file", a.mesh},
                  {"output", a.output},
                  {"kind", a.kind},
                  {"degree", tspline ? 3 : a.degree},
                  {"control_points", model.controlPoints.rows()},
                  {"midpoint_subdivisions", subdivisions}};
      if (tspline)
        report.update(Json{{"tmesh_faces", model.tmesh.numFaces()},
                           {"t_junctions", model.tmesh.numTJunctions()},
                           {"extraordinary_points", model.tmesh.numExtraordinary()},
                           {"missing_anchors", fit.missingAnchors},
                           {"grid", gridJson(build.grid)}});
      else
        report.update(domainJson(build.domain));
      report.update(Json{{"fit_rms_error", fit.rmsError / diagonal},
                         {"fit_max_error", fit.maxError / diagonal},
                         {"smoothing", fit.smoothing},
                         {"correction_rounds", fit.correctionRounds},
                         {"basis_without_samples", fit.basisWithoutSamples},
                         {"fit_samples", build.targets.rows()},
                         {tspline ? "sites_in_holes" : "sites_at_cones", fit.samplesOutside}});
      Json flatten{{"converged", flat["converged"]},
                   {"max_curvature_error", flat["max_curvature_error"]},
                   {"flips", flat["flips"]},
                   {"cones", flattening.cones.size()},
                   {"cone_placement", flat["cone_placement"]},
                   {"reached_max_cones", flat["reached_max_cones"]}};
      if (tspline) flatten["holonomy"] = flat.contains("holonomy") ? flat["holonomy"] : Json();
      report.update(Json{{"flatten", flatten}, {"seconds", total}, {"stage_seconds", stages}});
      if (command.json) {
        printJson(report);
      } else {
        std::cout << model.controlPoints.rows() << " control points on "
                  << (tspline ? model.tmesh.numFaces() : model.domain.faceCount())
                  << (tspline ? " cells (" : " domain faces (")
                  << (tspline ? model.tmesh.numExtraordinary() : build.domain.cones)
                  << (tspline ? " extraordinary points)" : " cones)") << ", fit error rms "
                  << fit.rmsError / diagonal << " max " << fit.maxError / diagonal
                  << " of the diagonal\nwrote " << a.output << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
