// mspline export: the evaluated surface of a spline model as a triangle mesh, with normals and
// chart coordinates, and optionally its control net, an error map of a scan and a picture
// (io/export_model.h); its quality (spline/quality/surface_quality.h) in the report.
#include <iostream>

#include "cli/command.h"
#include "mspline/io/export_model.h"
#include "mspline/io/quality_report.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/structure/core/stopwatch.h"

namespace mspline::cli {

namespace {

struct ExportArguments {
  std::string model;
  std::string output;
  int resolution = 8;
  double tolerance = 0.0;
  std::string controlNet;
  std::vector<std::string> errorMap;  // SCAN OUT.ply
  std::string png;
  bool markDefects = false;
  double creaseDegrees = 30.0;
};

Json controlNetReport(const std::string& path, const spline::ExportResult& exported) {
  const spline::ExportControlNet& net = exported.controlNet;
  Json entry{{"output", path}, {"points", net.points.size()}, {"lines", net.lines.size()}};
  if (exported.kind == spline::SplineKind::TriangularBSpline) {
    entry["faces"] = net.domainFaces;
  } else if (exported.kind == spline::SplineKind::TSpline) {
    entry["missing_anchors"] = net.missingAnchors;
    entry["edges_skipped"] = net.edgesSkipped;
    entry["note"] = "vertices without a blending function are left out, with their edges";
  }
  return entry;
}

Json errorMapReport(const io::ExportFileOptions& options, const io::ScanErrors& errors) {
  return {{"scan", options.scan},
          {"output", options.errorMap},
          {"vertices", errors.vertices},
          {"rms", errors.rms},
          {"max", errors.max},
          {"max_absolute", errors.maxAbsolute},
          {"color_scale", errors.colorScale},
          {"note",
           "rms, max relative to the scan's bounding-box diagonal; colors blue (0), white, "
           "red (color_scale, the 99th percentile, and above)"}};
}

int runExport(const ExportArguments& a, const Command& command) {
  io::ExportFileOptions options;
  options.output = a.output;
  options.surface.resolution = a.resolution;
  options.surface.tolerance = a.tolerance;
  options.controlNet = a.controlNet;
  if (!a.errorMap.empty()) {
    options.scan = a.errorMap[0];
    options.errorMap = a.errorMap[1];
  }
  options.png = a.png;
  options.markDefects = a.markDefects;
  options.creaseDegrees = a.creaseDegrees;
  // Refuse bad output names before reading the model.
  io::checkExportFiles(options);
  structure::Stopwatch clock;
  const spline::SplineModel model = io::readSplineModel(a.model);
  const io::ExportFileResult result = io::exportModel(model, a.model, options);
  spline::QualityOptions qualityOptions;
  qualityOptions.name = a.model;
  const spline::SurfaceQuality quality = spline::measureQuality(model, nullptr, qualityOptions);
  const spline::ExportResult& exported = result.surface;
  const spline::ModelTessellation& surface = exported.surface;

  Json report{{"file", a.model}, {"kind", exported.kindName}, {"output", a.output}};
  report["resolution"] = exported.resolution;
  if (a.tolerance > 0.0) {
    report["tolerance"] = a.tolerance;
    report["chord_error_estimate"] = exported.chordErrorEstimate;
    report["tolerance_met"] = exported.toleranceMet;
  }
  report["vertices"] = surface.mesh.positions.size();
  report["faces"] = surface.mesh.faces.size();
  report["trimmed_faces"] = exported.trimmedFaces;
  report["normals"] = surface.normals.size();
  std::string note;  // appended to the human-readable summary
  for (const spline::TessellationFigure& figure : surface.report) {
    if (figure.count)
      report[figure.name] = std::int64_t(figure.value);
    else
      report[figure.name] = figure.value;
    if (exported.kind == spline::SplineKind::TSpline && figure.name == "hole_samples" &&
        figure.value > 0)
      note = ", " + std::to_string(std::int64_t(figure.value)) + " samples closing holes";
  }
  if (!a.controlNet.empty()) report["control_net"] = controlNetReport(a.controlNet, exported);
  if (!a.errorMap.empty()) report["error_map"] = errorMapReport(options, result.scanErrors);
  if (!a.png.empty()) report["png"] = a.png;
  if (!a.png.empty() && a.markDefects) report["marked_faces"] = result.markedFaces;
  report["quality"] = Json::parse(io::qualityJson(quality));
  report["seconds"] = clock.lap();
  if (command.json) {
    printJson(report);
  } else {
    std::cout << "wrote " << a.output << " (" << surface.mesh.faces.size() << " triangles" << note
              << ", resolution " << exported.resolution << ")" << std::endl;
    if (!a.errorMap.empty())
      std::cout << "error map " << a.errorMap[1] << ": rms " << result.scanErrors.rms << ", max "
                << result.scanErrors.max << " of the scan's diagonal" << std::endl;
    if (!a.png.empty() && a.markDefects)
      std::cout << "marked " << result.markedFaces << " triangles at creases and folds in " << a.png
                << std::endl;
    std::cout << "quality: " << io::qualitySummary(quality) << std::endl;
  }
  return int(kExitSuccess);
}

}  // namespace

void addExportCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<ExportArguments>();
  auto* sub = app.add_subcommand(
      "export",
      "Writes the surface of a spline model as a watertight triangle mesh (OBJ, PLY or STL) with "
      "a unit normal per vertex (OBJ vn, PLY nx ny nz; STL has facet normals) and, in OBJ, each "
      "vertex's chart coordinates (vt): every domain face sampled on a regular grid, shared "
      "sides sampled once. For a T-spline, every T-mesh edge gets R segments and every face an "
      "R x R grid inside, stitched to faces' T-junctions; extraordinary points are sampled on "
      "their cap patches.");
  sub->add_option("MODEL", arguments->model, "Model file (.msp)")->required();
  sub->add_option("-o,--output", arguments->output, "Mesh to write (.obj, .ply, .stl)")->required();
  auto* resolution = sub->add_option("--resolution", arguments->resolution,
                                     "Segments along each domain side or T-mesh edge (default 8)")
                         ->check(CLI::Range(1, 1000));
  sub->add_option("--tolerance", arguments->tolerance,
                  "Instead of --resolution: the smallest resolution whose chord error estimate "
                  "h^2 max|x''| / 8 (h the longest grid edge of a face, x'' the second "
                  "derivatives at a few points of it) is at most T times the model's "
                  "bounding-box diagonal (resolution at most 256)")
      ->check(CLI::PositiveNumber)
      ->excludes(resolution);
  sub->add_option("--control-net", arguments->controlNet,
                  "Also write the control net as OBJ points and `l` lines");
  sub->add_option("--error-map", arguments->errorMap,
                  "SCAN OUT.ply: the scan with its vertices colored by their distance to the "
                  "exported surface")
      ->expected(2);
  auto* png =
      sub->add_option("--png", arguments->png, "Also write a shaded picture of the surface (PNG)");
  sub->add_flag("--mark-defects", arguments->markDefects,
                "In the --png picture, draw in red the triangles at a crease or fold: those with "
                "a neighbour whose normal differs by more than --crease-degrees")
      ->needs(png);
  sub->add_option("--crease-degrees", arguments->creaseDegrees,
                  "The angle between neighbouring triangles' normals above which --mark-defects "
                  "marks them (default 30, at the export resolution)")
      ->check(CLI::Range(0.0, 180.0));
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "export";
    command.files = {arguments->model, arguments->output, arguments->controlNet, arguments->png};
    command.files.insert(command.files.end(), arguments->errorMap.begin(),
                         arguments->errorMap.end());
    command.run = [&command, arguments] { return runExport(*arguments, command); };
  });
}

}  // namespace mspline::cli
