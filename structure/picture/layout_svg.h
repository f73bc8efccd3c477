#pragma once
// A picture of a flat layout as SVG text: the triangles, the seams, the cones and, for a flat
// torus, a piece of the universal cover tiled by the periods.
#include <array>
#include <string>
#include <vector>

#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct LayoutSvgOptions {
  /// Width of the drawing in pixels; the height follows the layout's aspect ratio.
  double width = 800.0;
  /// With periods: also draw the layout translated by i p0 + j p1 for all |i|, |j| <= coverRadius
  /// (1 gives the 3 x 3 copies of a finite piece of the universal cover). 0 draws the layout alone.
  int coverRadius = 0;
};

/// Maps layout coordinates to SVG pixels (y up in the layout, down in SVG).
struct SvgFrame {
  Eigen::Vector2d low;
  double top = 0.0;
  double scale = 1.0;
  double margin = 10.0;
  /// The drawing's size in pixels, margins included.
  double width = 0.0;
  double height = 0.0;
  /// The frame showing the box [low, high] `drawingWidth` pixels wide.
  static SvgFrame fit(const Eigen::Vector2d& low, const Eigen::Vector2d& high, double drawingWidth);
  Eigen::Vector2d operator()(const Eigen::Vector2d& p) const {
    return {margin + (p.x() - low.x()) * scale, margin + (top - p.y()) * scale};
  }
};

/// The deck translations i p0 + j p1 for |i|, |j| <= radius (only zero for radius 0).
std::vector<Eigen::Vector2d> coverShifts(const FlatLayout& layout, int radius);

/// Lower and upper corners of the box holding every layout corner moved by every shift.
std::array<Eigen::Vector2d, 2> shiftedBounds(const FlatLayout& layout,
                                             const std::vector<Eigen::Vector2d>& shifts);

/// The SVG document: one <polygon> per drawn face (the layout's copy is filled darker), each
/// seam edge in red on both sides, the boundary in black, cones as blue dots and, with periods,
/// the fundamental parallelogram as a green <path>. Throws InputError for coverRadius > 0 on a
/// layout without periods or for coverRadius < 0.
std::string layoutSvg(const TriMesh& mesh, const FlatLayout& layout,
                      const LayoutSvgOptions& options = {});

}  // namespace mspline::structure
