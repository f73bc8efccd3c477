#include "cli/flatten_options.h"

#include <algorithm>
#include <charconv>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/cone_file.h"

namespace mspline::cli {

namespace {

using namespace structure;

std::vector<double> asVector(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

}  // namespace

bool isCount(const std::string& text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), ::isdigit);
}

bool parseCount(const std::string& text, int& count) {
  const char* end = text.data() + text.size();
  const auto parsed = std::from_chars(text.data(), end, count);
  return isCount(text) && parsed.ec == std::errc() && parsed.ptr == end;
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

void addCornerValenceOption(CLI::App& sub, int& minCornerValence) {
  sub.add_option(
         "--min-corner-valence", minCornerValence,
         "Quad layout: the smallest valence of a cone's corner, 3 (default: cones of angle "
         "3 pi / 2 at most; a cube's layout is its six faces) or 2 (one cone of angle pi at a "
         "sharp tip; fewer folds on some organic meshes, more on most of the data set)")
      ->check(CLI::Range(2, 3));
}

std::string coneFile(const FlattenSettings& settings) {
  const std::string& cones = settings.cones;
  const bool named = !isCount(cones) && cones != "none" && cones != "auto" && !settings.singleCone;
  return named ? cones : std::string();
}

FlattenOptions toFlattenOptions(const FlattenSettings& settings, const std::string& file) {
  FlattenOptions options;
  options.scheme = settings.scheme == "tangential"  ? MetricScheme::Tangential
                   : settings.scheme == "inversive" ? MetricScheme::Inversive
                                                    : MetricScheme::Yamabe;
  options.quantize = settings.quantize;
  options.singleCone = settings.singleCone;
  options.boundary = settings.boundary == "fixed"       ? BoundaryShape::Fixed
                     : settings.boundary == "rectangle" ? BoundaryShape::Rectangle
                                                        : BoundaryShape::Free;
  options.tolerance = settings.tolerance;
  options.maxIterations = settings.maxIterations;
  options.name = file;
  const std::string& cones = settings.cones;
  if (isCount(cones)) {
    if (!parseCount(cones, options.coneCount))
      throw InputError("--cones " + cones + ": not a number of cones from 0 to 2^31 - 1");
  } else if (cones == "none") {
    options.cones.emplace();
  } else if (const std::string path = coneFile(settings); !path.empty()) {
    options.cones = readConeFile(path);
  }
  return options;
}

Json flatteningJson(const Flattening& flattening, const FlattenOptions& options, Json& stages,
                    Command& command) {
  for (const auto& [name, seconds] : flattening.stageSeconds) stages[name] = seconds;
  const RicciResult& flow = flattening.flow;
  Json cones = Json::array();
  for (const auto& cone : flattening.cones)
    cones.push_back({{"vertex", cone.vertex},
                     {"curvature", cone.curvature},
                     {"angle", 2.0 * kPi - cone.curvature}});
  Json report{{"file", options.name},
              {"scheme", metricSchemeName(options.scheme)},
              {"cones", cones},
              {"flips", flattening.flips},
              {"rejected_cone_counts", flattening.rejectedConeCounts},
              {"cone_placement", flattening.conePlacement},
              {"reached_max_cones", flattening.reachedMaxCones}};
  if (flattening.plainSolve) {
    report["plain_solver"] = {{"message", flattening.plainSolve->message},
                              {"iterations", flattening.plainSolve->iterations}};
    report["doubled"] = flattening.doubled;
  }
  if (flattening.overlay)
    report["overlay"] = {{"faces", flattening.overlay->mesh.n_faces()},
                         {"crossings", flattening.overlay->crossingInputEdge.size()},
                         {"split_edges", flattening.splitEdges},
                         {"length_mismatch", flattening.overlay->maxLengthMismatch}};
  report["converged"] = flow.converged;
  report["message"] = flow.message;
  report["iterations"] = flow.iterations;
  report["max_curvature_error"] = flow.maxCurvatureError;
  if (flow.converged) {
    if (const auto& holonomy = flattening.holonomy)
      report["holonomy"] = {{"loops", holonomy->loops.size()},
                            {"initial_rotations", asVector(holonomy->initialRotation)},
                            {"target_rotations", asVector(holonomy->targetRotation)},
                            {"converged", holonomy->converged},
                            {"iterations", holonomy->iterations},
                            {"flips", holonomy->flips},
                            {"message", holonomy->message},
                            {"max_residual", holonomy->maxResidual},
                            {"max_log_length_change", holonomy->maxLogLengthChange}};
    const FlatLayout& layout = flattening.layout;
    report["flipped_triangles"] = layout.flippedTriangles;
    report["area_distortion"] = {{"min", flattening.areaDistortion.min},
                                 {"max", flattening.areaDistortion.max},
                                 {"mean", flattening.areaDistortion.mean}};
    report["angle_distortion"] = {{"mean", layout.meanAngleDistortion},
                                  {"max", layout.maxAngleDistortion}};
    report["layout_edge_length_error"] = layout.maxEdgeLengthError;
    report["max_seam_residual"] = layout.maxSeamResidual;
    report["seam_rotations"] = {
        {"rotated", flattening.seamRotations.rotated},
        {"max_quarter_turn_error", flattening.seamRotations.maxQuarterTurnError}};
    report["cut_edges"] = layout.cutEdges.size();
    if (layout.hasPeriods) {
      report["periods"] = {{layout.periods[0][0], layout.periods[0][1]},
                           {layout.periods[1][0], layout.periods[1][1]}};
      report["max_period_residual"] = layout.maxPeriodResidual;
    }
  }
  if (!flattening.converged) {
    report["stage_seconds"] = stages;
    command.partialResult = report;
    throw SolverError(flattening.message + " (nothing written)");
  }
  return report;
}

}  // namespace mspline::cli
