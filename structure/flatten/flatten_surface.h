#pragma once
// The flat metric as every pipeline that needs one computes it (flatten, atlas, picture, voronoi,
// spline, fit): cones (placed, given, or none), Newton on the Ricci energy (with intrinsic flips
// where the input degenerates), the rotation along handle loops quantized when asked, and the
// layout, with the figures a user is shown.
// CONTRACT (written before the implementation; the implementer may add fields and refine
// comments, but keeps these names): FlattenOptions, Flattening, flattenSurface.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/progress.h"
#include "mspline/structure/intrinsic/intrinsic_overlay.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/holonomy_quantization.h"
#include "mspline/structure/ricci/ricci_newton.h"

namespace mspline::structure {

enum class MetricScheme { Yamabe, Tangential, Inversive };
enum class BoundaryShape { Free, Fixed, Rectangle };

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
  /// Genus >= 2: all curvature in one cone.
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
  // ... (see the implementation: cones, flow, overlay, surface(), flatLengths, layout,
  // holonomy, flips, area distortion, seam rotations, per-stage seconds, converged/message)
};

/// Flattens `mesh`. Non-convergence of the flow or a layout with flipped triangles is reported in
/// the result (Flattening::converged false, with a message), not thrown; invalid options
/// (a rectangle boundary on a surface with two boundary loops, cones out of range) throw InputError.
/// `mesh` must outlive the result (Flattening::surface() may refer to it).
Flattening flattenSurface(const TriMesh& mesh, const FlattenOptions& options = {},
                          const Progress& progress = {});

}  // namespace mspline::structure
