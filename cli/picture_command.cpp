// mspline picture: PNG pictures of the flat structure, drawn without a GPU: the cut layout, the
// surface with a checkerboard or parallel lines in its flat coordinates, a flat torus' cover.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>

#include "cli/command.h"
#include "cli/flatten_options.h"
#include "mspline/io/atlas_file.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/raster_image.h"
#include "mspline/io/surface_pictures.h"
#include "mspline/structure/atlas/affine_atlas.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/topology/topology.h"

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

std::string lowerExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  return extension;
}

}  // namespace

void addPictureCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<PictureArguments>();
  auto* sub = app.add_subcommand(
      "picture",
      "Flattens the surface (as flatten does), or takes the flat metric of an atlas file written "
      "by `mspline atlas`, and draws a PNG: the cut layout with a checkerboard (layout), the "
      "surface with a checkerboard (checker) or parallel lines (lines) in its flat coordinates, "
      "or 3 x 3 copies of a flat torus' universal cover (cover).");
  sub->add_option("INPUT", arguments->mesh,
                  "Mesh file (must pass validation), or an atlas file (.json)")
      ->required();
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
    command.files = {arguments->mesh, arguments->output, coneFile(arguments->settings)};
    command.run = [&command, arguments] {
      const PictureArguments& a = *arguments;
      const io::PictureKind kind = a.kind == "layout"    ? io::PictureKind::Layout
                                   : a.kind == "checker" ? io::PictureKind::Checker
                                   : a.kind == "lines"   ? io::PictureKind::Lines
                                                         : io::PictureKind::Cover;
      if (lowerExtension(a.output) != ".png")
        throw InputError(a.output + ": picture writes PNG files (.png)");
      const Progress progress = progressLines(command, a.settings.quiet);
      Stopwatch clock;
      Json stages;
      Json report;
      // The surface and its flat metric: from the atlas file, or flattened here.
      std::optional<io::LoadedMesh> loaded;
      std::optional<io::LoadedAtlas> atlas;
      std::optional<Flattening> flat;
      const TriMesh* surface = nullptr;
      Eigen::VectorXd lengths;
      if (lowerExtension(a.mesh) == ".json") {
        atlas = io::readAtlas(a.mesh);
        surface = &atlas->mesh;
        lengths = atlasEdgeLengths(*surface, atlas->atlas);
        stages["load"] = clock.lap();
      } else {
        loaded = io::loadMesh(a.mesh);
        stages["load"] = clock.lap();
      }
      const TriMesh& mesh = atlas ? atlas->mesh : *loaded->mesh;
      if (kind == io::PictureKind::Cover) {
        const TopologyReport topology = analyzeTopology(mesh);
        if (!topology.closed || topology.genus != 1)
          throw InputError(a.mesh + ": --kind cover needs a closed genus-1 surface (this one has " +
                           "genus " + std::to_string(topology.genus) + " and " +
                           std::to_string(topology.boundaryLoops) + " boundary loops)");
      }
      if (!atlas) {
        const FlattenOptions options = toFlattenOptions(a.settings, a.mesh);
        flat = flattenSurface(mesh, options, progress);
        report = flatteningJson(*flat, options, stages, command);
        surface = &flat->surface();
      }
      const FlatLayout layout = flat ? flat->layout : layoutFlatMetric(*surface, lengths);
      if (kind == io::PictureKind::Cover && !layout.hasPeriods)
        throw InputError(a.mesh + ": --kind cover needs a flat torus, but the metric has " +
                         std::to_string(layout.cones.size()) + " cones" +
                         (atlas ? "" : " (use --cones none)"));
      clock.lap();
      const io::RasterImage image = io::renderPicture(*surface, layout, kind, a.options);
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
                  << image.height << ", " << layout.cones.size() << " cones, " << total << " s)"
                  << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
