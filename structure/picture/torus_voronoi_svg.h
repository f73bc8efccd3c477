#pragma once
// A picture of a Voronoi diagram on a flat torus as SVG text, drawn on the torus's layout.
#include <string>
#include <vector>

#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/layout/flat_torus_voronoi.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct TorusVoronoiSvgOptions {
  /// Width of the drawing in pixels; the height follows the layout's aspect ratio.
  double width = 800.0;
  /// Also draw the layout translated by i p0 + j p1 for all |i|, |j| <= coverRadius (1 gives
  /// 3 x 3 copies of a piece of the universal cover). Must be >= 0.
  int coverRadius = 0;
};

/// The SVG document: one <polygon> per drawn face filled with its cell's colour (paler on the
/// translated copies), one black <line> per boundary segment, one <circle> per drawn site and the
/// fundamental parallelogram as a green <path>. Throws InputError for a negative coverRadius or
/// a layout without periods.
std::string torusVoronoiSvg(const TriMesh& mesh, const FlatLayout& layout,
                            const std::vector<SurfacePoint>& sites, const TorusVoronoi& voronoi,
                            const TorusVoronoiSvgOptions& options = {});

}  // namespace mspline::structure
