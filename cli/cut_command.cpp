// mspline cut: opens a surface into a topological disk and writes it.
#include <iostream>

#include "cli/command.h"
#include "cli/mesh_report.h"
#include "mspline/io/load_mesh.h"
#include "mspline/io/read_mesh.h"
#include "mspline/io/write_mesh.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/topology/cut_to_disk.h"

namespace mspline::cli {

namespace {

struct CutArguments {
  std::string mesh;
  std::string output;
  int baseVertex = -1;
  bool generalCutGraph = false;
  bool quiet = false;
};

Json segmentsJson(const structure::CutResult& cut) {
  Json segments = Json::array();
  for (const auto& segment : cut.segments)
    segments.push_back({{"curve", cut.curveNames[segment.curve]},
                        {"orientation", segment.orientation},
                        {"begin", segment.begin},
                        {"end", segment.end},
                        {"boundary", segment.boundary}});
  return segments;
}

}  // namespace

void addCutCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<CutArguments>();
  auto* sub = app.add_subcommand(
      "cut",
      "Cut a surface into one topological disk. Closed surfaces of genus g >= 1 are cut along a "
      "one-vertex system of 2g loops (crossing the faces: points are added on edges and one inside "
      "a face), so the disk boundary reads a1 b1 a1^-1 b1^-1 ... (when canonical form fits in the "
      "size budget; otherwise 4g sides in another order); bounded surfaces also along paths to "
      "each boundary.");
  sub->add_option("MESH", arguments->mesh, "Mesh file (must pass validation)")->required();
  sub->add_option("-o,--output", arguments->output, "The cut-open disk (OBJ, OFF, PLY or STL)")
      ->required();
  sub->add_option("--base", arguments->baseVertex, "Base vertex of the loops (default: automatic)");
  sub->add_flag("--general", arguments->generalCutGraph,
                "Cut along the greedy cut graph on the original edges (no refinement; the "
                "boundary then has up to 12g-6 segments)");
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->add_flag("-q,--quiet", arguments->quiet, "No progress on stderr");
  sub->callback([&command, arguments] {
    command.name = "cut";
    command.files = {arguments->mesh, arguments->output};
    command.run = [&command, arguments] {
      structure::Stopwatch clock;
      io::meshFormatFromPath(arguments->output);  // fail before the work, not after
      io::LoadedMesh loaded = io::loadMesh(arguments->mesh);
      if (!arguments->quiet) addNotes(command, loaded.warnings, loaded.repairs);
      structure::CutOptions options;
      options.baseVertex = arguments->baseVertex;
      options.oneVertexSchema = !arguments->generalCutGraph;
      structure::CutResult cut = structure::cutToDisk(*loaded.mesh, options);
      io::writeMesh(arguments->output, cut.disk);
      const double seconds = clock.lap();
      if (command.json) {
        Json report{{"file", arguments->mesh},
                    {"output", arguments->output},
                    {"genus", cut.genus},
                    {"disk_euler", cut.diskEuler},
                    {"disk_boundary_loops", cut.diskBoundaryLoops},
                    {"disk_components", cut.diskComponents},
                    {"disk_vertices", cut.disk.n_vertices()},
                    {"disk_faces", cut.disk.n_faces()},
                    {"segments", cut.segments.size()},
                    {"word", cut.word},
                    {"one_vertex_schema", cut.oneVertexSchema},
                    {"canonical", cut.canonical},
                    {"refinements", cut.refinements},
                    {"edge_splits", cut.edgeSplits},
                    {"cut_edges", cut.cutEdges.size()},
                    {"base_vertex", cut.baseVertex},
                    {"seconds", seconds},
                    {"boundary_segments", segmentsJson(cut)}};
        if (!cut.notCanonicalBecause.empty())
          report["not_canonical_because"] = cut.notCanonicalBecause;
        printJson(report);
      } else {
        std::cout << "disk: euler " << cut.diskEuler << ", " << cut.diskBoundaryLoops
                  << " boundary loop(s), " << cut.segments.size() << " segments, "
                  << cut.disk.n_faces() << " faces (" << cut.refinements << " refinements, "
                  << cut.edgeSplits << " edge splits)\nword: " << cut.word
                  << (cut.canonical ? " (canonical)" : "")
                  << (cut.notCanonicalBecause.empty()
                          ? ""
                          : "\nnot canonical: " + cut.notCanonicalBecause)
                  << "\nwrote " << arguments->output << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
