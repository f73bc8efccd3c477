#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include <Eigen/Dense>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/planar_delaunay.h"

using mspline::structure::PlanarDelaunay;

namespace {

double perpDot(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Counter-clockwise triangles whose circumcircles hold no point (cocircular ones allowed up to
// `slack` of the squared radius).
void checkDelaunay(const std::vector<Eigen::Vector2d>& points, const PlanarDelaunay& delaunay,
                   double slack) {
  const auto triangles = delaunay.triangles();
  REQUIRE_FALSE(triangles.empty());
  int violations = 0, clockwise = 0;
  for (const auto& t : triangles) {
    const Eigen::Vector2d a = points[t[0]], b = points[t[1]], c = points[t[2]];
    if (perpDot(b - a, c - a) <= 0.0) ++clockwise;
    Eigen::Matrix2d rows;
    rows << (b - a).transpose(), (c - a).transpose();
    const Eigen::Vector2d center =
        a + rows.inverse() * Eigen::Vector2d((b - a).squaredNorm(), (c - a).squaredNorm()) / 2.0;
    const double radius2 = (a - center).squaredNorm();
    for (const Eigen::Vector2d& p : points)
      if ((p - center).squaredNorm() < radius2 * (1.0 - slack)) ++violations;
  }
  CHECK(clockwise == 0);
  CHECK(violations == 0);
}

// The nearest point by brute force must be as near as the one found (ties may pick either).
void checkNearest(const std::vector<Eigen::Vector2d>& points, const PlanarDelaunay& delaunay,
                  std::mt19937& random, double low, double high) {
  std::uniform_real_distribution<double> coordinate(low, high);
  int worse = 0, start = 0;
  for (int query = 0; query < 2000; ++query) {
    const Eigen::Vector2d q(coordinate(random), coordinate(random));
    start = delaunay.nearest(q, start);
    double best = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector2d& p : points) best = std::min(best, (p - q).norm());
    if ((points[start] - q).norm() > best * (1 + 1e-7) + 1e-7) ++worse;
  }
  CHECK(worse == 0);
}

}  // namespace

TEST_CASE("planar_delaunay: random points", "[structure]") {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-3.0, 5.0);
  std::vector<Eigen::Vector2d> points(2000);
  for (auto& p : points) p = {coordinate(random), coordinate(random)};
  const PlanarDelaunay delaunay(points);
  CHECK(delaunay.duplicates().empty());
  checkDelaunay(points, delaunay, 1e-9);
  // Every point is a vertex of some triangle.
  std::vector<int> used(points.size(), 0);
  for (const auto& t : delaunay.triangles())
    for (int v : t) ++used[v];
  CHECK(std::count(used.begin(), used.end(), 0) == 0);
  checkNearest(points, delaunay, random, -11.0, 13.0);
}

TEST_CASE("planar_delaunay: a square grid, cocircular everywhere", "[structure]") {
  // Coordinates 0 .. 16 snap exactly (the grid step is a power of two), so every unit square
  // stays cocircular and only the exact predicates keep the triangulation valid.
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= 16; ++i)
    for (int j = 0; j <= 16; ++j) points.emplace_back(i, j);
  const PlanarDelaunay delaunay(points);
  checkDelaunay(points, delaunay, 1e-12);
  // A triangulation of the square with all 289 points as vertices: 2 * 16^2 triangles.
  CHECK(delaunay.triangles().size() == 2 * 16 * 16);
  std::mt19937 random(3);
  checkNearest(points, delaunay, random, -16.0, 32.0);
}

TEST_CASE("planar_delaunay: duplicates and bad input", "[structure]") {
  const std::vector<Eigen::Vector2d> points = {{0, 0}, {1, 0}, {0, 1}, {1, 0}, {1, 1}, {0, 0}};
  const PlanarDelaunay delaunay(points);
  REQUIRE(delaunay.duplicates().size() == 2);
  CHECK(delaunay.duplicates()[0] == std::array<int, 2>{3, 1});
  CHECK(delaunay.duplicates()[1] == std::array<int, 2>{5, 0});
  CHECK(delaunay.triangles().size() == 2);
  // A left-out point as the start of a query.
  CHECK(delaunay.nearest({0.9, 0.8}, 5) == 4);
  CHECK_THROWS_AS(PlanarDelaunay({}), mspline::structure::InputError);
  CHECK_THROWS_AS(PlanarDelaunay({{0, 0}, {std::nan(""), 1}}), mspline::structure::InputError);
  CHECK_THROWS_AS(delaunay.nearest({5, 5}), mspline::structure::InternalError);
}
