#pragma once
// The flat metric as every command that needs one computes it (flatten, atlas, picture,
// voronoi): cones, Newton on the Ricci energy (with intrinsic flips where the input degenerates),
// and the layout, with the figures reported in JSON.
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cli/command.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/intrinsic/intrinsic_overlay.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::cli {

/// Seconds since the previous lap (or construction).
class Stopwatch {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

/// The command-line choices of the flattening; defaults as documented in addFlattenOptions.
struct FlattenSettings {
  std::string scheme = "yamabe";
  std::string cones = "auto";
  bool quantize = false;
  /// With quantize: the largest cone curvature in quarter turns (ConePlacementOptions).
  int maxConeQuarterTurns = 3;
  bool singleCone = false;
  std::string boundary = "free";
  double tolerance = 1e-10;
  int maxIterations = 100;
  bool quiet = false;
};

/// Whether `text` is a whole number written in decimal digits (e.g. a count given where a file
/// name is also accepted).
bool isCount(const std::string& text);

/// Adds --scheme, --cones, --quantize, --single-cone, --boundary, --tolerance (named
/// `toleranceFlag`, for commands with a tolerance of their own), --max-iterations and -q/--quiet
/// to a subcommand.
void addFlattenOptions(CLI::App& sub, FlattenSettings& settings,
                       const std::string& toleranceFlag = "--tolerance");

/// A flat metric with cones, laid out.
struct Flattening {
  /// The cones asked for (interior; boundary shapes are not listed).
  std::vector<structure::Cone> cones;
  /// The solve; u has one entry per input vertex.
  structure::RicciResult flow;
  /// The common subdivision when intrinsic flips were needed (then it is the surface laid out).
  std::optional<structure::IntrinsicOverlay> overlay;
  /// The input mesh (owned by the caller).
  const structure::TriMesh* input = nullptr;
  /// The surface laid out: the overlay when there is one, else the input. (A function, not a
  /// pointer kept in the struct, so that moving a Flattening cannot leave it dangling.)
  const structure::TriMesh& surface() const { return overlay ? overlay->mesh : *input; }
  /// Its flat edge lengths.
  Eigen::VectorXd flatLengths;
  structure::FlatLayout layout;
};

/// Flattens `mesh` (read from `file`), reporting progress through `progress` and the figures in
/// `report` (converged, iterations, max_curvature_error, cones, flips, flipped_triangles,
/// area_distortion, angle_distortion, seam and period figures) and per-stage seconds in `stages`.
/// Throws SolverError, with the report so far in command.partialResult, when the flow does not
/// converge or the layout has flipped triangles.
Flattening flattenMesh(const structure::TriMesh& mesh, const std::string& file,
                       const FlattenSettings& settings, Command& command, Json& report,
                       Json& stages, const std::function<void(const std::string&)>& progress);

}  // namespace mspline::cli
