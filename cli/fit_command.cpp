// mspline fit: the main job. A spline surface fitted to a scan: the flat structure and the space
// as `spline` builds them, then least squares with fairing, parameter correction and adaptive
// refinement (spline/fitting/surface_fit.h) until the RMS distance is within the tolerance or the control
// point budget is spent; the errors are measured both ways.
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <optional>

#include "cli/command.h"
#include "cli/flatten_options.h"
#include "cli/spline_setup.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/filled_faces.h"
#include "mspline/spline/subd/subd_fit_space.h"
#include "mspline/spline/subd/subd_tessellate.h"
#include "mspline/spline/fitting/surface_fit.h"
#include "mspline/spline/tribspline/tessellate.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/spline/tribspline/tri_bspline_fit_space.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_adaptive_fit.h"
#include "mspline/spline/tspline/tspline_fit_space.h"
#include "mspline/spline/tspline/tspline_tessellate.h"
#include "mspline/structure/mesh/cap_holes.h"
#include "mspline/structure/mesh/closest_point.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::cli {

namespace {

using namespace structure;

struct FitArguments {
  std::string scan;
  std::string output;
  std::string kind = "tspline";
  double tolerance = 1e-3;
  double maxErrorFactor = 10.0;
  int maxControl = 8000;
  int control = 0;
  double smoothing = -1.0;
  int correctionRounds = 3;
  int maxRefinements = 6;
  FlattenSettings settings;
};

// A progress bar on stderr: redrawn in place on a terminal, a line per stage otherwise.
class ProgressBar {
 public:
  explicit ProgressBar(bool quiet) : quiet_(quiet), terminal_(isatty(STDERR_FILENO) != 0) {}
  ~ProgressBar() { finish(); }
  void show(const std::string& stage, double fraction) {
    if (quiet_) return;
    if (!terminal_) {
      if (stage != last_) std::cerr << "fit: " << stage << std::endl;
      last_ = stage;
      return;
    }
    const int width = 30, done = int(std::lround(std::clamp(fraction, 0.0, 1.0) * width));
    std::cerr << "\rfit: [" << std::string(std::size_t(done), '#')
              << std::string(std::size_t(width - done), ' ') << "] " << std::setw(3)
              << int(std::lround(100.0 * fraction)) << "% " << std::left << std::setw(48)
              << stage.substr(0, 48) << std::right << std::flush;
    open_ = true;
  }
  void line(const std::string& text) {
    if (quiet_) return;
    finish();
    std::cerr << "fit: " << text << std::endl;
  }
  void finish() {
    if (open_) std::cerr << std::endl;
    open_ = false;
  }

 private:
  bool quiet_, terminal_, open_ = false;
  std::string last_;
};

std::vector<spline::FitParameter> toFitParameters(const std::vector<spline::TMeshPoint>& points) {
  std::vector<spline::FitParameter> parameters;
  for (const auto& p : points) parameters.push_back({p.face, p.position});
  return parameters;
}

// Distances from points spread over the fitted surface (the vertices of its tessellation, as
// export writes it) to the scan.
struct SurfaceToScan {
  double rms = 0.0, max = 0.0;
  int samples = 0;
};

SurfaceToScan surfaceToScan(const structure::PolygonSoup& surface,
                            const TriangleMeshDistance& scan) {
  SurfaceToScan result;
  result.samples = int(surface.positions.size());
  double squares = 0.0;
  std::vector<Eigen::Vector3d> points;
  for (const auto& p : surface.positions) points.emplace_back(p[0], p[1], p[2]);
  for (const auto& hit : scan.queryAll(points)) {
    squares += hit.distance * hit.distance;
    result.max = std::max(result.max, hit.distance);
  }
  result.rms = points.empty() ? 0.0 : std::sqrt(squares / double(points.size()));
  return result;
}

// Samples on fill patches (their vertices) only keep the surface near the patch where there is no
// scan: they get this weight, and are not measured.
constexpr double kFillWeight = 0.01;

// Per sample of `setup`, its scan vertex or -1 (points inside faces, fill patch vertices), and
// the samples' weights: kFillWeight on fill patches.
std::vector<int> scanSampleVertices(const SplineSetup& setup, const std::vector<char>& scanVertex,
                                    const std::vector<char>& filledFace, Eigen::VectorXd& weights) {
  const std::size_t count = std::size_t(setup.targets.rows());
  std::vector<int> sampleVertex(count, -1);
  weights = Eigen::VectorXd::Ones(Eigen::Index(count));
  for (std::size_t k = 0; k < count; ++k) {
    const bool vertex = k < scanVertex.size();
    const bool filled =
        vertex ? !scanVertex[k] : filledFace[std::size_t(setup.sampleFaces[k - scanVertex.size()])];
    if (filled) weights[Eigen::Index(k)] = kFillWeight;
    if (vertex && !filled) sampleVertex[k] = int(k);
  }
  return sampleVertex;
}

Json roundsJson(const std::vector<spline::TSplineFitRound>& rounds, double diagonal) {
  Json list = Json::array();
  for (const auto& r : rounds)
    list.push_back({{"control_points", r.controlPoints},
                    {"rms_error", r.rmsError / diagonal},
                    {"max_error", r.maxError / diagonal},
                    {"refined_faces", r.splitFaces},
                    {"seconds", r.seconds}});
  return list;
}

}  // namespace

void addFitCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<FitArguments>();
  auto* sub = app.add_subcommand(
      "fit",
      "Fits a spline surface to a scan: closes its holes with fill patches, flattens it, builds "
      "the spline space on its flat structure, solves least squares with a thin-plate fairing "
      "term, corrects the samples' parameters to their closest points and refits, and refines "
      "where the error is above the tolerance, until the RMS distance is within it or the "
      "control point budget is spent. Writes a model file (.msp); export trims the fills away.");
  sub->add_option("SCAN", arguments->scan, "Scan (a mesh that passes validation)")->required();
  sub->add_option("-o,--output", arguments->output, "Model file to write (.msp)")->required();
  sub->add_option("--kind", arguments->kind,
                  "tspline (default: cubic T-spline on a seamless quad grid, refined locally), "
                  "tribspline (manifold triangular B-spline, domain refined adaptively) or subd "
                  "(Catmull-Clark limit surface of the same quad grid, no refinement)")
      ->check(CLI::IsMember({"tspline", "tribspline", "subd"}));
  sub->add_option("--tolerance", arguments->tolerance,
                  "Wanted RMS distance from the scan's vertices to the surface, relative to the "
                  "scan's bounding-box diagonal (default 1e-3); the maximum wanted is 10 times it")
      ->check(CLI::Range(1e-7, 0.5));
  sub->add_option("--max-control", arguments->maxControl, "Control point budget (default 8000)")
      ->check(CLI::Range(50, 10000000));
  sub->add_option("--control", arguments->control,
                  "Control points to start with (default: 3/4 of the budget; subd keeps this "
                  "grid, the T-spline's initial one)")
      ->check(CLI::Range(20, 10000000));
  sub->add_option("--smoothing", arguments->smoothing,
                  "Fairing weight relative to the data term (default: chosen by hold-out "
                  "validation among 1e-1 .. 1e-7)")
      ->check(CLI::Range(0.0, 1e3));
  sub->add_option("--rounds", arguments->correctionRounds,
                  "Parameter correction rounds per fit (default 3)")
      ->check(CLI::Range(0, 50));
  sub->add_option("--max-refinements", arguments->maxRefinements,
                  "Refinement rounds at most (default 6)")
      ->check(CLI::Range(0, 50));
  addFlattenOptions(*sub, arguments->settings, "--flatten-tolerance");
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "fit";
    if (arguments->kind != "tribspline") {
      arguments->settings.quantize = true;
      arguments->settings.maxConeQuarterTurns = 2;
    }
    command.run = [&command, arguments] {
      const FitArguments& a = *arguments;
      ProgressBar bar(a.settings.quiet);
      auto progress = [&](const std::string& line) { bar.line(line); };
      Stopwatch clock, total;
      Json stages;
      io::LoadedMesh loaded = io::loadMesh(a.scan);
      const TriMesh& scan = *loaded.mesh;
      const TopologyReport scanTopology = analyzeTopology(scan);
      // Holes are closed by fill patches: the spline spans them (fairing, no data) and export
      // trims them away again.
      std::optional<CappedSurface> capped;
      if (!scanTopology.closed) {
        progress("closing " + std::to_string(scanTopology.boundaryLoops) + " holes");
        capped = capHoles(scan);
      }
      const TriMesh& mesh = capped ? capped->mesh : scan;
      const TopologyReport topology = capped ? analyzeTopology(mesh) : scanTopology;
      stages["load"] = clock.lap();
      progress(std::to_string(scan.n_vertices()) + " vertices loaded; atlas");
      const FlattenOptions flattenOptions = toFlattenOptions(a.settings, a.scan);
      const Flattening flattening = flattenSurface(
          mesh, flattenOptions, [&](const std::string& line, double) { progress(line); });
      const Json flat = flatteningJson(flattening, flattenOptions, stages, command);
      stages["atlas"] = clock.lap();

      // Per vertex and face of the flattened surface (the mesh, or its common subdivision with
      // the intrinsic triangulation): whether it is the scan's.
      const TriMesh& surface = flattening.surface();
      std::vector<char> scanVertex(surface.n_vertices(), 1), filledFace(surface.n_faces(), 0);
      if (capped) {
        for (std::size_t v = 0; v < scanVertex.size(); ++v)
          scanVertex[v] = v < capped->capVertex.size() && !capped->capVertex[v];
        for (std::size_t f = 0; f < filledFace.size(); ++f)
          filledFace[f] = capped->capFace[std::size_t(
              flattening.overlay ? flattening.overlay->inputFace[f] : int(f))];
      }

      SplineSetupSettings settings;
      settings.kind = a.kind;
      settings.control = a.control > 0 ? a.control : a.maxControl * 3 / 4;
      // Cones kept apart add domain vertices to triangular B-splines: the target shrinks until
      // the budget holds.
      const auto setUpWithinBudget = [&] {
        SplineSetup built =
            setUpSpline(settings, flattening, topology.genus, stages, clock, progress);
        const int perFace = (settings.degree + 1) * (settings.degree + 2) / 2;
        while (a.kind == "tribspline" && perFace * built.model.domain.faceCount() > a.maxControl) {
          settings.control = int(0.98 * settings.control * a.maxControl /
                                 double(perFace * built.model.domain.faceCount()));
          built = setUpSpline(settings, flattening, topology.genus, stages, clock, progress);
        }
        // A quad layout whose rounding had to halve the cells can come out far above the
        // budget: coarser targets, a few times.
        for (int attempt = 0;
             a.kind != "tribspline" && attempt < 3 && built.model.tmesh.numVertices > a.maxControl;
             ++attempt) {
          progress(std::to_string(built.model.tmesh.numVertices) +
                   " control points are over the budget; a coarser grid");
          settings.control =
              int(0.9 * settings.control * a.maxControl / double(built.model.tmesh.numVertices));
          built = setUpSpline(settings, flattening, topology.genus, stages, clock, progress);
        }
        return built;
      };
      SplineSetup setup = setUpWithinBudget();
      Eigen::VectorXd sampleWeights;
      std::vector<int> sampleVertex =
          scanSampleVertices(setup, scanVertex, filledFace, sampleWeights);
      spline::SplineModel& model = setup.model;
      Eigen::MatrixX3d scanPoints(Eigen::Index(scan.n_vertices()), 3);
      for (const auto v : scan.vertices())
        scanPoints.row(v.idx()) << scan.point(v)[0], scan.point(v)[1], scan.point(v)[2];
      const double diagonal = boxDiagonal(scanPoints);

      spline::SurfaceFitOptions fitOptions;
      fitOptions.smoothing = a.smoothing;
      fitOptions.correctionRounds = a.correctionRounds;
      fitOptions.sampleWeights = sampleWeights;
      const auto showFit = [&](const std::string& stage, double fraction) {
        bar.show(stage, fraction);
      };
      spline::SurfaceFitResult fit;
      Json rounds = Json::array();
      std::unique_ptr<spline::FitSpace> finalSpace;
      std::unique_ptr<spline::TSplineSpace> tsplineSpace;
      std::unique_ptr<spline::TriBSplineSpace> triSpace;
      std::unique_ptr<spline::SubdSpace> subdSpace;
      bool reached = false;
      if (a.kind == "tspline") {
        spline::TSplineAdaptiveFitOptions options;
        options.tolerance = a.tolerance * diagonal;
        options.maxErrorFactor = a.maxErrorFactor;
        options.maxControlPoints = a.maxControl;
        options.maxRefinements = a.maxRefinements;
        options.fit = fitOptions;
        spline::TSplineAdaptiveFitResult adaptive = spline::fitTSplineAdaptively(
            model.tmesh, setup.tmeshSites, setup.targets, options, showFit);
        bar.finish();
        model.tmesh = std::move(adaptive.mesh);
        fit = std::move(adaptive.fit);
        reached = adaptive.reachedTolerance;
        rounds = roundsJson(adaptive.rounds, diagonal);
        // Every surface vertex (fill patches' too) on the refined T-mesh: sample k < V is vertex k.
        for (std::size_t v = 0; v < model.surfaceVertexTMeshPoints.size(); ++v)
          model.surfaceVertexTMeshPoints[v] = adaptive.parameters[v];
        model.weights = Eigen::VectorXd::Ones(Eigen::Index(fit.controlPoints.rows()));
        tsplineSpace = std::make_unique<spline::TSplineSpace>(model.tmesh);
      } else if (a.kind == "subd") {
        model.kind = spline::SplineKind::Subdivision;
        subdSpace = std::make_unique<spline::SubdSpace>(model.tmesh);
        finalSpace = std::make_unique<spline::SubdFitSpace>(*subdSpace);
        fit = spline::fitSurface(*finalSpace, toFitParameters(setup.tmeshSites), setup.targets,
                                 fitOptions, showFit);
        bar.finish();
        reached = fit.rmsError <= a.tolerance * diagonal &&
                  fit.maxError <= a.maxErrorFactor * a.tolerance * diagonal;
        for (std::size_t v = 0; v < model.surfaceVertexTMeshPoints.size(); ++v)
          model.surfaceVertexTMeshPoints[v] = {fit.parameters[v].face, fit.parameters[v].position};
        rounds.push_back({{"control_points", fit.controlPoints.rows()},
                          {"rms_error", fit.rmsError / diagonal},
                          {"max_error", fit.maxError / diagonal}});
      } else {
        // Adaptive refinement of the domain: the next domain is coarsened with more vertices
        // where the samples are far from the surface (density (distance / tolerance)^2, at most
        // 64, averaged over the one-ring), with the whole budget.
        for (int round = 0;; ++round) {
          const auto start = std::chrono::steady_clock::now();
          triSpace =
              std::make_unique<spline::TriBSplineSpace>(setup.model.domain, setup.model.knots);
          finalSpace = std::make_unique<spline::TriBSplineFitSpace>(*triSpace);
          std::vector<spline::FitParameter> parameters;
          for (const auto& p : setup.domainSites)
            parameters.push_back(spline::toFitParameter(*triSpace, p));
          const auto roundProgress = [&](const std::string& stage, double fraction) {
            bar.show("round " + std::to_string(round + 1) + ": " + stage, fraction);
          };
          fit =
              spline::fitSurface(*finalSpace, parameters, setup.targets, fitOptions, roundProgress);
          bar.finish();
          reached = fit.rmsError <= a.tolerance * diagonal &&
                    fit.maxError <= a.maxErrorFactor * a.tolerance * diagonal;
          rounds.push_back(
              {{"control_points", fit.controlPoints.rows()},
               {"rms_error", fit.rmsError / diagonal},
               {"max_error", fit.maxError / diagonal},
               {"seconds",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()}});
          if (reached || round >= a.maxRefinements ||
              (round > 0 && settings.control >= a.maxControl))
            break;
          Eigen::VectorXd pointDensity = Eigen::VectorXd::Ones(Eigen::Index(surface.n_vertices()));
          for (std::size_t k = 0; k < sampleVertex.size(); ++k) {
            const double d = fit.distances[Eigen::Index(k)] / (a.tolerance * diagonal);
            if (sampleVertex[k] >= 0 && std::isfinite(d))
              pointDensity[sampleVertex[k]] = std::clamp(d * d, 1.0, 64.0);
          }
          settings.density.setZero(Eigen::Index(surface.n_vertices()));
          for (const auto v : surface.vertices()) {
            double sum = pointDensity[v.idx()];
            int count = 1;
            for (const auto w : surface.vv_range(v)) {
              sum += pointDensity[w.idx()];
              ++count;
            }
            settings.density[v.idx()] = sum / count;
          }
          settings.control = a.maxControl;
          progress("refining the domain where the error is above the tolerance");
          setup = setUpWithinBudget();
          sampleVertex =
              scanSampleVertices(setup, scanVertex, filledFace, fitOptions.sampleWeights);
        }
        for (std::size_t v = 0; v < model.surfaceVertexLocations.size(); ++v)
          model.surfaceVertexLocations[v] = spline::toDomainPoint(*triSpace, fit.parameters[v]);
      }
      model.controlPoints = fit.controlPoints;
      stages["fit"] = clock.lap();

      // Honest errors: the scan's vertices to the surface (their projections), and points all
      // over the surface to the scan.
      progress("measuring the surface against the scan");
      double scanRms = 0.0, scanMax = 0.0;
      int measured = 0;
      for (std::size_t k = 0; k < sampleVertex.size(); ++k) {
        const double d = fit.distances[Eigen::Index(k)];
        if (sampleVertex[k] < 0 || !std::isfinite(d)) continue;
        scanRms += d * d;
        scanMax = std::max(scanMax, d);
        ++measured;
      }
      scanRms = std::sqrt(scanRms / std::max(measured, 1));
      std::vector<std::array<int, 3>> scanFaces;
      for (const auto f : scan.faces()) {
        std::array<int, 3> corners{};
        int k = 0;
        for (const auto v : scan.fv_range(f)) corners[std::size_t(k++)] = v.idx();
        scanFaces.push_back(corners);
      }
      const TriangleMeshDistance scanDistance(scanPoints, scanFaces);
      if (capped) model.surfaceFaceFilled = filledFace;
      structure::PolygonSoup tessellation =
          tsplineSpace
              ? spline::tessellateTSpline(*tsplineSpace, model.controlPoints, model.weights, 4).mesh
          : subdSpace ? spline::tessellateSubd(*subdSpace, model.controlPoints, 4).mesh
                      : spline::tessellate(*triSpace, model.controlPoints, 8).mesh;
      spline::keepFaces(tessellation, spline::facesOverScan(tessellation, model));
      const SurfaceToScan back = surfaceToScan(tessellation, scanDistance);
      stages["measure"] = clock.lap();
      io::writeSplineModel(a.output, model);
      stages["write"] = clock.lap();

      reached = reached && scanRms <= a.tolerance * diagonal &&
                scanMax <= a.maxErrorFactor * a.tolerance * diagonal;
      const bool withinBudget = model.controlPoints.rows() <= a.maxControl;
      if (!withinBudget)
        bar.line("warning: " + std::to_string(model.controlPoints.rows()) +
                 " control points, over the budget of " + std::to_string(a.maxControl) +
                 " (the quad layout needed smaller cells)");
      if (!reached)
        bar.line(
            "warning: the tolerance was not reached (RMS " + std::to_string(scanRms / diagonal) +
            ", max " + std::to_string(scanMax / diagonal) + " of the diagonal, wanted " +
            std::to_string(a.tolerance) + " and " + std::to_string(a.maxErrorFactor * a.tolerance) +
            "); the best model found was written");
      Json report{{"file", a.scan},
                  {"output", a.output},
                  {"kind", a.kind},
                  {"control_points", model.controlPoints.rows()},
                  {"scan_vertices", scanPoints.rows()},
                  {"scan_vertices_measured", measured},
                  {"filled_holes", capped ? int(capped->caps) : 0},
                  {"rms_error", scanRms / diagonal},
                  {"max_error", scanMax / diagonal},
                  {"rms_error_surface_to_scan", back.rms / diagonal},
                  {"max_error_surface_to_scan", back.max / diagonal},
                  {"surface_samples", back.samples},
                  {"tolerance", a.tolerance},
                  {"max_error_wanted", a.maxErrorFactor * a.tolerance},
                  {"reached_tolerance", reached},
                  {"within_budget", withinBudget},
                  {"rounds", rounds.size()},
                  {"correction_rounds", fit.rounds},
                  {"refinement", rounds},
                  {"smoothing", fit.smoothing},
                  {"samples_undefined", fit.samplesOutside},
                  {"rms_error_before_correction", fit.initialRmsError / diagonal},
                  {"space", setup.report},
                  {"flatten",
                   {{"converged", flat["converged"]},
                    {"max_curvature_error", flat["max_curvature_error"]},
                    {"flips", flat["flips"]}}},
                  {"seconds", total.lap()},
                  {"stage_seconds", stages}};
      if (command.json) {
        printJson(report);
      } else {
        std::cout << a.kind << ": " << model.controlPoints.rows()
                  << " control points; scan to surface rms " << scanRms / diagonal << " max "
                  << scanMax / diagonal << ", surface to scan rms " << back.rms / diagonal
                  << " max " << back.max / diagonal << " of the diagonal\nwrote " << a.output
                  << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
