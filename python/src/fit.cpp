// mspline.fit and Model.quality: the library's fitting pipeline (spline::fitScan) and its
// measurement (spline::measureQuality, reported as the CLI's `quality` object) on arrays, without
// the GIL, with progress through a Python callable.
#include <optional>
#include <string>
#include <utility>

#include <pybind11/stl.h>

#include "mspline/io/quality_report.h"
#include "mspline/spline/model/fit_scan.h"
#include "mspline/spline/quality/surface_quality.h"
#include "python/src/arrays.h"
#include "python/src/pipelines.h"

namespace mspline::python {

namespace {

// The `quality` object of `mspline fit|check|export --json`, from the one builder the CLI uses.
py::dict qualityDict(const spline::SurfaceQuality& quality) {
  return py::dict(py::module_::import("json").attr("loads")(io::qualityJson(quality)));
}

// The flat keys of `mspline fit --json` (with the 99th percentiles and the diagonal besides).
py::dict errorsDict(const spline::SurfaceQuality& quality) {
  const spline::SurfaceDistances& d = quality.distances;
  py::dict out;
  out["rms_error"] = d.scanToSurface.rms;
  out["p99_error"] = d.scanToSurface.p99;
  out["max_error"] = d.scanToSurface.max;
  out["scan_vertices_measured"] = d.scanToSurface.count;
  out["rms_error_surface_to_scan"] = d.surfaceToScan.rms;
  out["p99_error_surface_to_scan"] = d.surfaceToScan.p99;
  out["max_error_surface_to_scan"] = d.surfaceToScan.max;
  out["surface_samples"] = d.surfaceToScan.count;
  out["diagonal"] = d.diagonal;
  out["folds"] = quality.folds.total();
  return out;
}

py::dict fitReport(const spline::FitResult& result, const spline::FitOptions& options,
                   const Model& model) {
  py::dict report = errorsDict(result.quality);
  report["kind"] = spline::fitKindName(options.kind);
  report["control_points"] = model.model.controlPoints.rows();
  report["filled_holes"] = result.filledHoles;
  report["midpoint_subdivisions"] = result.midpointSubdivisions;
  report["tolerance"] = options.tolerance;
  report["max_error_wanted"] = options.maxErrorFactor * options.tolerance;
  report["reached_tolerance"] = result.reachedTolerance;
  report["within_budget"] = result.withinBudget;
  py::list rounds;
  for (const spline::FitRound& round : result.rounds) {
    py::dict entry;
    entry["control_points"] = round.controlPoints;
    entry["rms_error"] = round.rmsError;
    entry["max_error"] = round.maxError;
    entry["refined_faces"] = round.refinedFaces;
    entry["folds"] = round.folds;
    entry["measured_rms_error"] = round.measuredRms;
    entry["measured_max_error"] = round.measuredMax;
    entry["kept"] = round.kept;
    if (round.repairOf >= 0) {
      entry["repair_of"] = round.repairOf;
      entry["remedy"] = round.remedy;
      entry["parameters_held"] = round.parametersHeld;
    }
    entry["seconds"] = round.seconds;
    rounds.append(entry);
  }
  report["rounds"] = result.rounds.size();
  report["refinement"] = rounds;
  report["correction_rounds"] = result.correctionRounds;
  report["smoothing"] = result.smoothing;
  report["samples_undefined"] = result.samplesUndefined;
  report["rms_error_before_correction"] = result.rmsBeforeCorrection;
  py::dict flatten;
  flatten["converged"] = result.flatten.converged;
  flatten["max_curvature_error"] = result.flatten.maxCurvatureError;
  flatten["flips"] = result.flatten.flips;
  flatten["cones"] = result.flatten.cones;
  flatten["rejected_cone_counts"] = result.flatten.rejectedConeCounts;
  flatten["cone_placement"] = result.flatten.conePlacement;
  flatten["reached_max_cones"] = result.flatten.reachedMaxCones;
  report["flatten"] = flatten;
  report["warnings"] = result.warnings;
  py::dict seconds;
  for (const auto& [stage, value] : result.stageSeconds) seconds[py::str(stage)] = value;
  report["stage_seconds"] = seconds;
  report["quality"] = qualityDict(result.quality);
  return report;
}

Model fit(const py::handle& vertices, const py::handle& faces, const std::string& kind,
          double tolerance, int maxControl, int control, double smoothing, int rounds,
          int maxRefinements, int minCornerValence, const py::object& progress,
          const std::string& name) {
  const structure::PolygonSoup soup = toSoup(vertices, faces, name);
  spline::FitOptions options;
  options.kind = spline::parseFitKind(kind);
  options.tolerance = tolerance;
  options.maxControl = maxControl;
  options.control = control;
  options.smoothing = smoothing;
  options.correctionRounds = rounds;
  options.maxRefinements = maxRefinements;
  options.minCornerValence = minCornerValence;
  options.flatten.name = name;
  const structure::Progress report = progressOf(progress, "fit");
  std::optional<Model> model;
  spline::FitResult result;
  {
    py::gil_scoped_release release;
    const structure::TriMesh scan = validatedMesh(soup);
    result = spline::fitScan(scan, options, report);
    model.emplace(std::move(result.model), name);
  }
  model->fitReport = fitReport(result, options, *model);
  return std::move(*model);
}

py::dict quality(const Model& self, const py::handle& vertices, const py::handle& faces) {
  const structure::PolygonSoup soup = toSoup(vertices, faces, "the scan");
  spline::QualityOptions options;
  options.name = self.name;
  spline::SurfaceQuality quality;
  {
    py::gil_scoped_release release;
    const structure::TriMesh scan = validatedMesh(soup);
    quality = spline::measureQuality(self.model, &scan, options);
  }
  return qualityDict(quality);
}

}  // namespace

void bindFit(py::module_& module, py::class_<Model>& model) {
  const spline::FitOptions defaults;
  module.def(
      "fit", &fit, py::arg("V"), py::arg("F"), py::arg("kind") = spline::fitKindName(defaults.kind),
      py::arg("tolerance") = defaults.tolerance, py::arg("max_control") = defaults.maxControl,
      py::arg("control") = defaults.control, py::arg("smoothing") = defaults.smoothing,
      py::arg("rounds") = defaults.correctionRounds,
      py::arg("max_refinements") = defaults.maxRefinements,
      py::arg("min_corner_valence") = defaults.minCornerValence, py::arg("progress") = py::none(),
      py::arg("name") = "<arrays>",
      "Fits a spline surface to the scan (V, F) as `mspline fit` does (same options, same "
      "control points): kind 'tspline', 'tribspline' or 'subd'; tolerance: wanted RMS "
      "distance relative to the bounding-box diagonal; max_control: control point budget; "
      "control: control points to start with (0: 3/4 of the budget); smoothing: fairing "
      "weight (< 0: chosen by hold-out validation); rounds: parameter correction rounds; "
      "max_refinements: refinement rounds at most; min_corner_valence: tspline and subd, the "
      "smallest valence of a cone's corner in the quad layout (2 or 3); progress: None or a "
      "callable (stage, fraction); name: names the scan in messages. Returns a Model whose "
      "fit_report holds the figures of `mspline fit --json`.");
  model.def("quality", &quality, py::arg("V"), py::arg("F"),
            "The surface's quality against the scan (V, F) the model was fitted to: the `quality` "
            "object of `mspline check --scan --json` as a dict: distances both ways relative to "
            "the bounding-box diagonal (exact closest points), folds, smoothness (dihedral "
            "angles at two resolutions), regularity, seconds.");
}

}  // namespace mspline::python
