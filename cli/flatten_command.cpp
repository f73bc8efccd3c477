// mspline flatten: discrete Ricci flow to a flat metric with cone singularities, laid out in the
// plane with per-corner UVs.
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_options.h"
#include "mspline/io/atomic_file.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/read_mesh.h"
#include "mspline/io/write_mesh.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/picture/layout_svg.h"

namespace mspline::cli {

namespace {

using namespace structure;

struct FlattenArguments {
  std::string mesh;
  std::string output;
  FlattenSettings settings;
  std::string svg;
  bool cover = false;
};

}  // namespace

void addFlattenCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<FlattenArguments>();
  auto* sub = app.add_subcommand(
      "flatten",
      "Discrete Ricci flow (Newton's method on the convex Ricci energy): a flat metric with cone "
      "singularities, laid out in the plane; writes the mesh with per-corner UVs. Exits 3 when "
      "the flow does not converge.");
  sub->add_option("MESH", arguments->mesh, "Mesh file (must pass validation)")->required();
  sub->add_option("-o,--output", arguments->output, "Mesh with per-corner UVs (.obj)")->required();
  addFlattenOptions(*sub, arguments->settings);
  sub->add_option("--svg", arguments->svg, "Also write a picture of the layout");
  sub->add_flag("--cover", arguments->cover,
                "With --svg on a flat torus: draw 3 x 3 copies of the universal cover");
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "flatten";
    command.files = {arguments->mesh, arguments->output, coneFile(arguments->settings),
                     arguments->svg};
    command.run = [&command, arguments] {
      const FlattenArguments& a = *arguments;
      if (io::meshFormatFromPath(a.output) != io::MeshFormat::Obj)
        throw InputError(a.output + ": flatten writes per-corner UVs, which only OBJ holds");
      const Progress progress = progressLines(command, a.settings.quiet);
      Stopwatch clock;
      Json stages;
      io::LoadedMesh loaded = io::loadMesh(a.mesh);
      const TriMesh& mesh = *loaded.mesh;
      stages["load"] = clock.lap();
      const FlattenOptions options = toFlattenOptions(a.settings, a.mesh);
      const Flattening flat = flattenSurface(mesh, options, progress);
      Json report = flatteningJson(flat, options, stages, command);
      const TriMesh& surface = flat.surface();
      const FlatLayout& layout = flat.layout;
      clock.lap();
      io::writeMesh(a.output, soupWithCornerUVs(surface, layout, a.mesh));
      if (!a.svg.empty()) {
        LayoutSvgOptions svgOptions;
        svgOptions.coverRadius = a.cover ? 1 : 0;
        const std::string picture = layoutSvg(surface, layout, svgOptions);
        io::writeFileAtomically(a.svg, [&](std::ostream& out) { out << picture; });
      }
      stages["write"] = clock.lap();

      double total = 0.0;
      for (const auto& [name, seconds] : stages.items()) total += seconds.get<double>();
      report["seconds"] = total;
      report["stage_seconds"] = stages;
      report["output"] = a.output;
      if (command.json) {
        printJson(report);
      } else {
        std::cout << "converged in " << flat.flow.iterations
                  << " Newton steps, max curvature error " << flat.flow.maxCurvatureError << ", "
                  << flat.cones.size() << " cones, " << flat.flips << " intrinsic flips, "
                  << layout.flippedTriangles << " flipped triangles, " << total << " s\nwrote "
                  << a.output << (a.svg.empty() ? "" : " and " + a.svg) << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
