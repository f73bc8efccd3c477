#pragma once
// The flat metric as every pipeline that needs one computes it (flatten, atlas, picture, voronoi,
// spline, fit): cones (placed, given, or none), Newton on the Ricci energy (with intrinsic flips
// where the input degenerates), the rotation along handle loops quantized when asked, and the
// layout, with the figures a user is shown.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/progress.h"
#include "mspline/structure/intrinsic/holonomy_quantization.h"
#include "mspline/structure/intrinsic/intrinsic_overlay.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"

namespace mspline::structure {

enum class MetricScheme { Yamabe, Tangential, Inversive };
enum class BoundaryShape { Free, Fixed, Rectangle };

/// "yamabe", "tangential" or "inversive".
std::string metricSchemeName(MetricScheme scheme);

struct FlattenOptions {
  /// Discrete metric: vertex scaling (default), Thurston's circle packing or inversive distance.
  MetricScheme scheme = MetricScheme::Yamabe;
  /// Cones given by the caller (an empty list: no cones); when unset they are placed
  /// automatically (structure/ricci/cone_placement.h), `coneCount` of them when >= 0.
  std::optional<std::vector<Cone>> cones;
  int coneCount = -1;
  /// Cone curvatures multiples of pi/2 (seamless metrics), at most this many quarter turns.
  bool quantize = false;
  int maxConeQuarterTurns = 3;
  /// Quantized handle rotations: a metric whose laid-out seams miss quarter turns by more than
  /// this (radians) is rejected like one that cannot be quantized. A quad layout of the result
  /// needs at most its MotorcycleLayoutOptions::angleTolerance (the same default).
  double seamTolerance = 1e-6;
  /// Automatic cones at least this far apart along edges (ConePlacementOptions::
  /// minSeparationLength); 0: two edges apart.
  double minConeSeparation = 0.0;
  /// Genus >= 2: all curvature in one cone (placed automatically; `cones` is then ignored).
  bool singleCone = false;
  /// Open surfaces: boundary lengths kept (Free), a circle (Fixed) or a rectangle.
  BoundaryShape boundary = BoundaryShape::Free;
  /// Stop when max |K - K_target| <= tolerance (radians).
  double tolerance = 1e-10;
  int maxIterations = 100;
  /// Names the surface (its file) in messages.
  std::string name;
};

/// A flat metric with cones, laid out, and how it went.
struct Flattening {
  /// The cones asked for (interior; boundary shapes are not listed).
  std::vector<Cone> cones;
  /// Automatic cones: the placement's outcome in one line (ConePlacementResult::message), and
  /// whether it stopped at its maximum number of cones with the metric still stretching more
  /// than asked (a warning: the flattening is valid). Empty and false for cones given.
  std::string conePlacement;
  bool reachedMaxCones = false;
  /// The solve; u has one entry per input vertex.
  RicciResult flow;
  /// The common subdivision when intrinsic flips were needed, by the flow or by the holonomy
  /// quantization (then it is the surface laid out).
  std::optional<IntrinsicOverlay> overlay;
  /// The input mesh (owned by the caller).
  const TriMesh* input = nullptr;
  /// The surface laid out: the overlay when there is one, else the input. (A function, not a
  /// pointer kept in the struct, so that moving a Flattening cannot leave it dangling.)
  const TriMesh& surface() const { return overlay ? overlay->mesh : *input; }
  /// Its flat edge lengths (empty when the flow did not converge).
  Eigen::VectorXd flatLengths;
  /// The layout of surface() (empty when the flow did not converge). It also holds the angle
  /// distortion, the seams and, on a flat torus, the periods.
  FlatLayout layout;

  /// The plain solve on the input triangulation, when it degenerated and the flow went on with
  /// intrinsic Delaunay flips.
  struct PlainSolve {
    std::string message;
    int iterations = 0;
  };
  std::optional<PlainSolve> plainSolve;
  /// Intrinsic flips behind the overlay, the quantization's included (0 without an overlay).
  int flips = 0;
  /// With the fallback: whether the surface (one with boundary) was doubled.
  bool doubled = false;
  /// With an overlay: interior edges between boundary vertices split before doubling.
  int splitEdges = 0;

  /// The handle rotations made quarter turns (quantize on a closed surface of genus >= 1 but a
  /// torus without cones, whose flat metric rotates along no loop). When
  /// it did not converge the flat metric stays the conformal one and seams across handles turn by
  /// arbitrary angles.
  std::optional<HolonomyQuantizationResult> holonomy;

  /// Automatic cones only: the sizes of the cone sets tried first, in order, whose handle
  /// rotations could not be quantized (empty when the first set worked). When the last set tried
  /// failed too, `holonomy` reports it.
  std::vector<int> rejectedConeCounts;
  /// Per input vertex, the factor exp(2u) by which the flat metric scales area (u shifted so that
  /// the flat metric has the input's total area): its range and mean.
  struct AreaDistortion {
    double min = 0.0, max = 0.0, mean = 0.0;
  };
  AreaDistortion areaDistortion;

  /// Seams turning by a nonzero number of quarter turns, and the largest distance of a seam
  /// rotation from a multiple of pi/2 (radians; 0 up to rounding with quantized cones).
  struct SeamRotations {
    int rotated = 0;
    double maxQuarterTurnError = 0.0;
  };
  SeamRotations seamRotations;

  /// Wall-clock seconds per stage, in order: cones, ricci_flow, ricci_flow_flips (fallback),
  /// holonomy (quantization), layout; summed over the cone sets tried (rejectedConeCounts).
  std::vector<std::pair<std::string, double>> stageSeconds;

  /// The flow converged and the layout has no flipped triangle.
  bool converged = false;
  /// When not converged, why (naming the surface); else the flow's message.
  std::string message;
};

/// Flattens `mesh`. With automatic cones (no `cones`, `coneCount` -1, not `singleCone`) whose
/// handle rotations cannot be quantized, other automatic cone sets are tried (a few more cones,
/// then fewer, down to none on a torus; at most 4 sets in all), and the first that works is kept;
/// a set whose flattening throws is passed over.
/// Non-convergence of the flow or a layout with flipped triangles is reported in
/// the result (Flattening::converged false, with a message), not thrown; invalid options
/// (a rectangle boundary on a surface with two boundary loops, cones out of range) throw
/// InputError. `mesh` must outlive the result (Flattening::surface() may refer to it). Progress:
/// one line per step (stage names are messages, reported at fraction 1).
Flattening flattenSurface(const TriMesh& mesh, const FlattenOptions& options = {},
                          const Progress& progress = {});

}  // namespace mspline::structure
