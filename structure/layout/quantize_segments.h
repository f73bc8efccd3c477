#pragma once
// Whole numbers of cells for the segments of a rectangle layout (structure/layout/
// motorcycle_layout.h), the quantization of an integer-grid map: opposite sides of every rectangle
// get the same number of cells, every segment at least its minimum (0 lets it collapse), every
// separation set its least number of cells in all, and the numbers are as close as possible to
// length / cell size in relative terms (a cell's side stretched or shrunk on the surface),
//   minimize  sum_s |cells_s - t_s| / max(t_s, 0.01),   t_s = length_s / cell size,
// so that a cell a separation or a minimum demands goes to the longest of the short segments that
// can take it.
// Each segment borders two rectangles, so the constraints are those of a flow in a bidirected graph
// (quarter-turn seams make some arcs leave or enter both of their rectangles), the problem of
// "Min-Deviation-Flow in Bi-directed Graphs for T-Mesh Quantization" (Heistermann, Warnett, Bommes
// 2023). It is solved as an integer program by GLPK (branch and cut on the linear relaxation, whose
// costs are linear between whole numbers, so that its optimum is whole wherever the graph is
// directed): the optimum is exact, and a solution exists whenever the layout's own lengths satisfy
// the constraints, whatever the minima.
#include <vector>

#include "mspline/structure/layout/motorcycle_layout.h"

namespace mspline::structure {

/// Segments whose cells, summed, must reach `atLeast`.
struct SegmentSum {
  /// Indices of layout.segments(); one listed twice counts twice.
  std::vector<int> segments;
  int atLeast = 1;
};

struct QuantizeOptions {
  /// Target cell side in the layout's flat metric.
  double cellSize = 1.0;
  /// Per segment the fewest cells it may get; empty: one each.
  std::vector<int> minimumCells;
  /// Sets of segments with a least number of cells in all: one where they may not all collapse
  /// (a path of collapsed segments that joined two cones, say), more where fewer would make a
  /// cell repeat a vertex.
  std::vector<SegmentSum> separations;
  /// Time for the branch and cut (seconds): plain branching gets the first second of it, the MIP
  /// presolver with Gomory cuts the rest when that proved nothing; past it the best solution found
  /// is kept.
  double timeLimit = 20.0;
};

struct Quantization {
  /// Cells per segment (indices of layout.segments()).
  std::vector<int> segmentCells;
  /// The objective at segmentCells, and at the optimum of the linear relaxation (a lower bound).
  double deviation = 0.0;
  double relaxation = 0.0;
  /// The solver proved segmentCells optimal (false: the time limit stopped it first).
  bool optimal = false;
  /// max over segments of |cells - length / cellSize|.
  double maxRoundingError = 0.0;
  double seconds = 0.0;
};

/// Throws InputError for a non-positive cell size or minima of the wrong size, SolverError when no
/// whole numbers satisfy the constraints and the minima within the time limit.
Quantization quantizeSegments(const MotorcycleLayout& layout, const QuantizeOptions& options = {});

}  // namespace mspline::structure
