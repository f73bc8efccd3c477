#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <vector>

#include <Eigen/Dense>

#include "mspline/spline/tribspline/dms_spline.h"
#include "mspline/structure/core/errors.h"

using namespace mspline;
using Eigen::Vector2d;
using spline::BasisValues;
using spline::BivariatePolynomial;
using spline::DmsSpace;
using spline::KnotClouds;

namespace {

struct Domain {
  std::vector<Vector2d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

// The unit square as an n x n grid of cells split into two triangles each (diagonals
// alternating); interior vertices jittered by up to 0.2 cells so that no three vertices near the
// middle are collinear.
Domain jitteredGrid(int n, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> jitter(-0.2 / n, 0.2 / n);
  Domain domain;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      Vector2d p(double(i) / n, double(j) / n);
      if (i > 0 && i < n && j > 0 && j < n) p += Vector2d(jitter(random), jitter(random));
      domain.vertices.push_back(p);
    }
  const auto v = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if ((i + j) % 2 == 0) {
        domain.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
        domain.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
      } else {
        domain.triangles.push_back({v(i, j), v(i + 1, j), v(i, j + 1)});
        domain.triangles.push_back({v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
      }
    }
  return domain;
}

double snap(double value) {
  return std::round(value * 0x1.0p20) * 0x1.0p-20;
}
Vector2d snap(const Vector2d& p) {
  return Vector2d(snap(p.x()), snap(p.y()));
}

// Points well inside the square, away from the boundary edges' clouds.
Vector2d interiorPoint(std::mt19937_64& random) {
  std::uniform_real_distribution<double> uniform(0.15, 0.85);
  return Vector2d(uniform(random), uniform(random));
}

bool inClosedTriangle(const DmsSpace& space, int t, const Vector2d& x) {
  const auto& tri = space.triangles()[t];
  const auto& v = space.vertices();
  return spline::orientation(v[tri[0]], v[tri[1]], x) >= 0 &&
         spline::orientation(v[tri[1]], v[tri[2]], x) >= 0 &&
         spline::orientation(v[tri[2]], v[tri[0]], x) >= 0;
}

struct Sums {
  double value = 0.0;
  Vector2d gradient = Vector2d::Zero();
  Eigen::Matrix2d hessian = Eigen::Matrix2d::Zero();
};

Sums basisSums(const DmsSpace& space, int triangle, const Vector2d& x) {
  BasisValues basis;
  space.basisAt(triangle, x, basis, 2);
  Sums sums;
  for (std::size_t k = 0; k < basis.index.size(); ++k) {
    sums.value += basis.value[k];
    sums.gradient += basis.gradient[k];
    sums.hessian += basis.hessian[k];
  }
  return sums;
}

BivariatePolynomial randomPolynomial(std::mt19937_64& random, int degree, int dims) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  BivariatePolynomial p;
  p.degree = degree;
  p.coefficients.resize(BivariatePolynomial::monomialCount(degree), dims);
  for (Eigen::Index i = 0; i < p.coefficients.size(); ++i)
    p.coefficients.data()[i] = uniform(random);
  return p;
}

// d^(dx + dy) p / dx^dx dy^dy at x.
Eigen::VectorXd polynomialDerivative(const BivariatePolynomial& p, const Vector2d& x, int dx,
                                     int dy) {
  Eigen::VectorXd value = Eigen::VectorXd::Zero(p.coefficients.cols());
  for (int a = dx; a <= p.degree; ++a)
    for (int b = dy; a + b <= p.degree; ++b) {
      double factor = 1.0;
      for (int k = 0; k < dx; ++k) factor *= a - k;
      for (int k = 0; k < dy; ++k) factor *= b - k;
      value += p.coefficients.row(BivariatePolynomial::monomialIndex(a, b)).transpose() * factor *
               std::pow(x.x(), a - dx) * std::pow(x.y(), b - dy);
    }
  return value;
}

Eigen::MatrixXd randomControl(std::mt19937_64& random, int rows, int dims) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd control(rows, dims);
  for (Eigen::Index i = 0; i < control.size(); ++i) control.data()[i] = uniform(random);
  return control;
}

}  // namespace

TEST_CASE("dms_spline: basis functions are the normalized simplex splines", "[spline]") {
  for (int n : {2, 3}) {
    const Domain domain = jitteredGrid(4, 21);
    const DmsSpace space(domain.vertices, domain.triangles, n);
    REQUIRE(space.numBasis() == 32 * (n + 1) * (n + 2) / 2);
    std::mt19937_64 random(22);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (int p = 0; p < 40; ++p) {
      const Vector2d x(uniform(random), uniform(random));
      const int t = space.locate(x);
      REQUIRE(t >= 0);
      BasisValues basis;
      space.basisAt(t, x, basis, 2);
      std::map<int, std::size_t> reported;
      for (std::size_t k = 0; k < basis.index.size(); ++k) reported[basis.index[k]] = k;
      REQUIRE(reported.size() == basis.index.size());
      // Every basis function of the space, against the generic simplex spline: the reported
      // ones agree with it, all others vanish at x.
      for (int index = 0; index < space.numBasis(); ++index) {
        Vector2d gradient;
        Eigen::Matrix2d hessian;
        const double scale = space.normalization(index);
        const double value =
            scale * spline::simplexSpline<double>(x, space.knotSet(index), &gradient, &hessian);
        gradient *= scale;
        hessian *= scale;
        const auto it = reported.find(index);
        if (it == reported.end()) {
          CHECK(std::abs(value) <= 1e-14);
          CHECK(gradient.norm() <= 1e-12);
          continue;
        }
        const std::size_t k = it->second;
        CHECK(basis.value[k] == Approx(value).margin(1e-13));
        CHECK((basis.gradient[k] - gradient).norm() <= 1e-11 * std::max(1.0, gradient.norm()));
        CHECK((basis.hessian[k] - hessian).norm() <= 1e-10 * std::max(1.0, hessian.norm()));
      }
    }
  }
}

TEST_CASE("dms_spline: partition of unity inside the domain", "[spline]") {
  for (int n : {1, 2, 3, 4}) {
    const Domain domain = jitteredGrid(6, 31 + n);
    const DmsSpace space(domain.vertices, domain.triangles, n);
    std::mt19937_64 random(32);
    double worst = 0.0, worstGradient = 0.0, worstHessian = 0.0;
    for (int p = 0; p < 2000; ++p) {
      const Vector2d x = interiorPoint(random);
      const Sums sums = basisSums(space, space.locate(x), x);
      worst = std::max(worst, std::abs(sums.value - 1.0));
      worstGradient = std::max(worstGradient, sums.gradient.norm());
      worstHessian = std::max(worstHessian, sums.hessian.norm());
    }
    INFO("degree " << n);
    CHECK(worst <= 1e-13);
    CHECK(worstGradient <= 1e-10);
    CHECK(worstHessian <= 1e-7);
  }
}

TEST_CASE("dms_spline: partition of unity on knot lines and triangle edges", "[spline]") {
  // Dyadic vertices and knots (multiples of 2^-20): midpoints and quarter points of two knots
  // are exact, so these points lie exactly on knot lines, triangle edges, or at knots.
  for (int n : {2, 3}) {
    Domain domain = jitteredGrid(6, 41);
    for (Vector2d& v : domain.vertices) v = snap(v);
    KnotClouds knots = spline::generateKnotClouds(domain.vertices, domain.triangles, n);
    for (std::size_t i = 0; i < knots.size(); ++i)
      for (Vector2d& k : knots[i]) k = snap(k);
    const DmsSpace space(domain.vertices, domain.triangles, knots);
    std::vector<Vector2d> points;
    for (const auto& tri : domain.triangles)
      for (int j = 0; j < 3; ++j) {
        const int a = tri[j], b = tri[(j + 1) % 3];
        for (int u = 0; u <= n; ++u)
          for (int v = 0; v <= n; ++v) {
            const Vector2d& p = knots[a][u];
            const Vector2d& q = knots[b][v];
            points.push_back(p);
            points.push_back((p + q) / 2);
            points.push_back(p + (q - p) / 4);
            points.push_back(p + (q - p) / 1024);
            if (u != v) points.push_back((p + knots[a][v]) / 2);
          }
      }
    int tested = 0;
    for (const Vector2d& x : points) {
      if (x.minCoeff() < 0.15 || x.maxCoeff() > 0.85) continue;
      const int located = space.locate(x);
      REQUIRE(located >= 0);
      CHECK(spline::inHalfOpenTriangle(space.vertices()[space.triangles()[located][0]],
                                       space.vertices()[space.triangles()[located][1]],
                                       space.vertices()[space.triangles()[located][2]], x));
      // The same sum from every triangle whose closure holds x.
      for (int t = 0; t < space.numTriangles(); ++t) {
        if (!inClosedTriangle(space, t, x)) continue;
        const Sums sums = basisSums(space, t, x);
        CHECK(sums.value == Approx(1.0).margin(1e-13));
        CHECK(sums.gradient.norm() <= 1e-10);
        ++tested;
      }
    }
    CHECK(tested > 1000);
  }
}

TEST_CASE("dms_spline: reproduces polynomials up to its degree", "[spline]") {
  for (int n : {2, 3}) {
    const Domain domain = jitteredGrid(6, 51);
    const DmsSpace space(domain.vertices, domain.triangles, n);
    std::mt19937_64 random(52);
    Eigen::MatrixX2d points(300, 2);
    for (int p = 0; p < points.rows(); ++p) points.row(p) = interiorPoint(random).transpose();
    for (int d = 0; d <= n; ++d) {
      const BivariatePolynomial polynomial = randomPolynomial(random, d, 3);
      // The blossom: symmetric and equal to the polynomial on the diagonal.
      const std::vector<Vector2d> arguments = {Vector2d(0.2, 0.7), Vector2d(-0.4, 1.1),
                                               Vector2d(0.9, 0.3)};
      std::vector<Vector2d> swapped = arguments;
      std::swap(swapped[0], swapped[2]);
      CHECK((polynomial.blossom(arguments) - polynomial.blossom(swapped)).norm() <= 1e-14);
      CHECK(
          (polynomial.blossom({3, Vector2d(0.3, -0.6)}) - polynomial(Vector2d(0.3, -0.6))).norm() <=
          1e-14);

      const Eigen::MatrixXd control = spline::controlPointsOfPolynomial(space, polynomial);
      const spline::SplineSamples samples = space.evaluateBatch(control, {}, points, 2);
      const double scale = polynomial.coefficients.cwiseAbs().sum();
      double worst = 0.0, worstFirst = 0.0, worstSecond = 0.0;
      for (int p = 0; p < points.rows(); ++p) {
        const Vector2d x = points.row(p).transpose();
        worst = std::max(worst, (samples.position.row(p).transpose() - polynomial(x)).norm());
        worstFirst = std::max(
            worstFirst,
            (samples.du.row(p).transpose() - polynomialDerivative(polynomial, x, 1, 0)).norm());
        worstFirst = std::max(
            worstFirst,
            (samples.dv.row(p).transpose() - polynomialDerivative(polynomial, x, 0, 1)).norm());
        worstSecond = std::max(
            worstSecond,
            (samples.duu.row(p).transpose() - polynomialDerivative(polynomial, x, 2, 0)).norm());
        worstSecond = std::max(
            worstSecond,
            (samples.duv.row(p).transpose() - polynomialDerivative(polynomial, x, 1, 1)).norm());
        worstSecond = std::max(
            worstSecond,
            (samples.dvv.row(p).transpose() - polynomialDerivative(polynomial, x, 0, 2)).norm());
      }
      INFO("space degree " << n << ", polynomial degree " << d);
      CHECK(worst <= 1e-12 * scale);
      CHECK(worstFirst <= 1e-10 * scale);
      CHECK(worstSecond <= 1e-7 * scale);
    }
    // A blossom given as a function: |x|^2 is the average of u_i . u_j over pairs i < j.
    const Eigen::MatrixXd control =
        spline::controlPointsFromBlossom(space, [](const std::vector<Vector2d>& u) {
          double sum = 0.0;
          int pairs = 0;
          for (std::size_t i = 0; i < u.size(); ++i)
            for (std::size_t j = i + 1; j < u.size(); ++j, ++pairs) sum += u[i].dot(u[j]);
          return Eigen::VectorXd::Constant(1, sum / pairs);
        });
    for (int p = 0; p < 50; ++p) {
      const Vector2d x = points.row(p).transpose();
      CHECK(space.evaluate(control, -1, x, 0).position[0] == Approx(x.squaredNorm()).margin(1e-12));
    }
  }
}

TEST_CASE("dms_spline: C^(n-1) across knot lines", "[spline]") {
  // Crossing the segment between t_{k,1} and t_{l,n-1} of an interior edge (a knot line of
  // N_beta^I for beta_k >= 1, beta_l >= n - 1): the jump of the (n-1)-th derivative over a
  // distance 2h shrinks like h, the n-th derivative's does not.
  for (int n : {2, 3}) {
    const Domain domain = jitteredGrid(6, 61);
    const DmsSpace space(domain.vertices, domain.triangles, n);
    std::mt19937_64 random(62);
    const Eigen::MatrixXd control = randomControl(random, space.numBasis(), 3);
    const int k = 3 * 7 + 3, l = 3 * 7 + 4;  // vertices (3, 3) and (4, 3) of the 6 x 6 grid
    const Vector2d p = space.knots()[k][1];
    const Vector2d q = space.knots()[l][n - 1];
    const Vector2d m = p + 0.37 * (q - p);
    const Vector2d normal = Vector2d(-(q - p).y(), (q - p).x()).normalized();
    // The derivative of order n - 1 (n = 2: gradient; n = 3: second) along the normal, and the
    // n-th by differences of the (n - 1)-th at distance h.
    const auto derivative = [&](const Vector2d& x) {
      const spline::SplinePoint s = space.evaluate(control, -1, x, 2);
      if (n == 2) return Eigen::VectorXd(s.du * normal.x() + s.dv * normal.y());
      return Eigen::VectorXd(s.duu * normal.x() * normal.x() + 2 * s.duv * normal.x() * normal.y() +
                             s.dvv * normal.y() * normal.y());
    };
    std::vector<double> lowerJump, upperJump;
    double upperScale = 0.0;  // the n-th derivative on one side
    for (double h : {4e-5, 2e-5, 1e-5}) {
      const Eigen::VectorXd plus = derivative(m + h * normal), minus = derivative(m - h * normal);
      const Eigen::VectorXd plus2 = derivative(m + 2 * h * normal),
                            minus2 = derivative(m - 2 * h * normal);
      lowerJump.push_back((plus - minus).norm());
      upperJump.push_back(((plus2 - plus) / h - (minus - minus2) / h).norm());
      upperScale = ((plus2 - plus) / h).norm();
    }
    INFO("degree " << n << ": jumps of derivative n-1 " << lowerJump[0] << " " << lowerJump[1]
                   << " " << lowerJump[2] << ", of derivative n " << upperJump[0] << " "
                   << upperJump[1] << " " << upperJump[2] << " (size " << upperScale << ")");
    CHECK(upperJump[2] > 1e-2 * upperScale);
    CHECK(upperJump[2] == Approx(upperJump[0]).epsilon(0.05));
    // O(h): halving h halves the jump, which stays below (n-th derivative) * 2h.
    CHECK(lowerJump[1] == Approx(lowerJump[0] / 2).epsilon(0.05));
    CHECK(lowerJump[2] == Approx(lowerJump[1] / 2).epsilon(0.05));
    CHECK(lowerJump[2] <= 10 * upperScale * 2e-5);
  }
}

TEST_CASE("dms_spline: derivatives match finite differences", "[spline]") {
  for (int n : {2, 3}) {
    const Domain domain = jitteredGrid(5, 71);
    const DmsSpace space(domain.vertices, domain.triangles, n);
    std::mt19937_64 random(72);
    const Eigen::MatrixXd control = randomControl(random, space.numBasis(), 3);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const double h = 1e-6;
    int checked = 0, skipped = 0;
    for (int p = 0; p < 200; ++p) {
      const Vector2d x(uniform(random), uniform(random));
      const spline::SplinePoint s = space.evaluate(control, -1, x, 2);
      CHECK(std::abs(s.normal.norm() - 1.0) <= 1e-12);
      CHECK(std::abs(s.normal.dot(s.du)) <= 1e-10 * s.du.norm());
      CHECK(std::abs(s.normal.dot(s.dv)) <= 1e-10 * s.dv.norm());
      const double scale = 1.0 + s.duu.norm() + s.duv.norm() + s.dvv.norm();
      for (int axis = 0; axis < 2; ++axis) {
        const Vector2d step = h * Vector2d::Unit(axis);
        const spline::SplinePoint plus = space.evaluate(control, -1, Vector2d(x + step), 2);
        const spline::SplinePoint minus = space.evaluate(control, -1, Vector2d(x - step), 2);
        const Eigen::VectorXd first = axis == 0 ? s.du : s.dv;
        const Eigen::VectorXd mixed = axis == 0 ? s.duu : s.duv;
        const Eigen::VectorXd pure = axis == 0 ? s.duv : s.dvv;
        // Second derivatives jump on knot lines (n = 2): skip steps whose one-sided
        // differences disagree.
        const Eigen::VectorXd forward = ((axis == 0 ? plus.du : plus.dv) - first) / h;
        const Eigen::VectorXd backward = (first - (axis == 0 ? minus.du : minus.dv)) / h;
        if ((forward - backward).norm() > 1e-3 * scale) {
          ++skipped;
          continue;
        }
        ++checked;
        CHECK(((plus.position - minus.position) / (2 * h) - first).norm() <= 1e-7 * scale);
        CHECK(((plus.du - minus.du) / (2 * h) - mixed).norm() <= 1e-5 * scale);
        CHECK(((plus.dv - minus.dv) / (2 * h) - pure).norm() <= 1e-5 * scale);
      }
    }
    CHECK(skipped * 20 < checked);
  }
}

TEST_CASE("dms_spline: the spline is affine invariant", "[spline]") {
  const Domain domain = jitteredGrid(5, 81);
  const DmsSpace space(domain.vertices, domain.triangles, 3);
  Eigen::Matrix2d a;
  a << 1.7, 0.6, -0.4, 0.9;
  const Vector2d b(-3.2, 5.1);
  std::vector<Vector2d> vertices;
  for (const Vector2d& v : space.vertices()) vertices.push_back(a * v + b);
  KnotClouds knots = space.knots();
  for (auto& cloud : knots)
    for (Vector2d& k : cloud) k = a * k + b;
  const DmsSpace mapped(vertices, space.triangles(), knots);
  std::mt19937_64 random(82);
  const Eigen::MatrixXd control = randomControl(random, space.numBasis(), 3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::Matrix2d inverse = a.inverse();
  for (int p = 0; p < 200; ++p) {
    const Vector2d x(uniform(random), uniform(random));
    const int t = space.locate(x);
    const spline::SplinePoint s = space.evaluate(control, t, x, 1);
    const spline::SplinePoint image = mapped.evaluate(control, t, Vector2d(a * x + b), 1);
    CHECK((image.position - s.position).norm() <= 1e-12);
    // d/dy of s(A^{-1}(y - b)) = (d/dx s) A^{-1}.
    Eigen::MatrixXd jacobian(3, 2), mappedJacobian(3, 2);
    jacobian << s.du, s.dv;
    mappedJacobian << image.du, image.dv;
    CHECK((mappedJacobian - jacobian * inverse).norm() <= 1e-10 * (1.0 + jacobian.norm()));
  }
}

TEST_CASE("dms_spline: repeated and collinear knots", "[spline]") {
  // Dyadic knots, so that the collinear ones are exactly collinear.
  const int n = 3;
  Domain domain = jitteredGrid(6, 91);
  for (Vector2d& v : domain.vertices) v = snap(v);
  KnotClouds knots = spline::generateKnotClouds(domain.vertices, domain.triangles, n);
  for (std::size_t i = 0; i < knots.size(); ++i) {
    auto& t = knots[i];
    for (Vector2d& k : t) k = snap(k);
    if (i % 3 == 0) t[1] = t[0];                      // repeated
    if (i % 3 == 1) t[2] = t[0] - (t[1] - t[0]) / 2;  // collinear within the cloud
    if (i % 3 == 2) t[3] = t[1];                      // repeated away from the vertex
  }
  // A knot on an edge: t_{l,1} on the segment towards vertex k.
  const int k = 3 * 7 + 3, l = 3 * 7 + 4;
  knots[l][1] = knots[l][0] + (knots[k][0] - knots[l][0]) / 16;
  const DmsSpace space(domain.vertices, domain.triangles, knots);
  std::mt19937_64 random(92);
  const BivariatePolynomial polynomial = randomPolynomial(random, n, 2);
  const Eigen::MatrixXd control = spline::controlPointsOfPolynomial(space, polynomial);
  std::vector<Vector2d> points;
  for (int p = 0; p < 1000; ++p) points.push_back(interiorPoint(random));
  for (const auto& cloud : knots)
    for (const Vector2d& t : cloud)
      if (t.minCoeff() > 0.15 && t.maxCoeff() < 0.85) points.push_back(t);
  double worst = 0.0, worstPolynomial = 0.0;
  for (const Vector2d& x : points) {
    const int t = space.locate(x);
    const Sums sums = basisSums(space, t, x);
    REQUIRE(std::isfinite(sums.value));
    worst = std::max(worst, std::abs(sums.value - 1.0));
    worstPolynomial = std::max(worstPolynomial,
                               (space.evaluate(control, t, x, 0).position - polynomial(x)).norm());
  }
  INFO("partition of unity error " << worst << ", polynomial error " << worstPolynomial);
  // Nearly singular knot triangles: 3.6e-13 with clang's code, 1e-13 with GCC's.
  CHECK(worst <= 1e-12);
  CHECK(worstPolynomial <= 1e-12 * polynomial.coefficients.cwiseAbs().sum());
}

TEST_CASE("dms_spline: locate, neighbourhoods and indices", "[spline]") {
  const Domain domain = jitteredGrid(5, 101);
  const DmsSpace space(domain.vertices, domain.triangles, 2);
  std::mt19937_64 random(102);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int p = 0; p < 500; ++p) {
    const Vector2d x(uniform(random), uniform(random));
    const int t = space.locate(x);
    REQUIRE(t >= 0);
    CHECK(inClosedTriangle(space, t, x));
  }
  CHECK(space.locate(Vector2d(1.5, 0.5)) == -1);
  CHECK(space.locate(Vector2d(0.5, -1e-9)) == -1);
  // Corner (1, 1) is on the boundary, where the perturbation leaves the domain: the closure rule.
  const int corner = space.locate(Vector2d(1, 1));
  REQUIRE(corner >= 0);
  CHECK(inClosedTriangle(space, corner, Vector2d(1, 1)));

  for (int t = 0; t < space.numTriangles(); ++t) {
    const std::vector<int> influencing = space.influencingTriangles(t);
    REQUIRE(influencing.front() == t);
    const std::set<int> set(influencing.begin(), influencing.end());
    CHECK(set.size() == influencing.size());
    for (int other = 0; other < space.numTriangles(); ++other) {
      bool sharesVertex = false;
      for (int a : space.triangles()[t])
        for (int b : space.triangles()[other]) sharesVertex = sharesVertex || a == b;
      if (sharesVertex) CHECK(set.count(other) == 1);
    }
  }
  for (int index = 0; index < space.numBasis(); ++index) {
    const spline::BasisId id = space.basisId(index);
    CHECK(space.basisIndex(id.triangle, id.beta) == index);
    CHECK(space.knotSet(index).size() == 5u);
    CHECK(space.blossomArguments(index).size() == 2u);
  }
  CHECK(space.basisId(1).beta == std::array<int, 3>{1, 1, 0});
  CHECK(space.basisId(2).beta == std::array<int, 3>{1, 0, 1});
}

TEST_CASE("dms_spline: batch evaluation agrees with single points", "[spline]") {
  const Domain domain = jitteredGrid(5, 111);
  const DmsSpace space(domain.vertices, domain.triangles, 3);
  std::mt19937_64 random(112);
  const Eigen::MatrixXd control = randomControl(random, space.numBasis(), 3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::MatrixX2d points(100, 2);
  std::vector<int> triangles;
  for (int p = 0; p < points.rows(); ++p) {
    points.row(p) = Eigen::RowVector2d(uniform(random), uniform(random));
    triangles.push_back(p % 2 ? space.locate(points.row(p).transpose()) : -1);
  }
  const spline::SplineSamples samples = space.evaluateBatch(control, triangles, points, 2);
  for (int p = 0; p < points.rows(); ++p) {
    const spline::SplinePoint s = space.evaluate(control, -1, points.row(p).transpose(), 2);
    CHECK((samples.position.row(p).transpose() - s.position).norm() <= 1e-14);
    CHECK((samples.du.row(p).transpose() - s.du).norm() <= 1e-12);
    CHECK((samples.dvv.row(p).transpose() - s.dvv).norm() <= 1e-10);
    CHECK((samples.normal.row(p).transpose() - s.normal).norm() <= 1e-12);
  }
  const spline::SplineSamples positions = space.evaluateBatch(control, {}, points, 0);
  CHECK(positions.du.size() == 0);
  CHECK((positions.position - samples.position).norm() <= 1e-13);
  Eigen::MatrixX2d outside(1, 2);
  outside << 2.0, 0.5;
  CHECK_THROWS_AS(space.evaluateBatch(control, {}, outside, 1), structure::InputError);
}

TEST_CASE("dms_spline: one triangle's functions anywhere, polynomials inside", "[spline]") {
  const Domain domain = jitteredGrid(4, 121);
  const DmsSpace space(domain.vertices, domain.triangles, 3);
  const int per = space.basisPerTriangle();
  std::mt19937_64 random(122);
  spline::TriangleBasis alone;
  BasisValues all;
  int nonZero = 0;
  for (int s = 0; s < 200; ++s) {
    const Vector2d x = interiorPoint(random);
    space.basisAt(space.locate(x), x, all, 2);
    for (int t = 0; t < space.numTriangles(); ++t) {
      // What basisAt lists of T's functions (the others vanish at x).
      std::vector<double> value(per, 0.0), gradient(2 * per, 0.0), hessian(3 * per, 0.0);
      bool listed = false;
      for (std::size_t k = 0; k < all.index.size(); ++k) {
        const int j = all.index[k] - t * per;
        if (j < 0 || j >= per) continue;
        listed = true;
        value[j] = all.value[k];
        gradient[2 * j] = all.gradient[k].x();
        gradient[2 * j + 1] = all.gradient[k].y();
        hessian[3 * j] = all.hessian[k](0, 0);
        hessian[3 * j + 1] = all.hessian[k](0, 1);
        hessian[3 * j + 2] = all.hessian[k](1, 1);
      }
      if (!space.triangleBasisAt(t, x, alone, 2)) {
        CHECK_FALSE(listed);
        continue;
      }
      ++nonZero;
      for (int j = 0; j < per; ++j) {
        CHECK(std::abs(alone.value[j] - value[j]) <= 1e-14);
        CHECK(std::abs(alone.gradient[2 * j] - gradient[2 * j]) <= 1e-11);
        CHECK(std::abs(alone.gradient[2 * j + 1] - gradient[2 * j + 1]) <= 1e-11);
        CHECK(std::abs(alone.hessian[3 * j + 1] - hessian[3 * j + 1]) <= 1e-8);
      }
    }
  }
  // Each point has its own triangle's functions and, near edges, some neighbours'.
  CHECK(nonZero > 200);

  // Clouds lie within radiusFraction (0.3) times the inradius of their vertex, so at more than
  // 0.3 inradii from every side no edge set reaches: there the functions are the polynomials.
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int t = 0; t < space.numTriangles(); ++t) {
    const auto& tri = space.triangles()[t];
    const Vector2d& a = space.vertices()[tri[0]];
    const Vector2d& b = space.vertices()[tri[1]];
    const Vector2d& c = space.vertices()[tri[2]];
    const double la = (b - c).norm(), lb = (c - a).norm(), lc = (a - b).norm();
    const Vector2d incenter = (la * a + lb * b + lc * c) / (la + lb + lc);
    const double area = 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    const double inradius = 2.0 * area / (la + lb + lc);
    const BivariatePolynomial polynomials = space.trianglePolynomials(t);
    REQUIRE(polynomials.coefficients.cols() == per);
    for (int s = 0; s < 5; ++s) {
      const double r = 0.6 * inradius * std::sqrt(unit(random)), angle = 6.283185307 * unit(random);
      const Vector2d x = incenter + r * Vector2d(std::cos(angle), std::sin(angle));
      REQUIRE(space.triangleBasisAt(t, x, alone, 1));
      const Eigen::VectorXd value = polynomials(x - a);
      const Eigen::VectorXd dx = polynomialDerivative(polynomials, x - a, 1, 0);
      for (int j = 0; j < per; ++j) {
        CHECK(std::abs(value[j] - alone.value[j]) <= 1e-12);
        CHECK(std::abs(dx[j] - alone.gradient[2 * j]) * inradius <= 1e-11);
      }
    }
  }
}

TEST_CASE("dms_spline: rejects invalid input", "[spline]") {
  const Domain domain = jitteredGrid(3, 121);
  const KnotClouds knots = spline::generateKnotClouds(domain.vertices, domain.triangles, 3);
  using structure::InputError;
  CHECK_NOTHROW(DmsSpace(domain.vertices, domain.triangles, knots));
  auto clockwise = domain.triangles;
  std::swap(clockwise[4][1], clockwise[4][2]);
  CHECK_THROWS_AS(DmsSpace(domain.vertices, clockwise, knots), InputError);
  auto outOfRange = domain.triangles;
  outOfRange[2][0] = 99;
  CHECK_THROWS_AS(DmsSpace(domain.vertices, outOfRange, knots), InputError);
  auto duplicate = domain.triangles;
  duplicate.push_back(duplicate[0]);
  CHECK_THROWS_AS(DmsSpace(domain.vertices, duplicate, knots), InputError);
  KnotClouds shortCloud = knots;
  shortCloud[5].pop_back();
  CHECK_THROWS_AS(DmsSpace(domain.vertices, domain.triangles, shortCloud), InputError);
  KnotClouds moved = knots;
  moved[5][0] += Vector2d(1e-3, 0);
  CHECK_THROWS_AS(DmsSpace(domain.vertices, domain.triangles, moved), InputError);
  // A knot far across its triangles flips knot triangles.
  KnotClouds flipped = knots;
  flipped[5][2] = domain.vertices[5] + Vector2d(0.9, 0.9);
  CHECK_THROWS_AS(DmsSpace(domain.vertices, domain.triangles, flipped), InputError);
  CHECK_THROWS_AS(spline::generateKnotClouds(domain.vertices, domain.triangles, 0), InputError);
  spline::KnotCloudOptions wide;
  wide.radiusFraction = 0.8;
  CHECK_THROWS_AS(spline::generateKnotClouds(domain.vertices, domain.triangles, 3, wide),
                  InputError);

  const DmsSpace space(domain.vertices, domain.triangles, knots);
  const Eigen::MatrixXd control = Eigen::MatrixXd::Zero(space.numBasis() - 1, 3);
  CHECK_THROWS_AS(space.evaluate(control, 0, Vector2d(0.1, 0.05), 1), InputError);
  BasisValues basis;
  CHECK_THROWS_AS(space.basisAt(0, Vector2d(0.1, 0.05), basis, 3), InputError);
  CHECK_THROWS_AS(space.basisIndex(0, {1, 1, 0}), InputError);
}
