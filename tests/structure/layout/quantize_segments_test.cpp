#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/motorcycle_layout.h"
#include "mspline/structure/layout/quantize_segments.h"
#include "support/flat_metric.h"

using namespace mspline;
using structure::MotorcycleLayout;
using structure::Quantization;
using structure::QuantizeOptions;

namespace {

double rectangleArea(const MotorcycleLayout& layout) {
  double area = 0.0;
  for (const auto& r : layout.rectangles()) area += r.width() * r.height();
  return area;
}

// The objective of quantize_segments.h at `cells`.
double deviation(const MotorcycleLayout& layout, const std::vector<int>& cells, double cellSize) {
  double sum = 0.0;
  for (std::size_t s = 0; s < cells.size(); ++s) {
    const double target = layout.segments()[s].length() / cellSize;
    sum += std::abs(cells[s] - target) / std::max(target, 0.01);
  }
  return sum;
}

// Opposite sides of every rectangle get the same cells, every segment at least its minimum.
void checkValid(const MotorcycleLayout& layout, const Quantization& q,
                const std::vector<int>& minimum) {
  REQUIRE(q.segmentCells.size() == layout.segments().size());
  for (const auto& rect : layout.rectangles())
    for (int pair = 0; pair < 2; ++pair) {
      int a = 0, b = 0;
      for (int he : rect.sides[std::size_t(pair)]) a += q.segmentCells[std::size_t(he / 2)];
      for (int he : rect.sides[std::size_t(pair + 2)]) b += q.segmentCells[std::size_t(he / 2)];
      CHECK(a == b);
    }
  for (std::size_t s = 0; s < q.segmentCells.size(); ++s)
    CHECK(q.segmentCells[s] >= (minimum.empty() ? 1 : minimum[s]));
}

}  // namespace

TEST_CASE("quantize_segments: opposite sides equal, minima held, the optimum proven",
          "[structure]") {
  const test::FlatMetric flat = test::eightConeSphere();
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  QuantizeOptions options;
  options.cellSize = std::sqrt(rectangleArea(layout) / 600.0);
  const Quantization q = structure::quantizeSegments(layout, options);
  checkValid(layout, q, {});
  CHECK(q.optimal);
  CHECK(q.deviation == Approx(deviation(layout, q.segmentCells, options.cellSize)).epsilon(1e-9));
  // The relaxation bounds the optimum from below, and closely: its costs are linear between whole
  // numbers, so it is whole but where quarter-turn seams make the graph bidirected.
  CHECK(q.relaxation <= q.deviation + 1e-9);
  CHECK(q.deviation - q.relaxation < 0.1 * q.deviation + 1e-9);
  CHECK(q.maxRoundingError < 2.0);
  // At half the cell size, twice these cells are a solution: the optimum there is no worse.
  QuantizeOptions finer = options;
  finer.cellSize = options.cellSize / 2.0;
  std::vector<int> doubled = q.segmentCells;
  for (int& cells : doubled) cells *= 2;
  const Quantization fine = structure::quantizeSegments(layout, finer);
  checkValid(layout, fine, {});
  CHECK(fine.deviation <= deviation(layout, doubled, finer.cellSize) + 1e-9);
}

TEST_CASE("quantize_segments: segments far shorter than a cell still get their minima",
          "[structure]") {
  const test::FlatMetric flat = test::eightConeSphere();
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  double longest = 0.0;
  for (const auto& segment : layout.segments()) longest = std::max(longest, segment.length());
  QuantizeOptions options;
  options.cellSize = 20.0 * longest;
  // Two cells on every other segment, none required on the rest.
  options.minimumCells.resize(layout.segments().size());
  for (std::size_t s = 0; s < options.minimumCells.size(); ++s)
    options.minimumCells[s] = s % 2 == 0 ? 2 : 0;
  // And a cell among segments 1, 3 and 5, which may collapse.
  options.separations = {{{1, 3, 5}, 1}};
  const Quantization q = structure::quantizeSegments(layout, options);
  checkValid(layout, q, options.minimumCells);
  CHECK(q.segmentCells[1] + q.segmentCells[3] + q.segmentCells[5] >= 1);
  CHECK(q.optimal);
  // Three cells among them, segment 1 counted twice.
  options.separations = {{{1, 1, 3, 5}, 3}};
  const Quantization more = structure::quantizeSegments(layout, options);
  checkValid(layout, more, options.minimumCells);
  CHECK(2 * more.segmentCells[1] + more.segmentCells[3] + more.segmentCells[5] >= 3);
  CHECK(more.deviation >= q.deviation - 1e-12);
}

TEST_CASE("quantize_segments: bad options are refused", "[structure]") {
  const test::FlatMetric flat = test::eightConeSphere();
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  QuantizeOptions options;
  options.cellSize = 0.0;
  CHECK_THROWS_AS(structure::quantizeSegments(layout, options), structure::InputError);
  options.cellSize = 0.1;
  options.minimumCells = {1, 2};
  CHECK_THROWS_WITH(structure::quantizeSegments(layout, options), Catch::Contains("2 minima for"));
}
