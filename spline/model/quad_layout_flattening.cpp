#include "mspline/spline/model/quad_layout_flattening.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/motorcycle_layout.h"
#include "mspline/structure/ricci/cone_placement.h"

namespace mspline::spline {

namespace {

/// The side of the grid cells `build` asks for, in the surface's own lengths: `grid` times the
/// square root of its area, or `control` square cells covering it.
double cellSideOnSurface(const structure::TriMesh& mesh, const BuildSplineOptions& build) {
  double area = 0.0;
  for (const auto f : mesh.faces()) area += mesh.calc_face_area(f);
  return build.grid > 0.0 ? build.grid * std::sqrt(area)
                          : std::sqrt(area / double(std::max(build.control, 1)));
}

}  // namespace

QuadLayoutFlattening quadLayoutFlattening(const structure::TriMesh& mesh, int minCornerValence,
                                          const BuildSplineOptions& build,
                                          structure::FlattenOptions options) {
  if (minCornerValence < 2 || minCornerValence > 3)
    throw structure::InputError("quad layout: the smallest corner valence must be 2 or 3, not " +
                                std::to_string(minCornerValence));
  if (!(build.coneSeparationCells > 0.0) || !std::isfinite(build.coneSeparationCells))
    throw structure::InputError(
        "quad layout: the cones' separation must be a positive number of cells");
  // Knot lines must survive chart changes: quarter-turn cones and holonomy.
  options.quantize = true;
  options.maxConeQuarterTurns = 4 - minCornerValence;
  // The layout traces the seams with the default options: their angles must hold to its tolerance.
  options.seamTolerance = structure::MotorcycleLayoutOptions().angleTolerance;
  if (minCornerValence == 3)
    options.minConeSeparation = build.coneSeparationCells * cellSideOnSurface(mesh, build);
  return {options, structure::midpointLevelsForQuarterTurnCones(mesh, options.maxConeQuarterTurns)};
}

}  // namespace mspline::spline
