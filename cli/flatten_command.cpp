// mspline flatten: discrete Ricci flow to a flat metric with cone singularities, laid out in the
// plane with per-corner UVs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>

#include "cli/command.h"
#include "cli/mesh_report.h"
#include "io/atomic_file.h"
#include "io/load_mesh.h"
#include "io/read_mesh.h"
#include "io/write_mesh.h"
#include "structure/circle_packing_energy.h"
#include "structure/cone_file.h"
#include "structure/cone_placement.h"
#include "structure/errors.h"
#include "structure/flat_layout.h"
#include "structure/intrinsic_flattening.h"
#include "structure/layout_svg.h"
#include "structure/ricci_flips.h"
#include "structure/ricci_newton.h"
#include "structure/topology.h"
#include "structure/vertex_scaling_energy.h"

namespace mspline::cli {

namespace {

using namespace structure;
constexpr double kPi = 3.14159265358979323846;

struct FlattenArguments {
  std::string mesh;
  std::string output;
  std::string scheme = "yamabe";
  std::string cones = "auto";
  bool quantize = false;
  bool singleCone = false;
  std::string boundary = "free";
  std::string svg;
  bool cover = false;
  double tolerance = 1e-10;
  int maxIterations = 100;
  bool quiet = false;
};

class Stopwatch {
 public:
  double lap() {
    auto now = std::chrono::steady_clock::now();
    double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

bool isCount(const std::string& text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), ::isdigit);
}

std::vector<Cone> chooseCones(const TriMesh& mesh, const FlattenArguments& arguments) {
  if (arguments.singleCone || arguments.cones == "auto" || isCount(arguments.cones)) {
    ConePlacementOptions options;
    options.quantize = arguments.quantize;
    options.singleCone = arguments.singleCone;
    if (isCount(arguments.cones)) options.targetCount = std::stoi(arguments.cones);
    return placeCones(mesh, options).cones;
  }
  if (arguments.cones == "none") return {};
  return readConeFile(arguments.cones);
}

std::vector<std::vector<int>> boundaryLoops(const TriMesh& mesh) {
  std::vector<std::vector<int>> loops;
  std::vector<char> seen(mesh.n_halfedges(), 0);
  for (auto h : mesh.halfedges()) {
    if (!mesh.is_boundary(h) || seen[h.idx()]) continue;
    auto& loop = loops.emplace_back();
    for (auto walk = h; !seen[walk.idx()]; walk = mesh.next_halfedge_handle(walk)) {
      seen[walk.idx()] = 1;
      loop.push_back(mesh.from_vertex_handle(walk).idx());
    }
  }
  return loops;
}

// Geodesic curvatures for a disk whose boundary is prescribed: a circle (curvature spread by
// boundary length) or a rectangle (pi/2 at four corners a quarter of the perimeter apart).
std::vector<Cone> boundaryShape(const TriMesh& mesh, const std::string& shape,
                                const std::vector<Cone>& interiorCones) {
  auto loops = boundaryLoops(mesh);
  if (loops.size() != 1)
    throw InputError("--boundary " + shape + " needs a surface with exactly one boundary loop; " +
                     "this one has " + std::to_string(loops.size()));
  const auto& loop = loops.front();
  const std::size_t n = loop.size();
  std::vector<double> arc(n + 1, 0.0);  // arc length from loop[0] to loop[i]
  for (std::size_t i = 0; i < n; ++i) {
    auto p = mesh.point(TriMesh::VertexHandle(loop[i]));
    auto q = mesh.point(TriMesh::VertexHandle(loop[(i + 1) % n]));
    arc[i + 1] = arc[i] + (q - p).norm();
  }
  double interior = 0.0;
  for (const auto& cone : interiorCones) interior += cone.curvature;
  const double total = 2.0 * kPi - interior;  // Gauss-Bonnet on a disk
  std::vector<Cone> cones = interiorCones;
  if (shape == "fixed") {
    for (std::size_t i = 0; i < n; ++i) {
      const double before = arc[i == 0 ? n : i] - arc[i == 0 ? n - 1 : i - 1];
      const double after = arc[i + 1] - arc[i];
      cones.push_back({loop[i], total * 0.5 * (before + after) / arc[n]});
    }
    return cones;
  }
  if (std::abs(total - 2.0 * kPi) > 1e-12)
    throw InputError("--boundary rectangle needs interior cones whose curvatures sum to 0");
  for (int corner = 0; corner < 4; ++corner) {
    const double wanted = arc[n] * corner / 4.0;
    std::size_t best = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (std::abs(arc[i] - wanted) < std::abs(arc[best] - wanted)) best = i;
    cones.push_back({loop[best], kPi / 2});
  }
  return cones;
}

RicciScheme makeScheme(const TriMesh& mesh, const std::string& name) {
  if (name == "tangential") return circlePackingScheme(mesh, thurstonPackingMetric(mesh), name);
  if (name == "inversive") return circlePackingScheme(mesh, inversiveDistanceMetric(mesh), name);
  return vertexScalingScheme(mesh);
}

// exp(2u) over the input vertices, with u shifted so the flat metric has the input's total area:
// the factor by which the flat metric scales area around each vertex. `mesh` is the surface laid
// out (the input or its overlay) with its flat lengths.
Json areaDistortion(const TriMesh& mesh, const Eigen::VectorXd& flatLengths,
                    const Eigen::VectorXd& u) {
  auto area = [&](const Eigen::VectorXd& lengths) {
    double sum = 0.0;
    for (auto f : mesh.faces()) {
      double l[3];
      int k = 0;
      for (auto e : mesh.fe_range(f)) l[k++] = lengths[e.idx()];
      double s = 0.5 * (l[0] + l[1] + l[2]);
      sum += std::sqrt(std::max(0.0, s * (s - l[0]) * (s - l[1]) * (s - l[2])));
    }
    return sum;
  };
  const double shift = 0.5 * std::log(area(edgeLengths(mesh)) / area(flatLengths));
  Eigen::ArrayXd scale = (2.0 * (u.array() + shift)).exp();
  return {{"min", scale.minCoeff()}, {"max", scale.maxCoeff()}, {"mean", scale.mean()}};
}

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
  sub->add_option("--scheme", arguments->scheme,
                  "yamabe (vertex scaling, default), tangential (Thurston circle packing with "
                  "intersection angles from the mesh) or inversive (inversive distance)")
      ->check(CLI::IsMember({"yamabe", "tangential", "inversive"}));
  sub->add_option("--cones", arguments->cones,
                  "auto (greedy placement, default), none, a number N of cones to place, or a "
                  "file of 'vertex curvature' lines");
  sub->add_flag("--quantize", arguments->quantize,
                "Round cone curvatures to multiples of pi/2 (seam rotations by quarter turns)");
  sub->add_flag("--single-cone", arguments->singleCone,
                "Genus >= 2: all curvature in one cone (Gu et al. 2008)");
  sub->add_option("--boundary", arguments->boundary,
                  "free: boundary lengths kept, shape follows (u = 0 on the boundary, default); "
                  "fixed: the boundary becomes a circle; rectangle: four corners of pi/2 and "
                  "straight sides (disks only)")
      ->check(CLI::IsMember({"free", "fixed", "rectangle"}));
  sub->add_option("--svg", arguments->svg, "Also write a picture of the layout");
  sub->add_flag("--cover", arguments->cover,
                "With --svg on a flat torus: draw 3 x 3 copies of the universal cover");
  sub->add_option("--tolerance", arguments->tolerance,
                  "Stop when max |K - K_target| <= tolerance, in radians (default 1e-10)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--max-iterations", arguments->maxIterations, "Newton steps (default 100)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->add_flag("-q,--quiet", arguments->quiet, "No progress on stderr");
  sub->callback([&command, arguments] {
    command.name = "flatten";
    command.run = [&command, arguments] {
      const FlattenArguments& a = *arguments;
      if (io::meshFormatFromPath(a.output) != io::MeshFormat::Obj)
        throw InputError(a.output + ": flatten writes per-corner UVs, which only OBJ holds");
      auto progress = [&](const std::string& line) {
        if (!a.quiet) std::cerr << "flatten: " << line << std::endl;
      };
      Stopwatch clock;
      Json stages;
      io::LoadedMesh loaded = io::loadMesh(a.mesh);
      const TriMesh& mesh = *loaded.mesh;
      stages["load"] = clock.lap();
      progress(std::to_string(mesh.n_faces()) + " faces loaded; placing cones");

      std::vector<Cone> cones = chooseCones(mesh, a);
      stages["cones"] = clock.lap();
      const auto topology = analyzeTopology(mesh);
      BoundaryCondition condition = BoundaryCondition::FixedScale;
      std::vector<Cone> targets = cones;
      if (!topology.closed && a.boundary != "free") {
        condition = BoundaryCondition::PrescribedGeodesicCurvature;
        targets = boundaryShape(mesh, a.boundary, cones);
      }
      CurvatureTarget target = flatTarget(mesh, targets, condition);
      progress(std::to_string(cones.size()) + " cones; Newton on the " + a.scheme +
               " Ricci energy");

      RicciNewtonOptions options;
      options.tolerance = a.tolerance / (2.0 * kPi);  // the solver counts in units of 2 pi
      options.maxIterations = a.maxIterations;
      const RicciScheme scheme = makeScheme(mesh, a.scheme);
      RicciResult flow = solveRicciFlow(mesh, scheme, target, options);
      stages["ricci_flow"] = clock.lap();
      progress(std::to_string(flow.iterations) + " Newton steps, max curvature error " +
               std::to_string(flow.maxCurvatureError) + ": " + flow.message);

      Json cones_json = Json::array();
      for (const auto& cone : cones)
        cones_json.push_back({{"vertex", cone.vertex},
                              {"curvature", cone.curvature},
                              {"angle", 2.0 * kPi - cone.curvature}});
      Json report{{"file", a.mesh}, {"scheme", a.scheme}, {"cones", cones_json}, {"flips", 0}};
      // Where the input triangulation degenerates, vertex scaling continues on an intrinsic
      // triangulation kept Delaunay by Ptolemy flips, and the surface laid out is the common
      // subdivision of the input and that triangulation.
      std::optional<IntrinsicOverlay> overlay;
      if (!flow.converged && flow.status == RicciStatus::DegenerateTriangles &&
          a.scheme == "yamabe") {
        progress("the input triangulation degenerates (" + flow.message +
                 "); retrying with intrinsic Delaunay flips" +
                 (topology.closed ? "" : " on the doubled surface"));
        report["plain_solver"] = {{"message", flow.message}, {"iterations", flow.iterations}};
        IntrinsicFlattening flipped = flattenWithFlips(mesh, target, options);
        flow = flipped.solve.ricci;
        flow.u = flipped.u;
        report["flips"] = flipped.solve.flips;
        report["doubled"] = flipped.doubled;
        stages["ricci_flow_flips"] = clock.lap();
        if (flow.converged) {
          report["overlay"] = {{"faces", flipped.overlay.mesh.n_faces()},
                               {"crossings", flipped.overlay.crossingInputEdge.size()},
                               {"split_edges", flipped.splitEdges},
                               {"length_mismatch", flipped.overlay.maxLengthMismatch}};
          overlay = std::move(flipped.overlay);
        }
      }
      report["converged"] = flow.converged;
      report["message"] = flow.message;
      report["iterations"] = flow.iterations;
      report["max_curvature_error"] = flow.maxCurvatureError;
      if (!flow.converged) {
        stages["total"] = clock.lap();
        report["stage_seconds"] = stages;
        command.partialResult = report;
        throw SolverError(a.mesh + ": the Ricci flow did not converge: " + flow.message +
                          " (nothing written)");
      }
      const TriMesh& surface = overlay ? overlay->mesh : mesh;
      const Eigen::VectorXd& flatLengths = overlay ? overlay->edgeLengths : flow.edgeLengths;

      progress("laying out");
      FlatLayout layout = layoutFlatMetric(surface, flatLengths);
      stages["layout"] = clock.lap();
      PolygonSoup soup = toSoup(surface, a.mesh);
      soup.cornerUVs.resize(soup.faces.size());
      for (auto f : surface.faces())
        for (int k = 0; k < 3; ++k) {
          const auto row = layout.cornerUV.row(3 * f.idx() + k);
          soup.cornerUVs[f.idx()].push_back({row[0], row[1]});
        }
      io::writeMesh(a.output, soup);
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
      report["flipped_triangles"] = layout.flippedTriangles;
      report["area_distortion"] = areaDistortion(surface, flatLengths, flow.u);
      report["angle_distortion"] = {{"mean", layout.meanAngleDistortion},
                                    {"max", layout.maxAngleDistortion}};
      report["layout_edge_length_error"] = layout.maxEdgeLengthError;
      report["max_seam_residual"] = layout.maxSeamResidual;
      // With quantized cones every seam is a quarter-turn rotation plus a translation.
      double quarterTurnError = 0.0;
      int rotatedSeams = 0;
      for (const auto& seam : layout.seams) {
        const double quarters = seam.angle / (kPi / 2.0);
        quarterTurnError = std::max(quarterTurnError, std::abs(quarters - std::round(quarters)));
        rotatedSeams += std::round(quarters) != 0.0;
      }
      report["seam_rotations"] = {{"rotated", rotatedSeams},
                                  {"max_quarter_turn_error", quarterTurnError * kPi / 2.0}};
      report["cut_edges"] = layout.cutEdges.size();
      if (layout.hasPeriods) {
        report["periods"] = {{layout.periods[0][0], layout.periods[0][1]},
                             {layout.periods[1][0], layout.periods[1][1]}};
        report["max_period_residual"] = layout.maxPeriodResidual;
      }
      report["output"] = a.output;
      if (command.json) {
        printJson(report);
      } else {
        std::cout << "converged in " << flow.iterations << " Newton steps, max curvature error "
                  << flow.maxCurvatureError << ", " << cones.size() << " cones, "
                  << report["flips"].get<long>() << " intrinsic flips, " << layout.flippedTriangles
                  << " flipped triangles, " << total << " s\nwrote " << a.output
                  << (a.svg.empty() ? "" : " and " + a.svg) << std::endl;
      }
      if (layout.flippedTriangles > 0)
        throw SolverError(a.mesh + ": the layout has " + std::to_string(layout.flippedTriangles) +
                          " flipped triangles");
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
