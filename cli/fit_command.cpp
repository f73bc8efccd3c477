// mspline fit: the main job (spline/model/fit_scan.h) on a scan file: a spline surface fitted to
// it within a tolerance or a control point budget, written as a model file, with the errors both
// ways, the refinement rounds and the figures of the flattening and the space.
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_options.h"
#include "cli/spline_space_json.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/quality_report.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/fit_scan.h"
#include "mspline/structure/core/stopwatch.h"

namespace mspline::cli {

namespace {

using structure::Stopwatch;

struct FitArguments {
  std::string scan;
  std::string output;
  std::string kind = "tspline";
  /// Everything but the kind and the flattening, with the library's defaults.
  spline::FitOptions fit;
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

Json roundsJson(const spline::FitResult& fit, spline::FitKind kind) {
  Json list = Json::array();
  for (const auto& r : fit.rounds) {
    Json round{
        {"control_points", r.controlPoints}, {"rms_error", r.rmsError}, {"max_error", r.maxError}};
    if (kind == spline::FitKind::TSpline) {
      round["refined_faces"] = r.refinedFaces;
      round["folds"] = r.folds;
      round["measured_rms_error"] = r.measuredRms;
      round["measured_max_error"] = r.measuredMax;
      round["kept"] = r.kept;
      if (r.repairOf >= 0) {
        round["repair_of"] = r.repairOf;
        round["remedy"] = r.remedy;
        round["parameters_held"] = r.parametersHeld;
      }
    }
    if (kind != spline::FitKind::Subd) round["seconds"] = r.seconds;
    list.push_back(round);
  }
  return list;
}

Json spaceJson(const spline::FitResult& fit, spline::FitKind kind) {
  if (kind == spline::FitKind::TriBSpline) return domainJson(fit.domain);
  return gridJson(fit.grid);
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
  sub->add_option("--tolerance", arguments->fit.tolerance,
                  "Wanted RMS distance from the scan's vertices to the surface, relative to the "
                  "scan's bounding-box diagonal (default 1e-3); the maximum wanted is 10 times it")
      ->check(CLI::Range(1e-7, 0.5));
  sub->add_option("--max-control", arguments->fit.maxControl, "Control point budget (default 8000)")
      ->check(CLI::Range(50, 10000000));
  sub->add_option("--control", arguments->fit.control,
                  "Control points to start with (default: 3/4 of the budget; subd keeps this "
                  "grid, the T-spline's initial one)")
      ->check(CLI::Range(20, 10000000));
  addFairingOptions(*sub, arguments->fit.smoothing, arguments->fit.correctionRounds);
  sub->add_option("--max-refinements", arguments->fit.maxRefinements,
                  "Refinement rounds at most (default 6)")
      ->check(CLI::Range(0, 50));
  addFlattenOptions(*sub, arguments->settings, "--flatten-tolerance");
  addCornerValenceOption(*sub, arguments->fit.minCornerValence);
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "fit";
    command.files = {arguments->scan, arguments->output, coneFile(arguments->settings)};
    command.run = [&command, arguments] {
      const FitArguments& a = *arguments;
      ProgressBar bar(a.settings.quiet);
      Stopwatch clock, total;
      io::LoadedMesh loaded = io::loadMesh(a.scan);
      const double loadSeconds = clock.lap();
      spline::FitOptions options = a.fit;
      options.kind = spline::parseFitKind(a.kind);
      options.flatten = toFlattenOptions(a.settings, a.scan);
      const spline::FitResult fit =
          spline::fitScan(*loaded.mesh, options, [&](const std::string& stage, double fraction) {
            command.stage = stage;
            if (fraction < 1.0)
              bar.show(stage, fraction);
            else
              bar.line(stage);
          });
      clock.lap();
      io::writeSplineModel(a.output, fit.model);
      Json stages{{"load", loadSeconds}};
      for (const auto& [stage, seconds] : fit.stageSeconds) stages[stage] = seconds;
      stages["write"] = clock.lap();
      for (const auto& warning : fit.warnings) bar.line("warning: " + warning);

      const spline::SurfaceDistances& e = fit.quality.distances;
      Json report{{"file", a.scan},
                  {"output", a.output},
                  {"kind", a.kind},
                  {"control_points", fit.model.controlPoints.rows()},
                  {"scan_vertices", loaded.mesh->n_vertices()},
                  {"scan_vertices_measured", e.scanToSurface.count},
                  {"filled_holes", fit.filledHoles},
                  {"midpoint_subdivisions", fit.midpointSubdivisions},
                  {"rms_error", e.scanToSurface.rms},
                  {"max_error", e.scanToSurface.max},
                  {"rms_error_surface_to_scan", e.surfaceToScan.rms},
                  {"max_error_surface_to_scan", e.surfaceToScan.max},
                  {"surface_samples", e.surfaceToScan.count},
                  {"tolerance", options.tolerance},
                  {"max_error_wanted", options.maxErrorFactor * options.tolerance},
                  {"reached_tolerance", fit.reachedTolerance},
                  {"within_budget", fit.withinBudget},
                  {"max_control", options.maxControl},
                  {"warnings", fit.warnings},
                  {"rounds", fit.rounds.size()},
                  {"correction_rounds", fit.correctionRounds},
                  {"refinement", roundsJson(fit, options.kind)},
                  {"smoothing", fit.smoothing},
                  {"samples_undefined", fit.samplesUndefined},
                  {"rms_error_before_correction", fit.rmsBeforeCorrection},
                  {"space", spaceJson(fit, options.kind)},
                  {"flatten",
                   {{"converged", fit.flatten.converged},
                    {"max_curvature_error", fit.flatten.maxCurvatureError},
                    {"flips", fit.flatten.flips},
                    {"cones", fit.flatten.cones},
                    {"rejected_cone_counts", fit.flatten.rejectedConeCounts},
                    {"cone_placement", fit.flatten.conePlacement},
                    {"reached_max_cones", fit.flatten.reachedMaxCones}}},
                  {"quality", Json::parse(io::qualityJson(fit.quality))},
                  {"seconds", total.lap()},
                  {"stage_seconds", stages}};
      if (command.json) {
        printJson(report);
      } else {
        std::cout << a.kind << ": " << fit.model.controlPoints.rows() << " control points; "
                  << io::qualitySummary(fit.quality) << "\nwrote " << a.output << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
