// mspline voronoi: the Voronoi diagram of sites on a closed genus-1 surface in its flat metric,
// computed on the universal cover and written as the mesh with one group per cell and the cell
// boundaries as polylines.
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_options.h"
#include "mspline/io/atomic_file.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/raster_image.h"
#include "mspline/io/read_mesh.h"
#include "mspline/io/site_file.h"
#include "mspline/io/surface_pictures.h"
#include "mspline/io/write_labeled_mesh.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/flatten/surface_voronoi.h"
#include "mspline/structure/picture/torus_voronoi_svg.h"

namespace mspline::cli {

namespace {

using namespace structure;

struct VoronoiArguments {
  std::string mesh;
  std::string sites;
  std::string output;
  std::string svg;
  std::string png;
  bool cover = false;
  unsigned seed = 1;
  bool quiet = false;
};

}  // namespace

void addVoronoiCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<VoronoiArguments>();
  auto* sub = app.add_subcommand(
      "voronoi",
      "Voronoi diagram of sites on a closed genus-1 surface in its flat metric (Ricci flow "
      "without cones), computed on the universal cover; writes the mesh with one group per cell "
      "and the cell boundaries as polylines.");
  sub->add_option("MESH", arguments->mesh, "Closed genus-1 mesh (must pass validation)")
      ->required();
  sub->add_option("--sites", arguments->sites,
                  "A number N of random sites, or a file of 'face b0 b1 b2' lines (barycentric "
                  "coordinates in the face, '#' comments)")
      ->required();
  sub->add_option("-o,--output", arguments->output,
                  "Mesh with a group cell_<k> per cell and 'l' boundary polylines (.obj)")
      ->required();
  sub->add_option("--svg", arguments->svg, "Also write a picture of the cells on the layout");
  sub->add_flag("--cover", arguments->cover, "With --svg: draw 3 x 3 copies of the layout");
  sub->add_option("--png", arguments->png, "Also write a picture of the surface colored by cell");
  sub->add_option("--seed", arguments->seed, "Seed of the random sites (default 1)");
  sub->add_flag("-q,--quiet", arguments->quiet, "No progress on stderr");
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "voronoi";
    command.files = {arguments->mesh, arguments->output, arguments->svg, arguments->png};
    if (!isCount(arguments->sites)) command.files.push_back(arguments->sites);
    command.run = [&command, arguments] {
      const VoronoiArguments& a = *arguments;
      if (io::meshFormatFromPath(a.output) != io::MeshFormat::Obj)
        throw InputError(a.output + ": voronoi writes groups and polylines, which only OBJ holds");
      if (!a.png.empty() && (a.png.size() < 4 || a.png.compare(a.png.size() - 4, 4, ".png") != 0))
        throw InputError(a.png + ": --png writes PNG files (.png)");
      const Progress progress = progressLines(command, a.quiet);
      Stopwatch clock;
      io::LoadedMesh loaded = io::loadMesh(a.mesh);
      const TriMesh& mesh = *loaded.mesh;
      SurfaceVoronoiOptions options;
      options.name = a.mesh;
      options.seed = a.seed;
      if (!isCount(a.sites))
        options.sites = io::readSiteFile(a.sites, mesh);
      else if (!parseCount(a.sites, options.randomSites) || options.randomSites == 0)
        throw InputError("--sites " + a.sites + ": not a number of sites from 1 to 2^31 - 1");
      const SurfaceVoronoi cells = surfaceVoronoi(mesh, options, progress);
      Json stages;
      flatteningJson(cells.flattening, cells.flattenOptions, stages, command);
      const TriMesh& surface = cells.flattening.surface();
      const TorusVoronoi& voronoi = cells.voronoi;
      std::vector<io::LabeledPolyline> lines;
      for (const VoronoiPolyline& polyline : voronoi.polylines)
        lines.push_back({"boundary_" + std::to_string(polyline.cells[0]) + "_" +
                             std::to_string(polyline.cells[1]),
                         polyline.points});
      io::writeLabeledObj(a.output, surface, voronoi.faceLabel, "cell_", lines);
      if (!a.svg.empty()) {
        TorusVoronoiSvgOptions svgOptions;
        svgOptions.coverRadius = a.cover ? 1 : 0;
        const std::string picture =
            torusVoronoiSvg(surface, cells.flattening.layout, cells.sites, voronoi, svgOptions);
        io::writeFileAtomically(a.svg, [&](std::ostream& out) { out << picture; });
      }
      if (!a.png.empty())
        io::writePng(a.png, io::renderSurfaceLabels(surface, voronoi.faceLabel, {}));
      const double seconds = clock.lap();

      Json report;
      report["file"] = a.mesh;
      report["sites"] = cells.sites.size();
      report["cells"] = voronoi.cells;
      report["faces_per_cell"] = {{"min", cells.fewestFacesPerCell},
                                  {"max", cells.mostFacesPerCell}};
      report["boundary_polylines"] = voronoi.polylines.size();
      report["replicated_sites"] = voronoi.replicatedSites;
      report["max_equidistance_error"] = voronoi.maxEquidistanceError;
      report["seconds"] = seconds;
      report["output"] = a.output;
      if (command.json) {
        printJson(report);
      } else {
        std::cout << cells.sites.size() << " sites, " << voronoi.cells << " cells of "
                  << cells.fewestFacesPerCell << " to " << cells.mostFacesPerCell << " faces, "
                  << voronoi.polylines.size() << " boundary polylines, " << seconds << " s\nwrote "
                  << a.output << (a.svg.empty() ? "" : " and " + a.svg) << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
