// mspline export: the evaluated surface of a spline model as a triangle mesh.
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_pipeline.h"
#include "io/read_mesh.h"
#include "io/spline_model_file.h"
#include "io/write_mesh.h"
#include "spline/tessellate.h"
#include "spline/tri_bspline.h"
#include "structure/errors.h"

namespace mspline::cli {

namespace {

struct ExportArguments {
  std::string model;
  std::string output;
  int resolution = 8;
};

}  // namespace

void addExportCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<ExportArguments>();
  auto* sub = app.add_subcommand(
      "export",
      "Writes the surface of a spline model as a watertight triangle mesh (OBJ, PLY or STL): "
      "every domain face sampled on a regular grid, shared sides sampled once.");
  sub->add_option("MODEL", arguments->model, "Model file (.msp)")->required();
  sub->add_option("-o,--output", arguments->output, "Mesh to write (.obj, .ply, .stl)")->required();
  sub->add_option("--resolution", arguments->resolution,
                  "Samples along each domain side (default 8)")
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
