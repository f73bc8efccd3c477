#include <catch2/catch.hpp>

#include <cmath>

#include "mspline/spline/tribspline/spline_domain.h"
#include "mspline/structure/core/errors.h"
#include "support/test_meshes.h"

using namespace mspline;
using spline::SplineDomain;

namespace {

// Plane position of corner k of face f of flatTorusDomain(n, shear), unwrapped around cell (0, 0).
Eigen::Vector2d latticeCorner(int n, double shear, int f, int k) {
  const int cell = f / 2, i = cell % n, j = cell / n;
  static const int lower[3][2] = {{0, 0}, {1, 0}, {1, 1}};
  static const int upper[3][2] = {{0, 0}, {1, 1}, {0, 1}};
  const auto& offset = (f % 2 == 0 ? lower : upper)[k];
  const double x = i + offset[0], y = j + offset[1];
  return {x + shear * y, y};
}

}  // namespace

TEST_CASE("spline_domain: home charts of a flat torus are pieces of the plane", "[spline]") {
  const int n = 6;
  const double shear = 0.3;
  const SplineDomain domain = test::flatTorusDomain(n, shear);
  REQUIRE_NOTHROW(spline::validateDomain(domain));
  const auto charts = spline::buildHomeCharts(domain);
  REQUIRE(int(charts.size()) == domain.faceCount());
  double worst = 0.0;
  for (int home = 0; home < domain.faceCount(); ++home) {
    const auto& chart = charts[std::size_t(home)];
    // The home face and every face sharing a vertex with it (valence 6 everywhere).
    CHECK(chart.faces.size() == 13);
    CHECK(chart.faces.front() == home);
    // The chart is the plane itself, moved so that the home face's side 0 lies on the x axis:
    // lattice point x goes to R(-phi) (x - origin), up to the torus' periods.
    const Eigen::Vector2d origin = latticeCorner(n, shear, home, 0);
    const Eigen::Vector2d side = latticeCorner(n, shear, home, 1) - origin;
    const structure::RigidMotion toHome{-std::atan2(side.y(), side.x()), Eigen::Vector2d::Zero()};
    for (std::size_t k = 0; k < chart.faces.size(); ++k) {
      const int g = chart.faces[k];
      const auto corners = spline::canonicalCorners(domain, g);
      const Eigen::Vector2d shift = toHome.inverse()(chart.placement[k](corners[0])) -
                                    (latticeCorner(n, shear, g, 0) - origin);
      const double b = std::round(shift.y() / n);
      const double a = std::round((shift.x() - shear * b * n) / n);
      const Eigen::Vector2d period(a * n + shear * b * n, b * n);
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector2d expected = toHome(latticeCorner(n, shear, g, c) - origin + period);
        worst = std::max(worst, (chart.placement[k](corners[std::size_t(c)]) - expected).norm());
      }
    }
  }
  CHECK(worst <= 1e-12);
}

TEST_CASE("spline_domain: a small torus wraps, unmarked cones are refused", "[spline]") {
  // 2 x 2 cells: the fans around a face's corners reach faces along paths that go around the
  // torus, so the charts hold copies of them, one per piece of the plane they cover.
  const SplineDomain small = test::flatTorusDomain(2);
  const auto wrapped = spline::buildHomeCharts(small);
  for (const auto& chart : wrapped) {
    // The 13 faces around a face of the plane are 13 copies of the torus' 8.
    CHECK(chart.faces.size() == 13);
    int copies = 0;
    for (int f = 0; f < small.faceCount(); ++f) copies += int(chart.findAll(f).size() >= 2);
    CHECK(copies >= 4);
  }

  // Lengthen one diagonal: the four corners of its cell stop being flat.
  SplineDomain bent = test::flatTorusDomain(5);
  const int lower = 2 * (1 + 5 * 1), upper = lower + 1;
  bent.sideLengths[std::size_t(lower)][2] *= 1.1;
  bent.sideLengths[std::size_t(upper)][0] *= 1.1;
  CHECK_THROWS_WITH(spline::buildHomeCharts(bent), Catch::Contains("not flat"));
  for (int f : {lower, upper})
    for (int v : bent.faces[std::size_t(f)]) bent.cone[std::size_t(v)] = 1;
  const auto charts = spline::buildHomeCharts(bent);
  CHECK(charts[std::size_t(lower)].faces.size() < 13);

  SplineDomain broken = test::flatTorusDomain(4);
  broken.neighbourSide[0][0] = 2;
  CHECK_THROWS_AS(spline::validateDomain(broken), structure::InputError);
}
