// mspline voronoi: the Voronoi diagram of sites on a closed genus-1 surface in its flat metric,
// computed on the universal cover and written as the mesh with one group per cell and the cell
// boundaries as polylines.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>

#include <Eigen/Dense>

#include "cli/command.h"
#include "cli/flatten_options.h"
#include "mspline/io/atomic_file.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/raster_image.h"
#include "mspline/io/read_mesh.h"
#include "mspline/io/surface_pictures.h"
#include "mspline/io/write_labeled_mesh.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/intrinsic/intrinsic_overlay.h"
#include "mspline/structure/layout/flat_torus_voronoi.h"
#include "mspline/structure/picture/torus_voronoi_svg.h"
#include "mspline/structure/topology/topology.h"

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

template <typename Number>
bool parseWhole(const std::string& token, Number& value) {
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

// Lines "face b0 b1 b2" ('#' starts a comment), faces of `mesh`.
std::vector<SurfacePoint> readSiteFile(const std::string& path, const TriMesh& mesh) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw IoError(path + ": cannot open the sites file");
  std::vector<SurfacePoint> sites;
  std::string line;
  for (int lineNumber = 1; std::getline(file, line); ++lineNumber) {
    const std::string content = line.substr(0, line.find('#'));
    std::istringstream fields(content);
    std::vector<std::string> tokens;
    for (std::string token; fields >> token;) tokens.push_back(token);
    if (tokens.empty()) continue;
    const std::string where = path + ":" + std::to_string(lineNumber);
    SurfacePoint site;
    bool valid = tokens.size() == 4 && parseWhole(tokens[0], site.face);
    for (int k = 0; valid && k < 3; ++k) valid = parseWhole(tokens[k + 1], site.barycentric[k]);
    if (!valid)
      throw InputError(where +
                       ": expected 'face b0 b1 b2' (a face index and three barycentric "
                       "coordinates), got '" +
                       content.substr(0, content.find_last_not_of(" \t\r") + 1) + "'");
    checkSurfacePoint(mesh, site, where);
    sites.push_back(site);
  }
  if (file.bad()) throw IoError(path + ": error while reading the sites file");
  if (sites.empty()) throw InputError(path + ": no sites");
  return sites;
}

// A point of an input face as a point of the overlay face (a piece of it) that holds it.
std::vector<SurfacePoint> sitesOnOverlay(const TriMesh& input, const IntrinsicOverlay& overlay,
                                         const std::vector<SurfacePoint>& sites) {
  std::vector<std::vector<int>> pieces(input.n_faces());
  for (std::size_t g = 0; g < overlay.inputFace.size(); ++g)
    pieces[overlay.inputFace[g]].push_back(static_cast<int>(g));
  std::vector<SurfacePoint> mapped;
  for (const SurfacePoint& site : sites) {
    const Eigen::Vector3d x = surfacePosition(input, site);
    SurfacePoint best;
    double bestWorst = -std::numeric_limits<double>::infinity();
    for (int g : pieces[site.face]) {
      const Eigen::Vector3d q0 = surfacePosition(overlay.mesh, {g, Eigen::Vector3d(1, 0, 0)});
      const Eigen::Vector3d e1 = surfacePosition(overlay.mesh, {g, Eigen::Vector3d(0, 1, 0)}) - q0;
      const Eigen::Vector3d e2 = surfacePosition(overlay.mesh, {g, Eigen::Vector3d(0, 0, 1)}) - q0;
      Eigen::Matrix2d gram;
      gram << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
      const Eigen::Vector2d beta = gram.inverse() * Eigen::Vector2d(e1.dot(x - q0), e2.dot(x - q0));
      const Eigen::Vector3d b(1.0 - beta.sum(), beta.x(), beta.y());
      if (b.minCoeff() > bestWorst) {
        bestWorst = b.minCoeff();
        best = {g, b};
      }
    }
    best.barycentric = best.barycentric.cwiseMax(0.0);
    best.barycentric /= best.barycentric.sum();
    mapped.push_back(best);
  }
  return mapped;
}

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
    command.run = [&command, arguments] {
      const VoronoiArguments& a = *arguments;
      if (io::meshFormatFromPath(a.output) != io::MeshFormat::Obj)
        throw InputError(a.output + ": voronoi writes groups and polylines, which only OBJ holds");
      if (!a.png.empty() && (a.png.size() < 4 || a.png.compare(a.png.size() - 4, 4, ".png") != 0))
        throw InputError(a.png + ": --png writes PNG files (.png)");
      const Progress progress = progressLines("voronoi", a.quiet);
      Stopwatch clock;
      io::LoadedMesh loaded = io::loadMesh(a.mesh);
      const TriMesh& mesh = *loaded.mesh;
      const TopologyReport topology = analyzeTopology(mesh);
      if (topology.components != 1 || !topology.closed || topology.genus != 1)
        throw TopologyError(a.mesh + ": voronoi needs a closed genus-1 surface; this one has " +
                            std::to_string(topology.components) + " components, genus " +
                            std::to_string(topology.genus) + " and " +
                            std::to_string(topology.boundaryLoops) + " boundary loops");
      const bool random = isCount(a.sites);
      int count = 0;
      if (random && (!parseWhole(a.sites, count) || count == 0))
        throw InputError("--sites " + a.sites + ": not a number of sites from 1 to 2^31 - 1");
      std::vector<SurfacePoint> sites;
      if (!random) sites = readSiteFile(a.sites, mesh);

      FlattenOptions options;
      options.cones.emplace();
      options.name = a.mesh;
      Json stages;
      structure::report(progress,
                        std::to_string(mesh.n_faces()) + " faces loaded; flattening without cones");
      const Flattening flat = flattenSurface(mesh, options, progress);
      flatteningJson(flat, options, stages, command);
      const TriMesh& surface = flat.surface();
      if (random)
        sites = randomSurfacePoints(surface, count, a.seed);
      else if (flat.overlay)
        sites = sitesOnOverlay(mesh, *flat.overlay, sites);

      const TorusVoronoi voronoi = flatTorusVoronoi(surface, flat.layout, sites);
      std::vector<int> facesPerCell(sites.size(), 0);
      for (int label : voronoi.faceLabel) ++facesPerCell[label];
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
            torusVoronoiSvg(surface, flat.layout, sites, voronoi, svgOptions);
        io::writeFileAtomically(a.svg, [&](std::ostream& out) { out << picture; });
      }
      if (!a.png.empty())
        io::writePng(a.png, io::renderSurfaceLabels(surface, voronoi.faceLabel, {}));
      const double seconds = clock.lap();

      const auto [fewest, most] = std::minmax_element(facesPerCell.begin(), facesPerCell.end());
      Json report;
      report["file"] = a.mesh;
      report["sites"] = sites.size();
      report["cells"] = voronoi.cells;
      report["faces_per_cell"] = {{"min", *fewest}, {"max", *most}};
      report["boundary_polylines"] = voronoi.polylines.size();
      report["replicated_sites"] = voronoi.replicatedSites;
      report["max_equidistance_error"] = voronoi.maxEquidistanceError;
      report["seconds"] = seconds;
      report["output"] = a.output;
      if (command.json) {
        printJson(report);
      } else {
        std::cout << sites.size() << " sites, " << voronoi.cells << " cells of " << *fewest
                  << " to " << *most << " faces, " << voronoi.polylines.size()
                  << " boundary polylines, " << seconds << " s\nwrote " << a.output
                  << (a.svg.empty() ? "" : " and " + a.svg) << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
