#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "mspline/spline/model/quad_layout_flattening.h"
#include "mspline/spline/tspline/layout_tmesh.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_check.h"
#include "mspline/spline/tspline/tspline_refine.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/motorcycle_layout.h"
#include "support/flat_metric.h"
#include "support/test_data.h"

using namespace mspline;

namespace {

// checkTSpline of random control points (seeded) at 3,000 points: the charts agree (a seamless
// T-spline evaluates the same in every chart).
spline::TSplineCheck checkSeamless(const spline::TSplineSpace& space, unsigned seed) {
  std::mt19937 random(seed);
  Eigen::MatrixXd control(space.numBasis(), 3);
  for (Eigen::Index i = 0; i < control.size(); ++i) control.data()[i] = double(random() % 1000);
  spline::TSplineCheckOptions checkOptions;
  checkOptions.samples = 3000;
  const auto check = spline::checkTSpline(space, control, {}, checkOptions);
  CHECK(check.chartDiscrepancy <= 1e-14);
  return check;
}

// Opposite sides of every rectangle got the same cells, the rectangle's.
void checkOppositeSides(const structure::MotorcycleLayout& layout,
                        const spline::LayoutTMesh& grid) {
  for (std::size_t r = 0; r < layout.rectangles().size(); ++r)
    for (int pair = 0; pair < 2; ++pair) {
      int a = 0, b = 0;
      for (int he : layout.rectangles()[r].sides[std::size_t(pair)])
        a += grid.segmentCells[std::size_t(he / 2)];
      for (int he : layout.rectangles()[r].sides[std::size_t(pair + 2)])
        b += grid.segmentCells[std::size_t(he / 2)];
      CHECK(a == b);
      CHECK(a == grid.rectangleCells[r][std::size_t(pair)]);
    }
}

// The cell side that divides the layout's flat area into about `cells` squares.
double cellSizeFor(const structure::MotorcycleLayout& layout, double cells) {
  double area = 0.0;
  for (const auto& r : layout.rectangles()) area += r.width() * r.height();
  return std::sqrt(area / cells);
}

}  // namespace

TEST_CASE("layout_tmesh: a seamless quad mesh with the cones as its only extraordinary points",
          "[spline]") {
  const test::FlatMetric flat = test::eightConeSphere();
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  spline::LayoutTMeshOptions options;
  options.cellSize = cellSizeFor(layout, 600);
  const spline::LayoutTMesh grid = spline::layoutTMesh(layout, options);
  const spline::TMesh& mesh = grid.mesh;
  // About the cells asked for, all unit squares, no T-junctions.
  CHECK(mesh.numFaces() > 400);
  CHECK(mesh.numFaces() < 900);
  long edges = 0;
  for (const auto& face : mesh.faces) {
    CHECK(face.vertices.size() == 4);
    CHECK(face.width == 1.0);
    CHECK(face.height == 1.0);
    edges += 4;
  }
  // A closed surface of genus 0: V - E + F = 2.
  CHECK(mesh.numVertices - edges / 2 + mesh.numFaces() == 2);
  int extraordinary = 0;
  for (int v = 0; v < mesh.numVertices; ++v) {
    CHECK_FALSE(mesh.onBoundary[v]);
    if (!mesh.isExtraordinary(v)) continue;
    ++extraordinary;
    CHECK(mesh.quarterTurnsAround[v] == 3);
  }
  CHECK(extraordinary == 8);
  checkOppositeSides(layout, grid);
  // A segment gets no cell only when shorter than the collapse threshold.
  for (std::size_t e = 0; e < grid.segmentCells.size(); ++e)
    if (grid.segmentCells[e] == 0)
      CHECK(layout.segments()[e].length() < options.collapseBelow * grid.cellSize);
  CHECK(grid.maxRoundingError < 3.0);
}

TEST_CASE("layout_tmesh: surface points land in their rectangle's cells", "[spline]") {
  const test::FlatMetric flat = test::eightConeSphere();
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  spline::LayoutTMeshOptions options;
  options.cellSize = 0.05;
  const spline::LayoutTMesh grid = spline::layoutTMesh(layout, options);
  std::mt19937 random(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int s = 0; s < 200; ++s) {
    const int face = int(random() % flat.surface.n_faces());
    const double a = unit(random), b = unit(random) * (1.0 - a);
    const structure::RectanglePoint point = layout.locate(face, Eigen::Vector3d(1.0 - a - b, a, b));
    const spline::FacePoint cell = spline::layoutPoint(layout, grid, point);
    const int first = grid.firstCell[std::size_t(point.rectangle)];
    const auto [cellsX, cellsY] = grid.rectangleCells[std::size_t(point.rectangle)];
    CHECK(cell.face >= first);
    CHECK(cell.face < first + cellsX * cellsY);
    CHECK(cell.position.minCoeff() >= 0.0);
    CHECK(cell.position.maxCoeff() <= 1.0);
    // Corners of the rectangle go to the corner cells.
    const auto& r = layout.rectangles()[std::size_t(point.rectangle)];
    structure::RectanglePoint corner = point;
    corner.position = {r.width(), r.height()};
    CHECK(spline::layoutPoint(layout, grid, corner).face == first + cellsX * cellsY - 1);
    CHECK(spline::layoutPoint(layout, grid, corner).position == Eigen::Vector2d(1.0, 1.0));
  }
}

TEST_CASE("layout_tmesh: the T-spline on it is seamless, with caps at the cones", "[spline]") {
  const test::FlatMetric flat = test::eightConeSphere();
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  spline::LayoutTMeshOptions options;
  options.cellSize = 0.05;
  const spline::TSplineSpace space(spline::layoutTMesh(layout, options).mesh);
  // Every vertex anchors a function; the three faces around each cone (valence 3) are caps.
  CHECK(space.missingAnchors().empty());
  CHECK(space.capFaces().size() == 8 * 3);
  const auto check = checkSeamless(space, 4);
  CHECK(check.edgeSamples > 2500);
  CHECK(check.partitionOfUnityErrorAway <= 1e-13);
  CHECK(check.awaySamples > 1500);
  CHECK(check.holeSamples == 0);
  CHECK(check.minDenominator > 0.0);
}

TEST_CASE("layout_tmesh: rectangles thinner than a tenth of a cell collapse, cones stay apart",
          "[spline]") {
  // Cones in tight clusters on cow.off leave rectangles a thousandth of a cell wide between them.
  const test::FlatMetric flat = test::clusteredConesCow();
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  int cones = 0;
  for (const auto& node : layout.nodes()) cones += node.vertex >= 0;
  double area = 0.0, thinnest = INFINITY;
  for (const auto& r : layout.rectangles()) {
    area += r.width() * r.height();
    thinnest = std::min({thinnest, r.width(), r.height()});
  }
  spline::LayoutTMeshOptions options;
  options.cellSize = std::sqrt(area / 2000.0);
  // A whole cell across such a sliver would make cells thousands of times longer than wide.
  REQUIRE(thinnest < 0.1 * options.cellSize);
  const spline::LayoutTMesh grid = spline::layoutTMesh(layout, options);
  CHECK(grid.collapsedRectangles > 0);
  CHECK(grid.collapsedSegments > 0);
  const spline::TMesh& mesh = grid.mesh;
  long edges = 0;
  for (const auto& face : mesh.faces) {
    CHECK(face.width == 1.0);
    CHECK(face.height == 1.0);
    edges += long(face.vertices.size());
  }
  CHECK(mesh.numVertices - edges / 2 + mesh.numFaces() == 2);
  // The cones kept apart; what else the collapse joined is regular.
  int extraordinary = 0;
  for (int v = 0; v < mesh.numVertices; ++v) {
    CHECK(mesh.quarterTurnsAround[v] >= 2);
    extraordinary += mesh.isExtraordinary(v);
  }
  CHECK(extraordinary == cones);
  for (std::size_t r = 0; r < layout.rectangles().size(); ++r) {
    const auto [cellsX, cellsY] = grid.rectangleCells[r];
    CHECK((grid.firstCell[r] < 0) == (cellsX == 0 || cellsY == 0));
  }
  // Every surface point lands in a cell.
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int s = 0; s < 4000; ++s) {
    const int face = int(random() % flat.surface.n_faces());
    const double a = unit(random), b = unit(random) * (1.0 - a);
    const structure::RectanglePoint point = layout.locate(face, Eigen::Vector3d(1.0 - a - b, a, b));
    const spline::FacePoint cell = spline::layoutPoint(layout, grid, point);
    REQUIRE(cell.face >= 0);
    REQUIRE(cell.face < mesh.numFaces());
    CHECK(cell.position.minCoeff() >= 0.0);
    CHECK(cell.position.maxCoeff() <= 1.0);
  }
  // Points of a collapsed rectangle land on the cell sides it was glued into.
  for (std::size_t r = 0; r < layout.rectangles().size(); ++r) {
    if (grid.firstCell[r] >= 0) continue;
    const auto& rect = layout.rectangles()[r];
    for (double t : {0.0, 0.3, 0.5, 0.9, 1.0}) {
      structure::RectanglePoint point;
      point.rectangle = int(r);
      point.position = {t * rect.width(), (1.0 - t) * rect.height()};
      const spline::FacePoint cell = spline::layoutPoint(layout, grid, point);
      REQUIRE(cell.face >= 0);
      const Eigen::Vector2d x = cell.position;
      CHECK(std::min({x.x(), 1.0 - x.x(), x.y(), 1.0 - x.y()}) < 1e-12);
      CHECK(x.minCoeff() >= 0.0);
      CHECK(x.maxCoeff() <= 1.0);
    }
  }
  // A T-spline is built on it once the cells next to clustered cones are split for caps.
  spline::TMesh refined = mesh;
  std::vector<spline::FacePoint> none;
  spline::refineAroundCones(refined, none);
  CHECK(spline::TSplineSpace(refined).missingAnchors().empty());
}

TEST_CASE("layout_tmesh: traces that met head-on leave no sliver to collapse", "[spline]") {
  // The ellipsoid's four cones of angle pi send traces along the same lines from opposite sides;
  // they meet half-way, and the grid is four rectangles of square cells.
  const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh("ellipsoid.off"));
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  spline::LayoutTMeshOptions options;
  options.cellSize = cellSizeFor(layout, 2000);
  const spline::LayoutTMesh grid = spline::layoutTMesh(layout, options);
  CHECK(grid.collapsedRectangles == 0);
  CHECK(grid.maxAnisotropy < 1.05);
  int valenceTwo = 0;
  for (int v = 0; v < grid.mesh.numVertices; ++v)
    valenceTwo += grid.mesh.quarterTurnsAround[std::size_t(v)] == 2;
  CHECK(valenceTwo == 4);
  checkOppositeSides(layout, grid);
}

TEST_CASE("layout_tmesh: segments far shorter than a cell that may not collapse still get a grid",
          "[spline]") {
  // Cones in tight clusters: segments between them are 1e-3 to 1e-2 of a cell and may not collapse
  // (that would join cones). Rounding a lattice basis greedily found no whole numbers for them;
  // the integer program always does.
  const test::FlatMetric flat = test::clusteredConesCow();
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  spline::LayoutTMeshOptions options;
  options.cellSize = cellSizeFor(layout, 6000);
  // Segments shorter than a tenth of a cell at a cone.
  std::vector<std::size_t> shortAtCone;
  for (std::size_t e = 0; e < layout.segments().size(); ++e) {
    const auto& segment = layout.segments()[e];
    if (segment.length() < 0.1 * options.cellSize &&
        (layout.nodes()[std::size_t(segment.from)].vertex >= 0 ||
         layout.nodes()[std::size_t(segment.to)].vertex >= 0))
      shortAtCone.push_back(e);
  }
  REQUIRE(shortAtCone.size() > 3);
  const spline::LayoutTMesh grid = spline::layoutTMesh(layout, options);
  // Some of them kept a cell (their collapse joined two cones).
  int kept = 0;
  for (std::size_t e : shortAtCone) kept += grid.segmentCells[e] > 0;
  CHECK(kept > 0);
  CHECK(grid.quantizationOptimal);
  checkOppositeSides(layout, grid);
  const spline::TMesh& mesh = grid.mesh;
  long edges = 0;
  for (const auto& face : mesh.faces) edges += long(face.vertices.size());
  CHECK(mesh.numVertices - edges / 2 + mesh.numFaces() == 2);
  int cones = 0;
  for (const auto& node : layout.nodes()) cones += node.vertex >= 0;
  int extraordinary = 0;
  for (int v = 0; v < mesh.numVertices; ++v) extraordinary += mesh.isExtraordinary(v);
  CHECK(extraordinary == cones);
  // The cells' anisotropy: its 99th percentile recomputed cell by cell.
  std::vector<double> perCell;
  for (std::size_t r = 0; r < layout.rectangles().size(); ++r) {
    const auto [x, y] = grid.rectangleCells[r];
    const auto& rect = layout.rectangles()[r];
    if (x == 0 || y == 0) continue;
    const double ratio = (x / rect.width()) / (y / rect.height());
    perCell.insert(perCell.end(), std::size_t(x * y), std::max(ratio, 1.0 / ratio));
  }
  std::sort(perCell.begin(), perCell.end());
  CHECK(grid.maxAnisotropy == Approx(perCell.back()).epsilon(1e-12));
  CHECK(grid.anisotropyP99 ==
        Approx(perCell[std::size_t(std::ceil(0.99 * double(perCell.size()))) - 1]).epsilon(1e-12));
  for (const auto& face : mesh.faces) {
    CHECK(face.width == 1.0);
    CHECK(face.height == 1.0);
  }
}

TEST_CASE("layout_tmesh: a bad cell size is refused", "[spline]") {
  const test::FlatMetric flat = test::eightConeSphere();
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  spline::LayoutTMeshOptions options;
  options.cellSize = 0.0;
  CHECK_THROWS_AS(spline::layoutTMesh(layout, options), structure::InputError);
  options.cellSize = 0.1;
  options.collapseBelow = 1.0;
  CHECK_THROWS_AS(spline::layoutTMesh(layout, options), structure::InputError);
}

TEST_CASE("layout_tmesh: man.off, collapses that break the grid are undone longest first",
          "[spline][slow]") {
  // At about 1,500 cells, collapsing man's segments under a quarter of a cell glues a rectangle
  // into a mesh that does not close up. Undoing every collapse then gave the slivers a whole cell
  // across, cells 368 times longer than wide; undoing those longer than a tenth of a cell first
  // keeps the slivers collapsed.
  const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh("man.off"));
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  spline::LayoutTMeshOptions options;
  options.cellSize = cellSizeFor(layout, 1500);
  const spline::LayoutTMesh grid = spline::layoutTMesh(layout, options);
  CHECK(grid.quantizations > 1);
  int slivers = 0;
  for (std::size_t e = 0; e < grid.segmentCells.size(); ++e) {
    if (grid.segmentCells[e] != 0) continue;
    const double length = layout.segments()[e].length() / options.cellSize;
    CHECK(length < options.collapseBelow);
    slivers += length < 0.1;
  }
  CHECK(slivers > 10);
  CHECK(grid.maxAnisotropy < 10.0);
  checkOppositeSides(layout, grid);
}

TEST_CASE("layout_tmesh: femur.off, every quantization proven optimal", "[spline]") {
  // After collapses and separations, plain branching searched one of femur's quantizations at
  // about 1,500 cells for its whole 20 s without meeting a whole solution (the layout failed), and
  // the MIP presolver with Gomory cuts stalled on one at about 2,200; one of the two settles each.
  const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh("femur.off"));
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  for (const double cells : {1500.0, 2200.0}) {
    CAPTURE(cells);
    spline::LayoutTMeshOptions options;
    options.cellSize = cellSizeFor(layout, cells);
    const spline::LayoutTMesh grid = spline::layoutTMesh(layout, options);
    CHECK(grid.quantizations > 1);
    CHECK(grid.quantizationOptimal);
    checkOppositeSides(layout, grid);
  }
}

TEST_CASE("layout_tmesh: femur.off, one cone at opposite corners of a sliver", "[spline]") {
  // The layout fit builds (valence-3 corners, cones three cells apart, 6,000 cells): a rectangle
  // 0.6 by 0.05 cells has one cone at two opposite corners, so 1 x 1 cells would repeat it. Two
  // cells along each side made cells 12 times longer than wide; one more cell in all, along the
  // side the quantization picks, keeps them within 6.
  spline::BuildSplineOptions build;
  build.kind = spline::SpaceKind::TSpline;
  build.control = 6000;
  const structure::TriMesh mesh = test::realMesh("femur.off");
  const spline::QuadLayoutFlattening quad = spline::quadLayoutFlattening(mesh, 3, build);
  const structure::Flattening flattening = structure::flattenSurface(mesh, quad.options);
  REQUIRE(flattening.converged);
  const structure::MotorcycleLayout layout(flattening.surface(), flattening.flatLengths);
  spline::LayoutTMeshOptions options;
  options.cellSize = cellSizeFor(layout, 6000);
  const spline::LayoutTMesh grid = spline::layoutTMesh(layout, options);
  checkOppositeSides(layout, grid);
  // Such rectangles get three cells at least, and the sliver no more.
  int withThreeCells = 0;
  for (std::size_t r = 0; r < layout.rectangles().size(); ++r) {
    const auto& sides = layout.rectangles()[r].sides;
    const auto startOf = [&](int side) {
      const int he = sides[std::size_t(side)].front();
      const auto& segment = layout.segments()[std::size_t(he / 2)];
      return he % 2 == 0 ? segment.from : segment.to;
    };
    if (startOf(0) != startOf(2) && startOf(1) != startOf(3)) continue;
    const int cells = grid.rectangleCells[r][0] + grid.rectangleCells[r][1];
    CAPTURE(r);
    CHECK(cells >= 3);
    withThreeCells += cells == 3;
  }
  CHECK(withThreeCells >= 1);
  CHECK(grid.maxAnisotropy <= 6.0);
}
