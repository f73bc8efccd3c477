#include "cli/flatten_pipeline.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "mspline/structure/ricci/circle_packing_energy.h"
#include "mspline/structure/ricci/cone_file.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/holonomy_quantization.h"
#include "mspline/structure/intrinsic/intrinsic_flattening.h"
#include "mspline/structure/intrinsic/ricci_flips.h"
#include "mspline/structure/topology/topology.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"

namespace mspline::cli {

namespace {

using namespace structure;
constexpr double kPi = 3.14159265358979323846;

std::vector<double> asVector(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

std::vector<Cone> chooseCones(const TriMesh& mesh, const FlattenSettings& arguments) {
  if (arguments.singleCone || arguments.cones == "auto" || isCount(arguments.cones)) {
    ConePlacementOptions options;
    options.quantize = arguments.quantize;
    options.maxQuarterTurns = arguments.maxConeQuarterTurns;
    options.singleCone = arguments.singleCone;
    if (isCount(arguments.cones)) {
      const std::string& text = arguments.cones;
      const auto parsed =
          std::from_chars(text.data(), text.data() + text.size(), options.targetCount);
      if (parsed.ec != std::errc())
        throw InputError("--cones " + text + ": not a number of cones from 0 to 2^31 - 1");
    }
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

bool isCount(const std::string& text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), ::isdigit);
}

void addFlattenOptions(CLI::App& sub, FlattenSettings& settings, const std::string& toleranceFlag) {
  sub.add_option("--scheme", settings.scheme,
                 "yamabe (vertex scaling, default), tangential (Thurston circle packing with "
                 "intersection angles from the mesh) or inversive (inversive distance)")
      ->check(CLI::IsMember({"yamabe", "tangential", "inversive"}));
  sub.add_option("--cones", settings.cones,
                 "auto (greedy placement, default), none, a number N of cones to place, or a "
                 "file of 'vertex curvature' lines");
  sub.add_flag("--quantize", settings.quantize,
               "Round cone curvatures to multiples of pi/2 (seam rotations by quarter turns)");
  sub.add_flag("--single-cone", settings.singleCone,
               "Genus >= 2: all curvature in one cone (Gu et al. 2008)");
  sub.add_option("--boundary", settings.boundary,
                 "free: boundary lengths kept, shape follows (u = 0 on the boundary, default); "
                 "fixed: the boundary becomes a circle; rectangle: four corners of pi/2 and "
                 "straight sides (disks only)")
      ->check(CLI::IsMember({"free", "fixed", "rectangle"}));
  sub.add_option(toleranceFlag, settings.tolerance,
                 "Stop when max |K - K_target| <= tolerance, in radians (default 1e-10)")
      ->check(CLI::PositiveNumber);
  sub.add_option("--max-iterations", settings.maxIterations, "Newton steps (default 100)")
      ->check(CLI::PositiveNumber);
  sub.add_flag("-q,--quiet", settings.quiet, "No progress on stderr");
}

Flattening flattenMesh(const TriMesh& mesh, const std::string& file,
                       const FlattenSettings& settings, Command& command, Json& report,
                       Json& stages, const std::function<void(const std::string&)>& progress) {
  Stopwatch clock;
  Flattening out;
  out.cones = chooseCones(mesh, settings);
  const std::vector<Cone>& cones = out.cones;
  stages["cones"] = clock.lap();
  const auto topology = analyzeTopology(mesh);
  BoundaryCondition condition = BoundaryCondition::FixedScale;
  std::vector<Cone> targets = cones;
  if (!topology.closed && settings.boundary != "free") {
    condition = BoundaryCondition::PrescribedGeodesicCurvature;
    targets = boundaryShape(mesh, settings.boundary, cones);
  }
  CurvatureTarget target = flatTarget(mesh, targets, condition);
  progress(std::to_string(cones.size()) + " cones; Newton on the " + settings.scheme +
           " Ricci energy");

  RicciNewtonOptions options;
  options.tolerance = settings.tolerance / (2.0 * kPi);  // the solver counts in units of 2 pi
  options.maxIterations = settings.maxIterations;
  const RicciScheme scheme = makeScheme(mesh, settings.scheme);
  RicciResult& flow = out.flow;
  flow = solveRicciFlow(mesh, scheme, target, options);
  stages["ricci_flow"] = clock.lap();
  progress(std::to_string(flow.iterations) + " Newton steps, max curvature error " +
           std::to_string(flow.maxCurvatureError) + ": " + flow.message);

  Json cones_json = Json::array();
  for (const auto& cone : cones)
    cones_json.push_back({{"vertex", cone.vertex},
                          {"curvature", cone.curvature},
                          {"angle", 2.0 * kPi - cone.curvature}});
  report["file"] = file;
  report["scheme"] = settings.scheme;
  report["cones"] = cones_json;
  report["flips"] = 0;
  // Where the input triangulation degenerates, vertex scaling continues on an intrinsic
  // triangulation kept Delaunay by Ptolemy flips, and the surface laid out is the common
  // subdivision of the input and that triangulation.
  if (!flow.converged && flow.status == RicciStatus::DegenerateTriangles &&
      settings.scheme == "yamabe") {
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
      out.overlay = std::move(flipped.overlay);
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
    throw SolverError(file + ": the Ricci flow did not converge: " + flow.message +
                      " (nothing written)");
  }

  out.input = &mesh;
  out.flatLengths = out.overlay ? out.overlay->edgeLengths : flow.edgeLengths;
  // Quantized cones make the rotations around cones quarter turns; on a closed surface with
  // handles the rotations along the handles must be made so too.
  if (settings.quantize && topology.closed && topology.genus >= 1) {
    progress("quantizing the rotation along " + std::to_string(2 * topology.genus) +
             " handle loops");
    HolonomyQuantizationResult holonomy;
    try {
      holonomy = quantizeHolonomy(out.surface(), out.flatLengths, cones);
    } catch (const SolverError& error) {
      // A singular step (too few triangles to move the rotations): as non-convergence.
      holonomy.converged = false;
      holonomy.message = error.what();
    }
    stages["holonomy"] = clock.lap();
    report["holonomy"] = {{"loops", holonomy.loops.size()},
                          {"initial_rotations", asVector(holonomy.initialRotation)},
                          {"target_rotations", asVector(holonomy.targetRotation)},
                          {"converged", holonomy.converged},
                          {"iterations", holonomy.iterations},
                          {"max_residual", holonomy.maxResidual},
                          {"max_log_length_change", holonomy.maxLogLengthChange}};
    // A fixed triangulation cannot always follow the deformation (eight.off degenerates; that
    // needs flips with point tracking): keep the conformal metric, whose seams then turn by
    // arbitrary angles, and say so.
    if (holonomy.converged)
      out.flatLengths = holonomy.edgeLengths;
    else
      progress("warning: the handle rotations stay unquantized (" + holonomy.message +
               "); seams across handles turn by arbitrary angles");
  }
  progress("laying out");
  out.layout = layoutFlatMetric(out.surface(), out.flatLengths);
  stages["layout"] = clock.lap();
  const FlatLayout& layout = out.layout;
  report["flipped_triangles"] = layout.flippedTriangles;
  report["area_distortion"] = areaDistortion(out.surface(), out.flatLengths, flow.u);
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
  if (layout.flippedTriangles > 0) {
    report["stage_seconds"] = stages;
    command.partialResult = report;
    throw SolverError(file + ": the layout has " + std::to_string(layout.flippedTriangles) +
                      " flipped triangles (nothing written)");
  }
  return out;
}

}  // namespace mspline::cli
