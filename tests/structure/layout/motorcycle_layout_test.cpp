#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/motorcycle_layout.h"
#include "mspline/structure/mesh/cap_holes.h"
#include "support/flat_metric.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::MotorcycleLayout;

namespace {

double flatArea(const test::FlatMetric& flat) {
  double area = 0.0;
  for (const auto f : flat.surface.faces()) {
    std::array<double, 3> l{};
    int k = 0;
    for (const auto e : f.edges()) l[std::size_t(k++)] = flat.lengths[e.idx()];
    const double s = 0.5 * (l[0] + l[1] + l[2]);
    area += std::sqrt(std::max(0.0, s * (s - l[0]) * (s - l[1]) * (s - l[2])));
  }
  return area;
}

// The rectangles tile the surface with opposite sides equal, to `tolerance` of the surface's size:
// Euler's formula for the graph (the surface's characteristic `euler`), and the areas add up.
void checkTiling(const test::FlatMetric& flat, const MotorcycleLayout& layout, double tolerance,
                 long euler = 2) {
  const double size = std::sqrt(flatArea(flat));
  double area = 0.0;
  for (const auto& r : layout.rectangles()) {
    CHECK(std::abs(r.sideLength[0] - r.sideLength[2]) <= tolerance * size);
    CHECK(std::abs(r.sideLength[1] - r.sideLength[3]) <= tolerance * size);
    area += r.width() * r.height();
  }
  const long v = long(layout.nodes().size()), e = long(layout.segments().size()),
             f = long(layout.rectangles().size());
  CHECK(v - e + f == euler);
  CHECK(area == Approx(flatArea(flat)).epsilon(tolerance));
}

// Per node, the number of segments that end there.
std::vector<int> nodeDegrees(const MotorcycleLayout& layout) {
  std::vector<int> degree(layout.nodes().size(), 0);
  for (const auto& s : layout.segments())
    ++degree[std::size_t(s.from)], ++degree[std::size_t(s.to)];
  return degree;
}

}  // namespace

TEST_CASE("motorcycle_layout: eight cones cut a sphere into rectangles", "[structure]") {
  const test::FlatMetric flat = test::eightConeSphere();
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  // Three traces leave every cone of angle 3 pi / 2; each ends at a T-node.
  CHECK(layout.numTraces() == 24);
  CHECK(layout.nodes().size() == 8 + 24);
  checkTiling(flat, layout, 1e-10);
  // Every half-edge has its rectangle, and the sides' pieces add up to the side.
  for (std::size_t he = 0; he < layout.halfedgeRectangle().size(); ++he) {
    const auto& r = layout.rectangles()[std::size_t(layout.halfedgeRectangle()[he])];
    const int side = layout.halfedgeSide()[he];
    CHECK(layout.halfedgeOffset()[he] + layout.segments()[he / 2].length() <=
          r.sideLength[std::size_t(side)] * (1.0 + 1e-12));
  }
}

namespace {

// Points of `face` at barycentric p and p + delta (summing to 0), located: positions inside their
// rectangles, and at the two points' flat distance when in the same rectangle (the rectangles
// are isometric charts). Returns whether they were in the same rectangle.
bool checkLocateIsometry(const test::FlatMetric& flat, const MotorcycleLayout& layout, int face,
                         const Eigen::Vector3d& p,
                         const Eigen::Vector3d& delta = Eigen::Vector3d(-1e-3, 1e-3, 0.0),
                         double margin = 1e-8) {
  const Eigen::Vector3d q = p + delta;
  const auto here = layout.locate(face, p), there = layout.locate(face, q);
  const auto& r = layout.rectangles()[std::size_t(here.rectangle)];
  CHECK(here.position.x() >= 0.0);
  CHECK(here.position.y() >= 0.0);
  CHECK(here.position.x() <= r.width());
  CHECK(here.position.y() <= r.height());
  if (here.rectangle != there.rectangle) return false;
  // The flat distance of the two points, from the face's side lengths.
  const auto f = flat.surface.face_handle(face);
  std::array<double, 3> l{};
  auto h = flat.surface.halfedge_handle(f);
  for (int k = 0; k < 3; ++k, h = flat.surface.next_halfedge_handle(h))
    l[std::size_t(k)] =
        flat.lengths[flat.surface.edge_handle(flat.surface.next_halfedge_handle(h)).idx()];
  // Barycentric difference (d0, d1, d2) summing to zero: |x|^2 = -sum_{i<j} d_i d_j l_ij^2,
  // l_ij the side between corners i and j (corner k is the to-vertex of halfedge k).
  const double l01 = l[0], l12 = l[1], l20 = l[2];
  const double distance =
      std::sqrt(-(delta[0] * delta[1] * l01 * l01 + delta[1] * delta[2] * l12 * l12 +
                  delta[2] * delta[0] * l20 * l20));
  // (The walk starts 1e-6 of the face inside it, which scales differences by 1 - 1e-6; positions
  // are clamped into their rectangle: slivers 1e-8 wide move them by that much, and so do traces
  // that met head-on 1e-8 apart.)
  CHECK((there.position - here.position).norm() ==
        Approx(distance).epsilon(3e-6).margin(margin * layout.longestTrace()));
  return true;
}

}  // namespace

TEST_CASE("motorcycle_layout: locating is an isometry into the rectangles", "[structure]") {
  const test::FlatMetric flat = test::eightConeSphere();
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.05, 0.9);
  int sameRectangle = 0;
  for (int s = 0; s < 300; ++s) {
    const int face = int(random() % flat.surface.n_faces());
    double a = unit(random), b = unit(random) * (1.0 - a);
    sameRectangle += checkLocateIsometry(flat, layout, face, Eigen::Vector3d(1.0 - a - b, a, b));
  }
  CHECK(sameRectangle > 250);
}

TEST_CASE("motorcycle_layout: traces running back along each other meet head-on", "[structure]") {
  // libcgal-demo's ellipsoid with four cones of angle pi at the tips of its two longer axes: by
  // symmetry, traces from opposite cones run along the same lines, 1e-8 apart in floating point.
  // They meet half-way at one node instead of passing each other, which left slivers 1e-8 wide
  // between them (walks stepped past them; their grids collapsed).
  const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh("ellipsoid.off"));
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  // The two traces of a meeting are 1e-8 apart in floating point.
  checkTiling(flat, layout, 1e-7);
  double thinnest = INFINITY;
  for (const auto& r : layout.rectangles()) thinnest = std::min({thinnest, r.width(), r.height()});
  CHECK(thinnest > 0.1 * std::sqrt(flatArea(flat)));
  const std::vector<int> degree = nodeDegrees(layout);
  int headOn = 0;
  for (std::size_t n = 0; n < degree.size(); ++n)
    if (layout.nodes()[n].vertex < 0) {
      CHECK(degree[n] >= 2);
      CHECK(degree[n] <= 4);
      headOn += degree[n] != 3;
    }
  CHECK(headOn > 0);
  int sameRectangle = 0, pairs = 0;
  for (int face = 0; face < int(flat.surface.n_faces()); ++face)
    for (int i = 1; i < 9; i += 2)
      for (int j = 1; i + j < 10; j += 2) {
        const double a = 0.1 * i, b = 0.1 * j;
        sameRectangle += checkLocateIsometry(flat, layout, face, Eigen::Vector3d(1 - a - b, a, b),
                                             Eigen::Vector3d(-1e-3, 1e-3, 0.0), 1e-7);
        ++pairs;
      }
  CHECK(sameRectangle > pairs * 9 / 10);
}

TEST_CASE("motorcycle_layout: traces aimed exactly at cones on coarse polyhedra", "[structure]") {
  // A tetrahedron's four corners (angle pi each) and an octahedron's: traces run along edges
  // straight into other corners, where a cone's own trace comes back along the same line.
  for (const char* name : {"tetrahedron.off", "octahedron.off", "star.off"}) {
    INFO(name);
    const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh(name));
    const MotorcycleLayout layout(flat.surface, flat.lengths);
    checkTiling(flat, layout, 1e-7);
    double thinnest = INFINITY;
    for (const auto& r : layout.rectangles())
      thinnest = std::min({thinnest, r.width(), r.height()});
    CHECK(thinnest > 1e-3 * std::sqrt(flatArea(flat)));
  }
}

TEST_CASE("motorcycle_layout: four traces aimed at one vertex meet there", "[structure]") {
  // The octahedron's flat metric is a pillowcase: a square on each side, four cones of angle pi
  // at its corners, a vertex at the centre of each square. Every cone sends its two traces along
  // the diagonals, and the four traces of a square reach its centre together. Decided by which
  // one rounding lets through first, the layout changed with the BLAS kernel; met exactly, it is
  // four squares, two corners at cones and two at the centres, whose four traces all end there.
  const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh("octahedron.off"));
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  checkTiling(flat, layout, 1e-10);
  REQUIRE(layout.rectangles().size() == 4);
  const double side = std::sqrt(flatArea(flat) / 4.0);
  for (const auto& r : layout.rectangles()) {
    CHECK(r.width() == Approx(side).epsilon(1e-9));
    CHECK(r.height() == Approx(side).epsilon(1e-9));
  }
  const std::vector<int> degree = nodeDegrees(layout);
  REQUIRE(layout.nodes().size() == 6);
  for (std::size_t n = 0; n < degree.size(); ++n)
    CHECK(degree[n] == (layout.nodes()[n].vertex >= 0 ? 2 : 4));
  // Every trace runs along mesh edges, from vertex to vertex: each face lies in one rectangle,
  // whichever side its walks start from.
  for (int face = 0; face < int(flat.surface.n_faces()); ++face)
    for (int i = 1; i < 9; i += 2)
      for (int j = 1; i + j < 10; j += 2) {
        const double a = 0.1 * i, b = 0.1 * j;
        CHECK(checkLocateIsometry(flat, layout, face, Eigen::Vector3d(1 - a - b, a, b)));
      }
}

TEST_CASE("motorcycle_layout: a trace along a mesh edge is met from both sides", "[structure]") {
  // Boxes of twelve triangles: traces run from corner to corner along the edges, and others cross
  // those edges from either side. Stored in one face only, such a trace let the crossings from the
  // other face through (a 12-corner face of the trace graph).
  for (const char* name : {"cube_quad.off", "beam.off"}) {
    INFO(name);
    const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh(name));
    const MotorcycleLayout layout(flat.surface, flat.lengths);
    checkTiling(flat, layout, 1e-7);
    int sameRectangle = 0, pairs = 0;
    for (int face = 0; face < int(flat.surface.n_faces()); ++face)
      for (int i = 1; i < 9; i += 2)
        for (int j = 1; i + j < 10; j += 2) {
          const double a = 0.1 * i, b = 0.1 * j;
          sameRectangle +=
              checkLocateIsometry(flat, layout, face, Eigen::Vector3d(1 - a - b, a, b));
          ++pairs;
        }
    CHECK(sameRectangle > pairs * 3 / 4);
  }
}

TEST_CASE("motorcycle_layout: a box with a cone at each corner is its six faces", "[structure]") {
  // beam.off (0.4 x 0.4 x 3.6, twelve triangles) in its own metric: eight cones of angle 3 pi / 2.
  // Each edge carries two traces, one from each corner, which cross the edge's face in one step
  // and meet head-on half-way. When the first one ran on into the other's cone before that one
  // had left, two nodes coincided and the layout was traced again with a turned field, whose
  // rectangles cut the faces at an angle (and the beam's fits rippled along its edges).
  const structure::TriMesh mesh = test::realMesh("beam.off");
  test::FlatMetric flat{mesh, Eigen::VectorXd(mesh.n_edges())};
  for (const auto e : mesh.edges()) flat.lengths[e.idx()] = mesh.calc_edge_length(e);
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  checkTiling(flat, layout, 1e-12);
  CHECK(layout.numTraces() == 24);
  REQUIRE(layout.rectangles().size() == 6);
  std::vector<std::pair<double, double>> sides;
  for (const auto& r : layout.rectangles()) {
    sides.emplace_back(std::min(r.width(), r.height()), std::max(r.width(), r.height()));
  }
  std::sort(sides.begin(), sides.end(),
            [](const auto& a, const auto& b) { return a.second < b.second; });
  for (std::size_t k = 0; k < 6; ++k) {
    CHECK(sides[k].first == Approx(0.4).epsilon(1e-12));
    CHECK(sides[k].second == Approx(k < 2 ? 0.4 : 3.6).epsilon(1e-12));
  }
  // Twelve nodes half-way along the edges, where two traces met head-on.
  const std::vector<int> degree = nodeDegrees(layout);
  REQUIRE(layout.nodes().size() == 20);
  for (std::size_t n = 0; n < degree.size(); ++n)
    CHECK(degree[n] == (layout.nodes()[n].vertex >= 0 ? 3 : 2));
  for (const auto& segment : layout.segments())
    CHECK((segment.length() == Approx(0.2).epsilon(1e-12) ||
           segment.length() == Approx(1.8).epsilon(1e-12)));
}

TEST_CASE(
    "motorcycle_layout: a trace that crossed a face in one step stops where another got "
    "first",
    "[structure]") {
  // quad.off, a single square, closed by its fill: four triangles, each far larger than the
  // traces' steps elsewhere. A trace laid across a whole face at once stopped a trace that reached
  // the crossing before it ("face of the trace graph is not a rectangle").
  const test::FlatMetric flat =
      test::seamlessFlatMetric(structure::capHoles(test::realMesh("quad.off")).mesh);
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  checkTiling(flat, layout, 1e-7);
  // Which trace stops which depends on the last bits of the flat metric (edge lengths that the
  // square's symmetry makes equal differ by 1e-15): 4 rectangles on one machine, 6 on another.
  // Both tile the surface without a sliver.
  CHECK(layout.rectangles().size() >= 4);
  for (const auto& r : layout.rectangles())
    CHECK(std::min(r.width(), r.height()) > 0.05 * std::sqrt(flatArea(flat)));
}

TEST_CASE("motorcycle_layout: points of sliver faces are located through their neighbours",
          "[structure]") {
  // The flattening needs intrinsic flips; faces of their common subdivision can be 1e-4 of the
  // surface's size, where a hair inside a corner is closer to its sides than the walks resolve:
  // such corners are located from the faces next to them.
  const test::FlatMetric flat = test::clusteredConesCow();
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  const auto& mesh = flat.surface;
  // Per vertex, where it is located from each face around it (face corner k is the to-vertex of
  // the face's k-th halfedge).
  std::vector<std::vector<structure::RectanglePoint>> located(mesh.n_vertices());
  const double size = std::sqrt(flatArea(flat));
  int tiny = 0;
  for (const auto f : mesh.faces()) {
    std::array<double, 3> l{};
    int k = 0;
    for (const auto e : f.edges()) l[std::size_t(k++)] = flat.lengths[e.idx()];
    tiny += std::max({l[0], l[1], l[2]}) < 1e-4 * size;
    auto h = mesh.halfedge_handle(f);
    for (int corner = 0; corner < 3; ++corner, h = mesh.next_halfedge_handle(h)) {
      Eigen::Vector3d b = Eigen::Vector3d::Zero();
      b[corner] = 1.0;
      located[std::size_t(mesh.to_vertex_handle(h).idx())].push_back(layout.locate(f.idx(), b));
    }
  }
  REQUIRE(tiny > 0);
  // Seen from any two faces in one rectangle, a vertex is at one place.
  int pairs = 0;
  for (const auto& points : located)
    for (std::size_t i = 1; i < points.size(); ++i)
      if (points[i].rectangle == points[0].rectangle) {
        CHECK((points[i].position - points[0].position).norm() < 1e-4 * layout.longestTrace());
        ++pairs;
      }
  CHECK(pairs > int(mesh.n_vertices()));
}

TEST_CASE("motorcycle_layout: needles of a flipped overlay keep the angle sums made exact",
          "[structure]") {
  // mpi_triang.off needs intrinsic flips; its overlay has needles (a side 1e-7 of the others)
  // whose heights, from sqrt(l^2 - x^2), turned frames by 2e-3 rad: "the holonomy is not made of
  // quarter turns" although the holonomy quantization had made every angle sum exact.
  const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh("mpi_triang.off"));
  const MotorcycleLayout layout(flat.surface, flat.lengths);
  checkTiling(flat, layout, 1e-7, 0);  // a torus
}

TEST_CASE("motorcycle_layout: metrics it cannot lay out are refused", "[structure]") {
  const structure::TriMesh sphere = test::icosphere(2);
  // Twelve cones of angle 5 pi / 3 (an icosahedron's): not multiples of pi/2.
  std::vector<structure::Cone> cones;
  for (int v = 0; v < 12; ++v) cones.push_back({v, kPi / 3.0});
  const test::FlatMetric icosahedral = test::flatMetric(sphere, cones);
  CHECK_THROWS_WITH(MotorcycleLayout(icosahedral.surface, icosahedral.lengths),
                    Catch::Contains("quarter turns") || Catch::Contains("multiple of pi/2"));
  // The flattening before should have quantized them: a failed computation, not bad input.
  CHECK_THROWS_AS(MotorcycleLayout(icosahedral.surface, icosahedral.lengths),
                  structure::SolverError);
  CHECK_THROWS_AS(MotorcycleLayout(sphere, Eigen::VectorXd::Ones(3)), structure::InputError);
  CHECK_THROWS_WITH(
      MotorcycleLayout(test::gridDisk(4),
                       Eigen::VectorXd::Ones(Eigen::Index(test::gridDisk(4).n_edges()))),
      Catch::Contains("boundary"));
}

TEST_CASE("motorcycle_layout: a turned cross field lays out a pyramid", "[structure]") {
  // pyramid.off: five corners, four of them cones. The field aligned with face 0 sends traces
  // exactly through the apex, where the floating tracing can miss a crossing (whether it does
  // depends on the last bits of the arithmetic); turned by 0.618 of a quarter turn, every trace
  // runs clear of the corners.
  const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh("pyramid.off"));
  structure::MotorcycleLayoutOptions options;
  options.frameAngle = 0.618 * 0.5 * kPi;
  const MotorcycleLayout layout(flat.surface, flat.lengths, options);
  checkTiling(flat, layout, 1e-7);
  CHECK(layout.rectangles().size() >= 4);
}
