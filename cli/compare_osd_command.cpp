// mspline compare-osd: a T-spline model against OpenSubdiv's Catmull-Clark limit of its control
// net (spline/subd/model_osd_comparison.h). It reports; it does not judge.
#include <iostream>

#include "cli/command.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/subd/model_osd_comparison.h"
#include "mspline/structure/core/stopwatch.h"

namespace mspline::cli {

namespace {

struct CompareOsdArguments {
  std::string model;
  int samples = 10000;
  unsigned seed = 1;
};

}  // namespace

void addCompareOsdCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<CompareOsdArguments>();
  auto* sub = app.add_subcommand(
      "compare-osd",
      "Compares a T-spline model with OpenSubdiv's Catmull-Clark limit of the same control net "
      "(the T-mesh as net, a control point per vertex) at random points of every face: on "
      "regular faces (a uniform bicubic B-spline on both sides) they must agree to rounding, "
      "elsewhere the deviation measures two different surfaces. Deviations are relative to the "
      "control points' bounding-box diagonal. T-meshes with T-junctions are refused (no "
      "Catmull-Clark net). Reports timings too; exits 0 whatever it finds.");
  sub->add_option("MODEL", arguments->model, "T-spline model file (.msp)")->required();
  sub->add_option("--samples", arguments->samples, "Random points, face by face (default 10000)")
      ->check(CLI::Range(1, 100000000));
  sub->add_option("--seed", arguments->seed, "Seed of the random points (default 1)");
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "compare-osd";
    command.files = {arguments->model};
    command.run = [&command, arguments] {
      const CompareOsdArguments& a = *arguments;
      structure::Stopwatch clock;
      const spline::SplineModel model = io::readSplineModel(a.model);
      const double loadSeconds = clock.lap();
      spline::OsdCompareOptions options;
      options.samples = a.samples;
      options.seed = a.seed;
      const spline::ModelOsdComparison result =
          spline::compareWithOpenSubdiv(model, a.model, options);
      const spline::OsdComparison& c = result.comparison;
      const double compareSeconds = clock.lap();
      Json report{{"file", a.model},
                  {"kind", "tspline"},
                  {"tmesh_faces", result.tmeshFaces},
                  {"control_points", result.controlPoints},
                  {"t_junctions", result.tJunctions},
                  {"extraordinary_points", result.extraordinaryPoints},
                  {"regular_faces", c.regularFaces},
                  {"irregular_faces", c.irregularFaces},
                  {"faces_without_surface", c.facesWithoutSurface},
                  {"samples", c.samples},
                  {"regular_samples", c.regularSamples},
                  {"scale", c.scale},
                  {"regular_max_deviation", c.regularMaxDeviation},
                  {"irregular_max_deviation", c.irregularMaxDeviation},
                  {"regular_max_derivative_deviation", c.regularMaxDerivativeDeviation},
                  {"irregular_max_derivative_deviation", c.irregularMaxDerivativeDeviation},
                  {"mspline_points_per_second", c.msplinePointsPerSecond},
                  {"osd_points_per_second", c.osdPointsPerSecond},
                  {"mspline_setup_seconds", c.msplineSetupSeconds},
                  {"osd_setup_seconds", c.osdSetupSeconds},
                  {"seconds", loadSeconds + compareSeconds},
                  {"stage_seconds", {{"load", loadSeconds}, {"compare", compareSeconds}}}};
      if (command.json) {
        printJson(report);
      } else {
        std::cout << c.samples << " samples on " << c.regularFaces << " regular and "
                  << c.irregularFaces << " irregular faces (" << c.facesWithoutSurface
                  << " without surface): deviation " << c.regularMaxDeviation << " (regular), "
                  << c.irregularMaxDeviation << " (irregular) of the diagonal; "
                  << c.msplinePointsPerSecond << " vs " << c.osdPointsPerSecond
                  << " points/s (mspline vs OpenSubdiv)" << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
