// mspline picture: PNG pictures of the flat structure, drawn without a GPU: the cut layout, the
// surface with a checkerboard or parallel lines in its flat coordinates, a flat torus' cover.
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_pipeline.h"
#include "io/load_mesh.h"
#include "io/raster_image.h"
#include "io/surface_pictures.h"
#include "structure/errors.h"
#include "structure/topology.h"

namespace mspline::cli {

namespace {

using namespace structure;

struct PictureArguments {
  std::string mesh;
  std::string kind;
  std::string output;
  io::PictureOptions options;
  FlattenSettings settings;
};

bool isPngPath(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  return extension == ".png";
}

}  // namespace

void addPictureCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<PictureArguments>();
  auto* sub = app.add_subcommand(
      "picture",
      "Flattens the surface (as flatten does) and draws a PNG: the cut layout with a "
      "checkerboard (layout), the surface with a checkerboard (checker) or parallel lines (lines) "
      "in its flat coordinates, or 3 x 3 copies of a flat torus' universal cover (cover).");
  sub->add_option("MESH", arguments->mesh, "Mesh file (must pass validation)")->required();
  sub->add_option("--kind", arguments->kind, "layout, checker, lines or cover")
      ->required()
      ->check(CLI::IsMember({"layout", "checker", "lines", "cover"}));
  sub->add_option("-o,--output", arguments->output, "Picture (.png)")->required();
  sub->add_option("--width", arguments->options.width, "Image width in pixels (default 800)")
      ->check(CLI::Range(1, 16384));
  sub->add_option("--height", arguments->options.height, "Image height in pixels (default 800)")
      ->check(CLI::Range(1, 16384));
  sub->add_flag("--edges", arguments->options.edges, "Draw the triangles' edges");
  sub->add_flag("!--no-seams", arguments->options.seams,
                "Do not draw the cut edges on the surface");
  addFlattenOptions(*sub, arguments->settings);
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "picture";
    command.run = [&command, arguments] {
      const PictureArguments& a = *arguments;
      if (!isPngPath(a.output)) throw InputError(a.output + ": picture writes PNG files (.png)");
      auto progress = [&](const std::string& line) {
        if (!a.settings.quiet) std::cerr << "picture: " << line << std::endl;
      };
      Stopwatch clock;
      Json stages;
      io::LoadedMesh loaded = io::loadMesh(a.mesh);
      const TriMesh& mesh = *loaded.mesh;
      stages["load"] = clock.lap();
      if (a.kind == "cover") {
        const TopologyReport topology = analyzeTopology(mesh);
        if (!topology.closed || topology.genus != 1)
          throw InputError(a.mesh + ": --kind cover needs a closed genus-1 surface (this one has " +
                           "genus " + std::to_string(topology.genus) + " and " +
                           std::to_string(topology.boundaryLoops) + " boundary loops)");
      }
      progress(std::to_string(mesh.n_faces()) + " faces loaded; flattening");

      Json report;
      const Flattening flat =
          flattenMesh(mesh, a.mesh, a.settings, command, report, stages, progress);
      if (a.kind == "cover" && !flat.layout.hasPeriods)
        throw InputError(a.mesh + ": --kind cover needs a flat torus, but the flattening has " +
                         std::to_string(flat.layout.cones.size()) + " cones (use --cones none)");
      clock.lap();
      const TriMesh& surface = *flat.surface;
      const io::RasterImage image =
          a.kind == "layout" ? io::renderLayout(surface, flat.layout, a.options)
          : a.kind == "checker"
              ? io::renderSurface(surface, flat.layout, a.options, io::SurfaceTexture::Checker)
          : a.kind == "lines"
              ? io::renderSurface(surface, flat.layout, a.options, io::SurfaceTexture::Lines)
              : io::renderCover(surface, flat.layout, a.options);
      stages["render"] = clock.lap();
      io::writePng(a.output, image);
      stages["write"] = clock.lap();

      double total = 0.0;
      for (const auto& [name, seconds] : stages.items()) total += seconds.get<double>();
      report["seconds"] = total;
      report["stage_seconds"] = stages;
      Json result = {{"file", a.mesh},
                     {"kind", a.kind},
                     {"output", a.output},
                     {"width", image.width},
                     {"height", image.height}};
      for (const auto& [key, value] : report.items()) result[key] = value;
      if (command.json) {
        printJson(result);
      } else {
        std::cout << "wrote " << a.output << " (" << a.kind << ", " << image.width << " x "
                  << image.height << ", " << flat.cones.size() << " cones, " << total << " s)"
                  << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
