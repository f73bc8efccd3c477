#pragma once
// A seamless quad mesh from a rectangle layout (structure/layout/motorcycle_layout.h): every
// segment of the layout gets a whole number of cells, chosen so that opposite sides of every
// rectangle get the same number (an integer-grid map in the sense of Bommes et al. and Campen et
// al.: the rectangles, rescaled to whole sides, glue to a flat surface with the same cones), then
// every rectangle is gridded into unit cells. Grid lines meet across every side, so the T-mesh has
// no T-junctions; its only extraordinary vertices are the cones, and every knot interval is one,
// which makes the cubic T-spline a uniform B-spline wherever the mesh is regular (OpenSubdiv's
// limit surface there).
//
// Rounding: the whole numbers of cells are the exact optimum of an integer program
// (structure/layout/quantize_segments.h): closest to length / cell size in relative terms under
// the rectangles' constraints, so a layout whose segments are far shorter than a cell still gets a
// grid (they get one cell each where they may not collapse), whatever parities the quarter-turn
// holonomy imposes.
//
// Collapse: a segment shorter than a quarter of a cell (an option) may get no cell. Its two nodes
// become one T-mesh vertex, and a rectangle left without cells across (two traces running that
// close) has its two long sides glued together. Without this, the sliver between two nearly
// coincident traces got a whole cell across and cells a million times longer than wide (ellipsoid).
// A collapse that joins two cones or repeats a vertex in a cell is undone where it happened: the
// chain of collapses that joined them must get a cell somewhere (a separation constraint, as in
// quantized global parametrization) and the integer program is solved again; a collapse that
// breaks the mesh otherwise gives a cell to the collapsed segments longer than a tenth of a cell,
// and to all of them if it still breaks.
#include <array>
#include <vector>

#include "mspline/spline/tspline/tmesh.h"
#include "mspline/structure/layout/motorcycle_layout.h"

namespace mspline::spline {

struct LayoutTMeshOptions {
  /// Target cell side in the layout's flat metric.
  double cellSize = 1.0;
  /// A segment shorter than this many cells may get no cell. Its points are crushed onto a line,
  /// which the fit follows badly where the strip is wide (homer folded 1,373 times at half a
  /// cell); a whole cell across a strip stretches the cells instead. Over the data set a quarter
  /// of a cell gave fewer stretched cells and fewer folds than a tenth, though not on every mesh
  /// (README).
  double collapseBelow = 0.25;
};

struct LayoutTMesh {
  TMesh mesh;
  /// The cell size asked for (the unit of segmentCells).
  double cellSize = 0.0;
  /// Cells along each layout segment (0: collapsed), and per rectangle its cells along x and y.
  std::vector<int> segmentCells;
  std::vector<std::array<int, 2>> rectangleCells;
  /// T-mesh face of cell (i, j) of rectangle r: firstCell[r] + j * cells along x + i; -1 for a
  /// collapsed rectangle (no cells along x or y).
  std::vector<int> firstCell;
  /// Per collapsed rectangle (empty for the others), per cell along the side it kept: the T-mesh
  /// points at that cell side's two ends, in one face. A 0 x 0 rectangle keeps one point.
  std::vector<std::vector<std::array<FacePoint, 2>>> collapsedSteps;
  /// Segments given no cell, and rectangles left without area.
  int collapsedSegments = 0;
  int collapsedRectangles = 0;
  /// max over segments of |cells - length / cellSize|.
  double maxRoundingError = 0.0;
  /// max over rectangles of the ratio of its two scale factors (cells per flat length along x
  /// and along y), >= 1, over the rectangles with cells: how far from square the cells are on the
  /// surface.
  double maxAnisotropy = 1.0;
  /// The same ratio's 99th percentile over the cells (each cell has its rectangle's).
  double anisotropyP99 = 1.0;
  /// Integer programs solved (one, and one more per collapse undone), their time in seconds, and
  /// whether every one was solved to proven optimality (false: one stopped at its time limit).
  int quantizations = 0;
  double quantizationSeconds = 0.0;
  bool quantizationOptimal = false;
};

/// A rectangle whose cells would repeat a vertex gets one more cell along the directions in which
/// the two corners differ (in all: a 1 x 1 rectangle with one cone at opposite corners becomes
/// 2 x 1 or 1 x 2, whichever the quantization's deviation from the segments' lengths prefers), a
/// collapse that fails is undone. Throws SolverError when no valid grid is found.
LayoutTMesh layoutTMesh(const structure::MotorcycleLayout& layout,
                        const LayoutTMeshOptions& options = {});

/// The point of the T-mesh at a point of the layout: the rectangle rescaled to its cells, the
/// sides piecewise linearly through their nodes, the inside blended between opposite sides
/// (continuous across rectangles); a point of a collapsed rectangle goes to the side it kept.
FacePoint layoutPoint(const structure::MotorcycleLayout& layout, const LayoutTMesh& grid,
                      const structure::RectanglePoint& point);

}  // namespace mspline::spline
