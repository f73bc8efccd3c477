// mspline export: the evaluated surface of a spline model as a triangle mesh.
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_pipeline.h"
#include "io/read_mesh.h"
#include "io/spline_model_file.h"
#include "io/write_mesh.h"
#include "spline/tessellate.h"
#include "spline/tri_bspline.h"
#include "spline/tspline_tessellate.h"
#include "structure/errors.h"

namespace mspline::cli {

namespace {

struct ExportArguments {
  std::string model;
  std::string output;
  int resolution = 8;
};

// T-spline models: spline::tessellateTSpline, `resolution` segments per T-mesh edge.
int exportTSpline(const ExportArguments& a, const spline::SplineModel& model, Stopwatch& clock,
                  const Command& command) {
  const spline::TSplineSpace space(model.tmesh);
  if (model.controlPoints.rows() != space.numBasis() || model.controlPoints.cols() != 3)
    throw structure::InputError(a.model + ": the control points do not fit the T-spline");
  spline::TSplineTessellation tessellation;
  try {
    tessellation =
        spline::tessellateTSpline(space, model.controlPoints, model.weights, a.resolution);
  } catch (const structure::InputError& e) {
    throw structure::InputError(a.model + ": " + e.what());
  }
  tessellation.mesh.sourceName = a.output;
  io::writeMesh(a.output, tessellation.mesh);
  const double seconds = clock.lap();
  Json report{{"file", a.model},
              {"kind", "tspline"},
              {"output", a.output},
              {"resolution", a.resolution},
              {"vertices", tessellation.mesh.positions.size()},
              {"faces", tessellation.mesh.faces.size()},
              {"min_denominator", tessellation.minDenominator},
              {"hole_samples", tessellation.holeVertices.size()},
              {"hole_offset", tessellation.holeOffset},
              {"seconds", seconds}};
  if (command.json) {
    printJson(report);
  } else {
    std::cout << "wrote " << a.output << " (" << tessellation.mesh.faces.size() << " triangles";
    if (!tessellation.holeVertices.empty())
      std::cout << ", " << tessellation.holeVertices.size() << " samples closing holes";
    std::cout << ")" << std::endl;
  }
  return int(kExitSuccess);
}

}  // namespace

void addExportCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<ExportArguments>();
  auto* sub = app.add_subcommand(
      "export",
      "Writes the surface of a spline model as a watertight triangle mesh (OBJ, PLY or STL): "
      "every domain face sampled on a regular grid, shared sides sampled once. For a T-spline, "
      "every T-mesh edge gets R segments and every face an R x R grid inside, stitched to "
      "faces' T-junctions; samples at extraordinary points (holes) are the surface's limit "
      "around them.");
  sub->add_option("MODEL", arguments->model, "Model file (.msp)")->required();
  sub->add_option("-o,--output", arguments->output, "Mesh to write (.obj, .ply, .stl)")->required();
  sub->add_option("--resolution", arguments->resolution,
                  "Segments along each domain side or T-mesh edge (default 8)")
      ->check(CLI::Range(1, 1000));
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "export";
    command.run = [&command, arguments] {
      const ExportArguments& a = *arguments;
      // Refuse a bad output name before the work.
      io::meshFormatFromPath(a.output);
      Stopwatch clock;
      const spline::SplineModel model = io::readSplineModel(a.model);
      if (model.kind == spline::SplineKind::TSpline) return exportTSpline(a, model, clock, command);
      const spline::TriBSplineSpace space(model.domain, model.knots);
      if (model.controlPoints.rows() != space.numBasis() || model.controlPoints.cols() != 3)
        throw structure::InputError(a.model + ": the control points do not fit the spline");
      spline::Tessellation tessellation =
          spline::tessellate(space, model.controlPoints, a.resolution);
      tessellation.mesh.sourceName = a.output;
      io::writeMesh(a.output, tessellation.mesh);
      const double seconds = clock.lap();
      Json report{{"file", a.model},
                  {"output", a.output},
                  {"resolution", a.resolution},
                  {"vertices", tessellation.mesh.positions.size()},
                  {"faces", tessellation.mesh.faces.size()},
                  {"min_denominator", tessellation.minDenominator},
                  {"cone_vertices", tessellation.coneVertices},
                  {"seconds", seconds}};
      if (command.json) {
        printJson(report);
      } else {
        std::cout << "wrote " << a.output << " (" << tessellation.mesh.faces.size() << " triangles)"
                  << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
