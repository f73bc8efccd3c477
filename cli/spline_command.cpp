// mspline spline: a manifold spline on a mesh, saved as a model file (.msp). The flat metric
// (as flatten computes it) is coarsened into the domain triangulation; the basis lives in its
// charts, and the control points are fitted to the mesh's vertices.
#include <algorithm>
#include <cmath>
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_pipeline.h"
#include "io/load_mesh.h"
#include "io/spline_model_file.h"
#include "spline/control_fit.h"
#include "spline/spline_model.h"
#include "spline/tri_bspline.h"
#include "structure/coarse_triangulation.h"
#include "structure/errors.h"
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
  unsigned seed = 1;
  FlattenSettings settings;
};

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
  sub->add_option("--kind", arguments->kind, "tribspline (manifold triangular B-spline, default)")
      ->check(CLI::IsMember({"tribspline"}));
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
      const int steps = int(std::ceil((std::sqrt(8.0 * perTriangle + 1.0) - 1.0) / 2.0)) + 2;
      for (int f = 0; perTriangle > 0 && f < int(surface.n_faces()); ++f) {
        const auto& corners = model.surfaceFaces[std::size_t(f)];
        // The interior points of a barycentric grid with `steps` intervals per side.
        for (int i = 1; i < steps; ++i)
          for (int j = 1; i + j < steps; ++j) {
            const Eigen::Vector3d b(double(steps - i - j) / steps, double(i) / steps,
                                    double(j) / steps);
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

      const double diagonal =
          (model.surfaceVertices.colwise().maxCoeff() - model.surfaceVertices.colwise().minCoeff())
              .norm();
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
