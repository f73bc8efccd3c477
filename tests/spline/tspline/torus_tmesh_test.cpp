#include <catch2/catch.hpp>

#include <cmath>

#include "mspline/spline/tspline/torus_tmesh.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/flat_layout.h"
#include "support/flat_metric.h"
#include "support/test_meshes.h"

using namespace mspline;

TEST_CASE("torus_tmesh: the lattice grid of a flat torus is seamless", "[spline]") {
  const test::FlatMetric flat = test::flatMetric(test::torus(24, 9), {});
  const structure::FlatLayout layout = structure::layoutFlatMetric(flat.surface, flat.lengths);
  REQUIRE(layout.hasPeriods);
  spline::TorusTMeshOptions options;
  options.targetCells = 500;
  const spline::TorusTMesh torus = spline::torusTMesh(layout, options);
  const int n = torus.cellsAlongFirst, m = torus.cellsAlongSecond;
  CHECK(n * m == torus.mesh.numFaces());
  CHECK(std::abs(n * m - 500) < 120);
  // A reduced basis: the first period is the shorter, the second at least 60 degrees away.
  CHECK(torus.firstPeriod.norm() <= torus.secondPeriod.norm() * (1.0 + 1e-12));
  CHECK(std::abs(torus.firstPeriod.dot(torus.secondPeriod)) <=
        0.5 * torus.firstPeriod.squaredNorm() * (1.0 + 1e-12));
  CHECK((torus.layoutToGrid * torus.firstPeriod - Eigen::Vector2d(n, 0)).norm() < 1e-9);
  CHECK((torus.layoutToGrid * torus.secondPeriod - Eigen::Vector2d(0, m)).norm() < 1e-9);
  CHECK(torus.anisotropy >= 1.0);
  CHECK(torus.anisotropy < 1.5);
  // Every copy of a vertex (one per face corner, across the layout's seams) lands on the same
  // grid point.
  std::vector<Eigen::Vector2d> gridOf(flat.surface.n_vertices(), Eigen::Vector2d::Constant(NAN));
  double worst = 0.0;
  for (const auto f : flat.surface.faces()) {
    int k = 0;
    for (const auto v : flat.surface.fv_range(f)) {
      const spline::FacePoint point = torus.cornerPoints[std::size_t(3 * f.idx() + k++)];
      const Eigen::Vector2d g(point.face % n + point.position.x(),
                              point.face / n + point.position.y());
      Eigen::Vector2d& seen = gridOf[std::size_t(v.idx())];
      if (std::isnan(seen.x())) {
        seen = g;
        continue;
      }
      // Compare on the torus: differences modulo the grid's size.
      Eigen::Vector2d d = g - seen;
      d.x() -= n * std::round(d.x() / n);
      d.y() -= m * std::round(d.y() / m);
      worst = std::max(worst, d.norm());
    }
  }
  CHECK(worst < 1e-9);
}

TEST_CASE("torus_tmesh: grid points wrap around both periods", "[spline]") {
  const test::FlatMetric flat = test::flatMetric(test::torus(16, 8), {});
  const spline::TorusTMesh torus =
      spline::torusTMesh(structure::layoutFlatMetric(flat.surface, flat.lengths));
  const int n = torus.cellsAlongFirst, m = torus.cellsAlongSecond;
  const spline::FacePoint a = spline::gridPoint(torus, {0.25, 1.5});
  const spline::FacePoint b = spline::gridPoint(torus, {0.25 + 3 * n, 1.5 - 2 * m});
  CHECK(a.face == b.face);
  CHECK((a.position - b.position).norm() < 1e-12);
  CHECK(a.face == n + 0);
  CHECK(spline::gridPoint(torus, {-0.5, -0.5}).face == (m - 1) * n + n - 1);
}

TEST_CASE("torus_tmesh: a layout without periods is refused", "[spline]") {
  structure::FlatLayout layout;
  CHECK_THROWS_AS(spline::torusTMesh(layout), structure::InputError);
}
