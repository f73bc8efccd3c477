#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "mspline/spline/tribspline/simplex_spline.h"
#include "mspline/structure/core/constants.h"

using namespace mspline;
using Eigen::Vector2d;
using spline::simplexSpline;
using Knots = std::vector<Vector2d>;

namespace {

__extension__ typedef __int128 Int128;

double cross(const Vector2d& u, const Vector2d& v) {
  return u.x() * v.y() - u.y() * v.x();
}

Knots randomKnots(std::mt19937_64& random, int count) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Knots knots;
  for (int k = 0; k < count; ++k) knots.emplace_back(uniform(random), uniform(random));
  return knots;
}

// A random point of the knots' bounding box or (every other call) of their convex hull.
Vector2d randomPoint(std::mt19937_64& random, const Knots& knots) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  if (random() % 2) {
    Vector2d sum = Vector2d::Zero();
    double weights = 0.0;
    for (const Vector2d& k : knots) {
      const double w = uniform(random);
      sum += w * k;
      weights += w;
    }
    return sum / weights;
  }
  Vector2d low = knots[0], high = knots[0];
  for (const Vector2d& k : knots) {
    low = low.cwiseMin(k);
    high = high.cwiseMax(k);
  }
  return low + Vector2d(uniform(random), uniform(random)).cwiseProduct(high - low);
}

using Polygon = std::vector<Vector2d>;

// The part of a convex polygon where a.z + c >= 0 (Sutherland-Hodgman against one half-plane).
Polygon clip(const Polygon& polygon, const Vector2d& a, double c) {
  Polygon out;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vector2d& p = polygon[i];
    const Vector2d& q = polygon[(i + 1) % polygon.size()];
    const double fp = a.dot(p) + c;
    const double fq = a.dot(q) + c;
    if (fp >= 0) out.push_back(p);
    if ((fp >= 0) != (fq >= 0)) out.push_back(p + (q - p) * (fp / (fp - fq)));
  }
  return out;
}

double area(const Polygon& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
    twice += cross(polygon[i], polygon[(i + 1) % polygon.size()]);
  return std::abs(twice) / 2;
}

// M(x | V) for 4 or 5 knots straight from the definition, independent of any recurrence: lift
// the knots to u_j = (v_j, z_j) in R^{m-1} with z_0 = z_1 = z_2 = 0 and z_{2+i} = e_i, so that
// the simplex sigma = conv(u_j) projects onto V; then M(x) = vol(slice of sigma over x) /
// vol(sigma). A point of the slice is sum_j s_j u_j with s >= 0, sum s = 1, sum s_j v_j = x,
// parametrized isometrically by z = (s_3, ..., s_{m-1}); s_0, s_1, s_2 are affine in z.
double sliceVolumeSpline(const Vector2d& x, const Knots& v) {
  const int m = static_cast<int>(v.size());
  REQUIRE((m == 4 || m == 5));
  Eigen::Matrix3d a;
  a << v[0].x(), v[1].x(), v[2].x(), v[0].y(), v[1].y(), v[2].y(), 1, 1, 1;
  const Eigen::Matrix3d inverse = a.inverse();
  // s_{0..2}(z) = inverse * ((x, 1) - sum_i z_i (v_{2+i}, 1)) = offset + slope * z.
  const Eigen::Vector3d offset = inverse * Eigen::Vector3d(x.x(), x.y(), 1);
  Eigen::MatrixXd slope(3, m - 3);
  for (int i = 0; i < m - 3; ++i)
    slope.col(i) = -inverse * Eigen::Vector3d(v[3 + i].x(), v[3 + i].y(), 1);

  Eigen::MatrixXd lifted(m - 1, m - 1);
  for (int j = 1; j < m; ++j) {
    lifted.block(0, j - 1, 2, 1) = v[j] - v[0];
    lifted.block(2, j - 1, m - 3, 1).setZero();
    if (j >= 3) lifted(2 + j - 3, j - 1) = 1.0;
  }
  double factorial = 1.0;
  for (int k = 2; k < m; ++k) factorial *= k;
  const double simplexVolume = std::abs(lifted.determinant()) / factorial;

  double slice = 0.0;
  if (m == 4) {
    double low = 0.0, high = 1.0;  // z = s_3 in [0, 1]
    for (int j = 0; j < 3; ++j) {
      const double c = offset[j], s = slope(j, 0);  // c + s z >= 0
      if (s > 0) low = std::max(low, -c / s);
      if (s < 0) high = std::min(high, -c / s);
      if (s == 0 && c < 0) high = low;
    }
    slice = std::max(0.0, high - low);
  } else {
    Polygon polygon = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int j = 0; j < 3 && !polygon.empty(); ++j)
      polygon = clip(polygon, Vector2d(slope(j, 0), slope(j, 1)), offset[j]);
    slice = polygon.size() >= 3 ? area(polygon) : 0.0;
  }
  return slice / simplexVolume;
}

// Splits convex polygons by the line through p and q.
std::vector<Polygon> split(const std::vector<Polygon>& polygons, const Vector2d& p,
                           const Vector2d& q) {
  const Vector2d normal(-(q - p).y(), (q - p).x());
  std::vector<Polygon> out;
  for (const Polygon& polygon : polygons)
    for (double sign : {1.0, -1.0}) {
      Polygon part = clip(polygon, sign * normal, -sign * normal.dot(p));
      if (part.size() >= 3 && area(part) > 1e-15) out.push_back(part);
    }
  return out;
}

// The integral of M over the plane, exact up to rounding: M is a polynomial of degree n on each
// cell of the arrangement of the lines through pairs of knots, so the convex hull is cut into
// those cells, each fanned into triangles and integrated by a collapsed Gauss-Legendre rule
// exact for degree n.
double integral(const Knots& knots) {
  Polygon hull;
  {
    Knots points = knots;
    std::sort(points.begin(), points.end(), [](const Vector2d& a, const Vector2d& b) {
      return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
    });
    for (int pass = 0; pass < 2; ++pass) {
      const std::size_t start = hull.size();
      for (const Vector2d& p : points) {
        while (hull.size() >= start + 2 &&
               cross(hull[hull.size() - 1] - hull[hull.size() - 2], p - hull[hull.size() - 2]) <= 0)
          hull.pop_back();
        hull.push_back(p);
      }
      hull.pop_back();
      std::reverse(points.begin(), points.end());
    }
  }
  std::vector<Polygon> cells = {hull};
  for (std::size_t i = 0; i < knots.size(); ++i)
    for (std::size_t j = i + 1; j < knots.size(); ++j)
      if (knots[i] != knots[j]) cells = split(cells, knots[i], knots[j]);

  const int degree = static_cast<int>(knots.size()) - 3;
  const int order = degree + 2;  // Gauss-Legendre exact to 2 order - 1 >= degree + 1 (Duffy)
  // Gauss-Legendre nodes on [0, 1] by Newton on the Legendre polynomial.
  std::vector<double> nodes, weights;
  for (int i = 0; i < order; ++i) {
    double t = std::cos(kPi * (i + 0.75) / (order + 0.5));
    double derivative = 0.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = t;
      for (int k = 2; k <= order; ++k) {
        const double p2 = ((2 * k - 1) * t * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = order * (t * p1 - p0) / (t * t - 1);
      t -= p1 / derivative;
    }
    nodes.push_back((t + 1) / 2);
    weights.push_back(1.0 / ((1 - t * t) * derivative * derivative));
  }
  double sum = 0.0;
  for (const Polygon& cell : cells)
    for (std::size_t k = 1; k + 1 < cell.size(); ++k) {
      const Vector2d& a = cell[0];
      const Vector2d e1 = cell[k] - a;
      const Vector2d e2 = cell[k + 1] - a;
      const double jacobian = std::abs(cross(e1, e2));
      for (int i = 0; i < order; ++i)
        for (int j = 0; j < order; ++j) {
          // (u, v) in the unit square -> (u, (1 - u) v) in the reference triangle.
          const double u = nodes[i], v = (1 - u) * nodes[j];
          sum += weights[i] * weights[j] * (1 - u) * jacobian *
                 simplexSpline<double>(a + u * e1 + v * e2, knots);
        }
    }
  return sum;
}

double bernstein(const std::array<int, 3>& beta, const Eigen::Vector3d& lambda) {
  const int n = beta[0] + beta[1] + beta[2];
  double value = std::tgamma(n + 1.0);
  for (int j = 0; j < 3; ++j) value *= std::pow(lambda[j], beta[j]) / std::tgamma(beta[j] + 1.0);
  return value;
}

}  // namespace

TEST_CASE("simplex_spline: matches slice volumes of a simplex for 4 and 5 knots", "[spline]") {
  std::mt19937_64 random(11);
  for (int m : {4, 5})
    for (int trial = 0; trial < 20; ++trial) {
      const Knots knots = randomKnots(random, m);
      double largest = 0.0;
      std::vector<std::array<double, 2>> pairs;
      for (int p = 0; p < 30; ++p) {
        const Vector2d x = randomPoint(random, knots);
        const double expected = sliceVolumeSpline(x, knots);
        pairs.push_back({simplexSpline<double>(x, knots), expected});
        largest = std::max(largest, expected);
      }
      REQUIRE(largest > 0.0);
      for (const auto& [value, expected] : pairs)
        CHECK(std::abs(value - expected) <= 1e-12 * largest);
    }
}

TEST_CASE("simplex_spline: integrates to 1", "[spline]") {
  std::mt19937_64 random(12);
  for (int m = 3; m <= 7; ++m) {
    const Knots knots = randomKnots(random, m);
    INFO(m << " knots");
    CHECK(integral(knots) == Approx(1.0).epsilon(1e-12));
  }
  SECTION("with a repeated knot and with three collinear knots") {
    Knots repeated = randomKnots(random, 5);
    repeated[3] = repeated[1];
    CHECK(integral(repeated) == Approx(1.0).epsilon(1e-12));
    Knots collinear = {{0, 0}, {1, 0.5}, {0.5, 0.25}, {0.2, 0.9}, {0.8, -0.3}, {-0.4, 0.1}};
    CHECK(integral(collinear) == Approx(1.0).epsilon(1e-12));
  }
}

TEST_CASE("simplex_spline: is affine invariant", "[spline]") {
  std::mt19937_64 random(13);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  for (int m = 4; m <= 8; ++m)
    for (int trial = 0; trial < 10; ++trial) {
      const Knots knots = randomKnots(random, m);
      Eigen::Matrix2d a;
      do {
        a << uniform(random), uniform(random), uniform(random), uniform(random);
      } while (std::abs(a.determinant()) < 0.1);
      const Vector2d b(uniform(random), uniform(random));
      Knots mapped;
      for (const Vector2d& k : knots) mapped.push_back(a * k + b);
      for (int p = 0; p < 10; ++p) {
        const Vector2d x = randomPoint(random, knots);
        const double value = simplexSpline<double>(x, knots);
        const double image =
            simplexSpline<double>(Vector2d(a * x + b), mapped) * std::abs(a.determinant());
        // The map's own rounding (condition numbers up to about 100) on top of the spline's.
        INFO("value " << value << ", image " << image);
        CHECK(std::abs(image - value) <= 1e-12 * std::max(value, 1.0));
      }
    }
}

TEST_CASE("simplex_spline: derivatives match finite differences", "[spline]") {
  std::mt19937_64 random(14);
  const double h = 1e-5;
  int checked = 0, skipped = 0;
  for (int m = 5; m <= 8; ++m)
    for (int trial = 0; trial < 10; ++trial) {
      Knots knots = randomKnots(random, m);
      if (trial % 3 == 1) knots[4] = knots[2];  // a repeated knot
      if (trial % 3 == 2) {  // three collinear: dyadic knots, so that the midpoint is exact
        for (Vector2d& k : knots) k = (k * 0x1.0p20).array().round().matrix() * 0x1.0p-20;
        knots[4] = (knots[0] + knots[1]) / 2;
      }
      for (int p = 0; p < 10; ++p) {
        const Vector2d x = randomPoint(random, knots);
        Vector2d gradient;
        Eigen::Matrix2d hessian;
        const double value = simplexSpline<double>(x, knots, &gradient, &hessian);
        REQUIRE(std::isfinite(value));
        const double scale = 1.0 + hessian.cwiseAbs().maxCoeff();
        for (int axis = 0; axis < 2; ++axis) {
          const Vector2d step = h * Vector2d::Unit(axis);
          Vector2d gPlus, gMinus;
          const double plus = simplexSpline<double>(x + step, knots, &gPlus);
          const double minus = simplexSpline<double>(x - step, knots, &gMinus);
          // A knot line between x - step and x + step spoils the difference; skip those.
          const Eigen::Vector2d secondDifference = (gPlus - gMinus) / (2 * h);
          if ((secondDifference - hessian.col(axis)).norm() > 1e-2 * scale) {
            ++skipped;
            continue;
          }
          ++checked;
          CHECK(std::abs((plus - minus) / (2 * h) - gradient[axis]) <= 1e-6 * scale);
          CHECK((secondDifference - hessian.col(axis)).norm() <= 1e-5 * scale);
        }
      }
    }
  CHECK(skipped * 10 < checked);
}

TEST_CASE("simplex_spline: knots at three points give Bernstein polynomials", "[spline]") {
  // Knot multiplicities beta + 1 at the corners of a triangle: M is the Dirichlet density
  // (n + 1)(n + 2) / |det| * B_beta(lambda), so the normalized splines sum to 1 on the
  // (half-open) triangle.
  const std::array<Vector2d, 3> corner = {Vector2d(0.1, -0.2), Vector2d(1.3, 0.2),
                                          Vector2d(0.4, 1.1)};
  const double det = cross(corner[1] - corner[0], corner[2] - corner[0]);
  std::mt19937_64 random(15);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int n = 1; n <= 4; ++n) {
    std::vector<Vector2d> points;
    for (int p = 0; p < 20; ++p) {
      double l1 = uniform(random), l2 = uniform(random);
      if (l1 + l2 > 1) l1 = 1 - l1, l2 = 1 - l2;
      points.push_back(corner[0] + l1 * (corner[1] - corner[0]) + l2 * (corner[2] - corner[0]));
    }
    // Points on the edges and corners: the sum is the half-open indicator there.
    points.push_back(corner[0]);
    points.push_back(corner[1]);
    points.push_back((corner[1] + corner[2]) / 2);
    points.push_back((corner[0] + corner[2]) / 2);
    points.push_back((corner[0] + corner[1]) / 2);
    for (const Vector2d& x : points) {
      Eigen::Matrix3d a;
      a << corner[0].x(), corner[1].x(), corner[2].x(), corner[0].y(), corner[1].y(), corner[2].y(),
          1, 1, 1;
      const Eigen::Vector3d lambda = a.inverse() * Eigen::Vector3d(x.x(), x.y(), 1);
      const bool inside = spline::inHalfOpenTriangle(corner[0], corner[1], corner[2], x);
      double sum = 0.0;
      for (int b0 = 0; b0 <= n; ++b0)
        for (int b1 = 0; b0 + b1 <= n; ++b1) {
          const std::array<int, 3> beta = {b0, b1, n - b0 - b1};
          Knots knots;
          for (int j = 0; j < 3; ++j) knots.insert(knots.end(), beta[j] + 1, corner[j]);
          const double value = simplexSpline<double>(x, knots) * det / ((n + 1) * (n + 2));
          CHECK(value == Approx(inside ? bernstein(beta, lambda) : 0.0).margin(1e-13));
          sum += value;
        }
      CHECK(sum == Approx(inside ? 1.0 : 0.0).margin(1e-13));
    }
  }
}

TEST_CASE("simplex_spline: collinear knots", "[spline]") {
  const Knots line = {{0, 0}, {1, 1}, {2, 2}, {0.5, 0.5}, {3, 3}};
  Vector2d onLine(1, 1);
  CHECK(simplexSpline<double>(Vector2d(1.5, 1.5), line, &onLine) == 0.0);
  CHECK(onLine.isZero());
  // Three collinear knots among others: finite values, non-negative.
  const Knots some = {{0, 0}, {1, 0}, {2, 0}, {0.5, 1}, {1.5, 0.7}};
  std::mt19937_64 random(16);
  for (int p = 0; p < 50; ++p) {
    const Vector2d x = randomPoint(random, some);
    const double value = simplexSpline<double>(x, some);
    CHECK(std::isfinite(value));
    CHECK(value >= -1e-14);
  }
  CHECK(simplexSpline<double>(Vector2d(1, 0), some) >= 0.0);
  // Nearly collinear (rounded) knots: huge values on a thin sliver, but finite everywhere.
  std::mt19937_64 random2(18);
  for (int trial = 0; trial < 20; ++trial) {
    Knots nearly = randomKnots(random2, 6);
    nearly[4] = 0.3 * nearly[0] + 0.7 * nearly[1];
    for (int p = 0; p < 20; ++p) {
      Vector2d gradient;
      Eigen::Matrix2d hessian;
      const double value =
          simplexSpline<double>(randomPoint(random2, nearly), nearly, &gradient, &hessian);
      CHECK(std::isfinite(value));
      CHECK(gradient.allFinite());
      CHECK(hessian.allFinite());
    }
  }
  CHECK_THROWS_AS(simplexSpline<double>(Vector2d(0, 0), Knots{{0, 0}, {1, 0}}),
                  structure::InputError);
}

TEST_CASE("simplex_spline: half-open triangles tile the plane exactly", "[spline]") {
  // A fan of triangles around the origin plus a square split in two: every point, also on the
  // shared edges and vertices, lies in exactly one half-open triangle of each tiling.
  const std::vector<std::array<Vector2d, 3>> square = {
      {{Vector2d(0, 0), Vector2d(1, 0), Vector2d(1, 1)}},
      {{Vector2d(0, 0), Vector2d(1, 1), Vector2d(0, 1)}}};
  std::vector<std::array<Vector2d, 3>> fan;
  const std::vector<Vector2d> rim = {{1, 0},  {0.5, 0.75}, {-0.5, 1},
                                     {-1, 0}, {-0.25, -1}, {0.75, -0.5}};
  for (std::size_t k = 0; k < rim.size(); ++k)
    fan.push_back({{Vector2d(0, 0), rim[k], rim[(k + 1) % rim.size()]}});
  const std::vector<Vector2d> squarePoints = {
      {0.5, 0.5}, {0.25, 0.25}, {0.5, 0.25}, {0.25, 0.5}, {0.75, 0.75}};
  for (const Vector2d& x : squarePoints) {
    int count = 0;
    for (const auto& t : square) count += spline::inHalfOpenTriangle(t[0], t[1], t[2], x);
    CHECK(count == 1);
  }
  std::vector<Vector2d> fanPoints = {{0, 0}};
  for (const Vector2d& r : rim) {
    fanPoints.push_back(r / 2);
    fanPoints.push_back(r / 4);
  }
  for (const Vector2d& x : fanPoints) {
    int count = 0;
    for (const auto& t : fan) count += spline::inHalfOpenTriangle(t[0], t[1], t[2], x);
    CHECK(count == 1);
  }
}

TEST_CASE("simplex_spline: orientation is exact", "[spline]") {
  // Integer coordinates below 2^40 are exact doubles and their orientation is exact in 128-bit
  // integers; nearly collinear triples defeat a plain floating-point determinant.
  std::mt19937_64 random(17);
  std::uniform_int_distribution<std::int64_t> coordinate(-(std::int64_t(1) << 38), std::int64_t(1)
                                                                                       << 38);
  std::uniform_int_distribution<std::int64_t> step(-50, 50);
  std::uniform_int_distribution<int> nudge(-1, 1);
  int zeros = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const std::array<std::int64_t, 2> p = {coordinate(random), coordinate(random)};
    const std::array<std::int64_t, 2> d = {coordinate(random) / 1024, coordinate(random) / 1024};
    const std::int64_t s = step(random), t = step(random);
    const std::array<std::int64_t, 2> q = {p[0] + s * d[0], p[1] + s * d[1]};
    const std::array<std::int64_t, 2> r = {p[0] + t * d[0] + nudge(random), p[1] + t * d[1]};
    const Int128 exact = static_cast<Int128>(q[0] - p[0]) * (r[1] - p[1]) -
                         static_cast<Int128>(q[1] - p[1]) * (r[0] - p[0]);
    const int expected = exact > 0 ? 1 : exact < 0 ? -1 : 0;
    zeros += expected == 0;
    const auto point = [](const std::array<std::int64_t, 2>& a) {
      return Vector2d(static_cast<double>(a[0]), static_cast<double>(a[1]));
    };
    REQUIRE(spline::orientation(point(p), point(q), point(r)) == expected);
    REQUIRE(spline::orientation(point(q), point(p), point(r)) == -expected);
  }
  CHECK(zeros > 100);
}
