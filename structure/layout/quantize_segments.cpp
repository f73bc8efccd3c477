#include "mspline/structure/layout/quantize_segments.h"

#include <glpk.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"

namespace mspline::structure {
namespace {

// Plain branching's first try (seconds); see quantizeSegments.
constexpr double kPlainBranchingSeconds = 1.0;

}  // namespace

Quantization quantizeSegments(const MotorcycleLayout& layout, const QuantizeOptions& options) {
  const auto& segments = layout.segments();
  const auto& rectangles = layout.rectangles();
  const int n = int(segments.size());
  if (!(options.cellSize > 0.0)) throw InputError("quantize segments: cell size must be positive");
  if (!options.minimumCells.empty() && int(options.minimumCells.size()) != n)
    throw InputError("quantize segments: " + std::to_string(options.minimumCells.size()) +
                     " minima for " + std::to_string(n) + " segments");
  Stopwatch clock;
  std::unique_ptr<glp_prob, decltype(&glp_delete_prob)> problem(glp_create_prob(),
                                                                &glp_delete_prob);
  glp_prob* lp = problem.get();
  glp_set_obj_dir(lp, GLP_MIN);
  // The cost of a segment is taken at whole numbers and linear between them (the convex hull of
  // its values there), so that the relaxation's vertices are whole wherever the constraints are a
  // directed graph's: with the kink at the fractional target it would simply return the targets.
  // Columns per segment s (1-based): cells 4s+1 (integer) = base + up to the next whole number
  // (4s+2, at most 1) + further up (4s+3) - down (4s+4), base = max(floor(target), minimum).
  glp_add_cols(lp, 4 * n);
  std::vector<double> target(static_cast<std::size_t>(n)), weight(target);
  double baseCost = 0.0;
  std::vector<int> rowIndex{0}, columnIndex{0};
  std::vector<double> value{0.0};
  const auto entry = [&](int row, int column, double coefficient) {
    rowIndex.push_back(row);
    columnIndex.push_back(column);
    value.push_back(coefficient);
  };
  glp_add_rows(lp, n);
  for (int s = 0; s < n; ++s) {
    const double t = segments[std::size_t(s)].length() / options.cellSize;
    const int minimum = options.minimumCells.empty() ? 1 : options.minimumCells[std::size_t(s)];
    const double w = 1.0 / std::max(t, 0.01);
    target[std::size_t(s)] = t;
    weight[std::size_t(s)] = w;
    const double base = std::max(std::floor(t), double(minimum));
    baseCost += w * std::abs(base - t);
    const int cells = 4 * s + 1, up = cells + 1, further = cells + 2, down = cells + 3;
    glp_set_col_kind(lp, cells, GLP_IV);
    glp_set_col_bnds(lp, cells, GLP_LO, double(minimum), 0.0);
    // From base = floor(t) the first step up costs w (1 - 2 (t - base)); from a base above t,
    // every step costs w.
    const bool belowTarget = base < t;
    glp_set_col_bnds(lp, up, belowTarget ? GLP_DB : GLP_FX, 0.0, belowTarget ? 1.0 : 0.0);
    glp_set_obj_coef(lp, up, belowTarget ? w * (1.0 - 2.0 * (t - base)) : 0.0);
    glp_set_col_bnds(lp, further, GLP_LO, 0.0, 0.0);
    glp_set_obj_coef(lp, further, w);
    const double downRoom = base - double(minimum);
    glp_set_col_bnds(lp, down, downRoom > 0.0 ? GLP_DB : GLP_FX, 0.0, downRoom);
    glp_set_obj_coef(lp, down, w);
    glp_set_row_bnds(lp, s + 1, GLP_FX, base, base);
    entry(s + 1, cells, 1.0);
    entry(s + 1, up, -1.0);
    entry(s + 1, further, -1.0);
    entry(s + 1, down, 1.0);
  }
  // Opposite sides of a rectangle: as many cells on sides 0 and 2, and on 1 and 3. A segment can
  // lie on two sides of one rectangle, so coefficients are summed before they are loaded.
  for (const LayoutRectangle& rect : rectangles)
    for (int pair = 0; pair < 2; ++pair) {
      std::map<int, double> coefficients;
      for (int he : rect.sides[std::size_t(pair)]) coefficients[he / 2] += 1.0;
      for (int he : rect.sides[std::size_t(pair + 2)]) coefficients[he / 2] -= 1.0;
      const int row = glp_add_rows(lp, 1);
      glp_set_row_bnds(lp, row, GLP_FX, 0.0, 0.0);
      for (const auto& [s, c] : coefficients)
        if (c != 0.0) entry(row, 4 * s + 1, c);
    }
  for (const SegmentSum& separation : options.separations) {
    std::map<int, double> coefficients;
    for (int s : separation.segments) {
      if (s < 0 || s >= n)
        throw InputError("quantize segments: a separation names segment " + std::to_string(s) +
                         " of " + std::to_string(n));
      coefficients[s] += 1.0;
    }
    const int row = glp_add_rows(lp, 1);
    glp_set_row_bnds(lp, row, GLP_LO, double(separation.atLeast), 0.0);
    for (const auto& [s, c] : coefficients) entry(row, 4 * s + 1, c);
  }
  glp_load_matrix(lp, int(value.size()) - 1, rowIndex.data(), columnIndex.data(), value.data());

  glp_term_out(GLP_OFF);
  glp_smcp simplex;
  glp_init_smcp(&simplex);
  simplex.msg_lev = GLP_MSG_OFF;
  if (glp_simplex(lp, &simplex) != 0 || glp_get_status(lp) != GLP_OPT)
    throw SolverError("quantize segments: the rectangles' constraints have no solution with " +
                      std::string("the segments' minima (linear relaxation)"));
  Quantization result;
  result.relaxation = baseCost + glp_get_obj_val(lp);
  // GLPK's branching is erratic where quarter-turn seams give the relaxation fractional vertices:
  // plain branching proves nearly every quantization of the data set optimal within milliseconds,
  // but searched one of femur's (1,500 control points) for its whole limit without meeting a whole
  // solution; the MIP presolver with Gomory cuts settles that one at once and stalls on another of
  // femur's (2,200). So plain branching gets a short first try, and the presolver with cuts, on a
  // copy (the first try leaves the problem's data as they were, and the presolver needs no
  // basis), the rest of the time limit unless the first try proved its optimum.
  const double limit = std::min(options.timeLimit, 1e6);
  const auto branchAndCut = [](glp_prob* mip, bool presolveAndCuts, double seconds) {
    glp_iocp branch;
    glp_init_iocp(&branch);
    branch.msg_lev = GLP_MSG_OFF;
    branch.presolve = branch.gmi_cuts = presolveAndCuts ? GLP_ON : GLP_OFF;
    branch.tm_lim = std::max(1, int(seconds * 1000.0));
    return glp_intopt(mip, &branch);
  };
  glp_prob* solved = lp;
  int code = branchAndCut(lp, false, std::min(kPlainBranchingSeconds, limit));
  int status = glp_mip_status(lp);
  std::unique_ptr<glp_prob, decltype(&glp_delete_prob)> copy(nullptr, &glp_delete_prob);
  if (status != GLP_OPT && limit > kPlainBranchingSeconds) {
    copy.reset(glp_create_prob());
    glp_copy_prob(copy.get(), lp, GLP_OFF);
    const int codeWithCuts = branchAndCut(copy.get(), true, limit - kPlainBranchingSeconds);
    const int statusWithCuts = glp_mip_status(copy.get());
    if (statusWithCuts == GLP_OPT ||
        (statusWithCuts == GLP_FEAS &&
         (status != GLP_FEAS || glp_mip_obj_val(copy.get()) < glp_mip_obj_val(lp)))) {
      solved = copy.get();
      code = codeWithCuts;
      status = statusWithCuts;
    }
  }
  if ((code != 0 && code != GLP_ETMLIM) || (status != GLP_OPT && status != GLP_FEAS))
    throw SolverError("quantize segments: no whole numbers of cells satisfy the rectangles' " +
                      std::string("constraints") +
                      (code == GLP_ETMLIM ? " within the time limit" : ""));
  result.optimal = status == GLP_OPT;
  result.segmentCells.resize(std::size_t(n));
  for (int s = 0; s < n; ++s) {
    const int cells = int(std::lround(glp_mip_col_val(solved, 4 * s + 1)));
    const double deviation = std::abs(cells - target[std::size_t(s)]);
    result.segmentCells[std::size_t(s)] = cells;
    result.deviation += weight[std::size_t(s)] * deviation;
    result.maxRoundingError = std::max(result.maxRoundingError, deviation);
  }
  result.seconds = clock.lap();
  return result;
}

}  // namespace mspline::structure
