#pragma once
// The flattening a quad layout needs (T-splines, and subdivision surfaces on the same net), as
// `fit`, `spline` and the layout bench set it up: quantized quarter-turn cones whose corners have
// the smallest valence asked for, and the midpoint splits a coarse polyhedron needs first.
#include "mspline/spline/model/build_spline.h"
#include "mspline/structure/flatten/flatten_surface.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::spline {

struct QuadLayoutFlattening {
  /// The options given, with quantize set, maxConeQuarterTurns = 4 - minCornerValence (a cone of
  /// k quarter turns of curvature is a corner of valence 4 - k) and, with valence 3,
  /// minConeSeparation = build.coneSeparationCells grid cells' sides on the surface.
  structure::FlattenOptions options;
  /// Rounds of subdivideMidpoint the surface needs before it is flattened with `options`: a
  /// coarse polyhedron's vertices are too few for its corners' cones. The splits keep the surface
  /// and its area, so `options` hold for the split surface.
  int midpointSubdivisions = 0;
};

/// The flattening of `mesh` (closed) for a quad layout whose corners have valence
/// `minCornerValence` or more, with cells of the side `build` asks for. Throws InputError unless
/// `minCornerValence` is 2 or 3 and build.coneSeparationCells is positive.
QuadLayoutFlattening quadLayoutFlattening(const structure::TriMesh& mesh, int minCornerValence,
                                          const BuildSplineOptions& build,
                                          structure::FlattenOptions options = {});

}  // namespace mspline::spline
