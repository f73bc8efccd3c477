#include "cli/spline_space_json.h"

namespace mspline::cli {

Json gridJson(const spline::GridFigures& grid) {
  if (grid.torus)
    return {{"layout", "torus lattice"},
            {"cells", {grid.cellsAlongFirst, grid.cellsAlongSecond}},
            {"anisotropy", grid.anisotropy},
            {"anisotropy_p99", grid.anisotropyP99},
            {"extraordinary_points", grid.extraordinaryPoints}};
  return {{"layout", "motorcycle graph"},
          {"traces", grid.traces},
          {"frame_angle", grid.frameAngle},
          {"frame_turned_because", grid.frameTurnedBecause},
          {"rectangles", grid.rectangles},
          {"cell_size", grid.cellSize},
          {"max_rounding_error", grid.maxRoundingError},
          {"collapsed_segments", grid.collapsedSegments},
          {"collapsed_rectangles", grid.collapsedRectangles},
          {"quantization",
           {{"optimal", grid.quantizationOptimal},
            {"solves", grid.quantizations},
            {"seconds", grid.quantizationSeconds}}},
          {"anisotropy", grid.anisotropy},
          {"anisotropy_p99", grid.anisotropyP99},
          {"extraordinary_points", grid.extraordinaryPoints}};
}

Json domainJson(const spline::DomainFigures& domain) {
  return {
      {"domain_vertices", domain.vertices},
      {"domain_faces", domain.faces},
      {"cones", domain.cones},
      {"unremoved_vertices", domain.unremovedVertices},
      {"cone_separating_vertices", domain.coneSeparatingVertices},
      {"cone_sides", domain.coneSides},
      {"tracking_error", domain.trackingError},
      {"domain_flatness", {{"before", domain.flatnessBefore}, {"after", domain.flatnessAfter}}}};
}

}  // namespace mspline::cli
