#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::TriMesh;

namespace {

// -int_0^x log(2 sin t) dt for 0 < x < pi: the singular part log(2t) integrated exactly, the
// smooth rest log(sin t / t) by composite Simpson.
double lobachevskyByQuadrature(double x) {
  const int n = 4000;
  const double h = x / n;
  const auto smooth = [](double t) { return t == 0.0 ? 0.0 : std::log(std::sin(t) / t); };
  double sum = smooth(0.0) + smooth(x);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * smooth(i * h);
  return (x - x * std::log(2.0 * x)) - sum * h / 3.0;
}

// The single series Cl2(t) = t - t log t + t sum_k zeta(2k) / (k (2k + 1)) (t / 2 pi)^(2k) on
// [0, pi] with 40 terms (converging like 4^-k everywhere), zeta summed directly: slow but simple,
// a reference for L(x) = Cl2(2x) / 2.
double lobachevskyBySeries(double x) {
  static const std::vector<double> coefficient = [] {
    std::vector<double> c;
    for (int k = 1; k <= 40; ++k) {
      double zeta = 0.0;
      for (int n = 20000; n >= 1; --n) zeta += std::pow(static_cast<double>(n), -2.0 * k);
      if (k == 1) zeta = kPi * kPi / 6.0;
      if (k == 2) zeta = std::pow(kPi, 4) / 90.0;
      c.push_back(zeta / (k * (2.0 * k + 1.0)));
    }
    return c;
  }();
  double t = std::remainder(2.0 * x, 2.0 * kPi);
  const double sign = t < 0.0 ? -1.0 : 1.0;
  t = std::abs(t);
  if (t == 0.0) return 0.0;
  const double q = (t / (2.0 * kPi)) * (t / (2.0 * kPi));
  double sum = 0.0;
  for (auto c = coefficient.rbegin(); c != coefficient.rend(); ++c) sum = (sum + *c) * q;
  return sign * 0.5 * (t - t * std::log(t) + t * sum);
}

// A smooth scale field with a little noise, small enough to keep every triangle valid.
Eigen::VectorXd sampleU(const TriMesh& mesh, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  Eigen::VectorXd u(static_cast<Eigen::Index>(mesh.n_vertices()));
  for (const auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    u[v.idx()] =
        amplitude * (std::sin(2.0 * p[0] + 0.5) * std::cos(1.5 * p[1]) + p[2] + noise(rng));
  }
  return u;
}

Eigen::VectorXd sampleTarget(const TriMesh& mesh, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> k(-0.5, 0.5);
  Eigen::VectorXd t(static_cast<Eigen::Index>(mesh.n_vertices()));
  for (Eigen::Index i = 0; i < t.size(); ++i) t[i] = k(rng);
  return t;
}

std::vector<int> randomVertices(const TriMesh& mesh, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(mesh.n_vertices()) - 1);
  std::vector<int> vertices;
  for (int i = 0; i < count; ++i) vertices.push_back(pick(rng));
  return vertices;
}

void checkGradientAgainstEnergy(const TriMesh& mesh, const Eigen::VectorXd& u,
                                const Eigen::VectorXd& target, const std::vector<int>& vertices) {
  const Eigen::VectorXd l0 = structure::edgeLengths(mesh);
  const Eigen::VectorXd gradient = structure::vertexScalingGradient(mesh, l0, u, target);
  const double scale = std::max(1.0, gradient.cwiseAbs().maxCoeff());
  const double h = 1e-5;
  double worst = 0.0;
  for (int v : vertices) {
    Eigen::VectorXd up = u, down = u;
    up[v] += h;
    down[v] -= h;
    const double fd = (structure::vertexScalingEnergy(mesh, l0, up, target) -
                       structure::vertexScalingEnergy(mesh, l0, down, target)) /
                      (2.0 * h);
    worst = std::max(worst, std::abs(fd - gradient[v]) / scale);
  }
  INFO("worst relative gradient error " << worst);
  CHECK(worst <= 1e-6);
}

void checkHessianAgainstGradient(const TriMesh& mesh, const Eigen::VectorXd& u,
                                 const std::vector<int>& vertices) {
  const Eigen::VectorXd l0 = structure::edgeLengths(mesh);
  const Eigen::VectorXd target = Eigen::VectorXd::Zero(u.size());
  const Eigen::SparseMatrix<double> hessian = structure::vertexScalingHessian(mesh, l0, u);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(hessian);
  const double h = 1e-6;
  double worst = 0.0;
  for (int v : vertices) {
    Eigen::VectorXd up = u, down = u;
    up[v] += h;
    down[v] -= h;
    const Eigen::VectorXd fd = (structure::vertexScalingGradient(mesh, l0, up, target) -
                                structure::vertexScalingGradient(mesh, l0, down, target)) /
                               (2.0 * h);
    const Eigen::VectorXd column = dense.col(v);
    worst = std::max(worst, (fd - column).cwiseAbs().maxCoeff() / column.cwiseAbs().maxCoeff());
  }
  INFO("worst relative Hessian column error " << worst);
  CHECK(worst <= 1e-6);
  // Restricting to unknowns keeps exactly the unknowns' rows and columns.
  std::vector<char> excluded(mesh.n_vertices(), 0);
  for (std::size_t i = 0; i < excluded.size(); i += 3) excluded[i] = 1;
  const structure::IndexMap map(mesh.n_vertices(), excluded);
  const Eigen::SparseMatrix<double> restricted = structure::vertexScalingHessian(mesh, l0, u, map);
  CHECK(restricted.nonZeros() == map.restrict(hessian).nonZeros());
  const Eigen::MatrixXd difference =
      Eigen::MatrixXd(restricted) - Eigen::MatrixXd(map.restrict(hessian));
  CHECK(difference.cwiseAbs().maxCoeff() <= 1e-12 * dense.cwiseAbs().maxCoeff());
  // A Laplacian: symmetric, rows summing to zero, positive semidefinite.
  CHECK((dense - dense.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * dense.cwiseAbs().maxCoeff());
  CHECK(dense.rowwise().sum().cwiseAbs().maxCoeff() <= 1e-9 * dense.cwiseAbs().maxCoeff());
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd x(u.size());
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = normal(rng);
    CHECK(x.dot(hessian * x) >= 0.0);
  }
}

TriMesh singleTriangle() {
  TriMesh mesh;
  const auto a = mesh.add_vertex({0.0, 0.0, 0.0});
  const auto b = mesh.add_vertex({1.0, 0.0, 0.0});
  const auto c = mesh.add_vertex({0.4, 0.8, 0.0});
  mesh.add_face(a, b, c);
  return mesh;
}

}  // namespace

TEST_CASE("vertex_scaling_energy: Lobachevsky function", "[structure]") {
  using structure::lobachevsky;
  // Catalan's constant G = Cl2(pi/2) = 2 L(pi/4); Cl2(pi/3) is the Clausen maximum.
  CHECK(lobachevsky(kPi / 4) == Approx(0.915965594177219015054603514932 / 2).epsilon(1e-15));
  CHECK(lobachevsky(kPi / 6) == Approx(1.01494160640965362502120255427 / 2).epsilon(1e-15));
  CHECK(std::abs(lobachevsky(0.0)) <= 1e-16);
  CHECK(std::abs(lobachevsky(kPi / 2)) <= 1e-15);
  CHECK(std::abs(lobachevsky(kPi)) <= 1e-15);
  for (double x : {1e-9, 1e-4, 0.1, 0.5, 1.0, 1.3, 1.5707, 2.0, 2.5, 3.0, 3.14}) {
    INFO("x = " << x);
    // The quadrature reference loses accuracy where sin t vanishes again (x near pi).
    if (x < 2.6) CHECK(std::abs(lobachevsky(x) - lobachevskyByQuadrature(x)) <= 1e-13);
    // Odd and pi-periodic.
    CHECK(std::abs(lobachevsky(-x) + lobachevsky(x)) <= 1e-15);
    CHECK(std::abs(lobachevsky(x + 3 * kPi) - lobachevsky(x)) <= 1e-13);
    // L'(x) = -log|2 sin x|.
    const double h = 1e-6;
    if (x > 1e-3 && x < 3.1) {
      const double fd = (lobachevsky(x + h) - lobachevsky(x - h)) / (2 * h);
      CHECK(std::abs(fd + std::log(2 * std::sin(x))) <= 1e-8);
    }
  }
}

TEST_CASE("vertex_scaling_energy: Lobachevsky function against the plain series", "[structure]") {
  // Dense in [0, pi] (the triangle angles), including both sides of the split at pi / 3 and the
  // ends, plus a few arguments outside that need the periodic reduction.
  double worst = 0.0;
  std::vector<double> xs;
  for (int i = 0; i <= 600; ++i) xs.push_back(kPi * i / 600.0);
  for (double x :
       {1e-300, 1e-12, kPi / 3 - 1e-12, kPi / 3 + 1e-12, kPi - 1e-12, -0.7, 4.0, -9.5, 40.0})
    xs.push_back(x);
  for (double x : xs) {
    const double error = std::abs(structure::lobachevsky(x) - lobachevskyBySeries(x));
    worst = std::max(worst, error);
  }
  INFO("worst absolute difference " << worst);
  // The reference cancels digits near x = pi / 2 (t log t against the sum), hence 1e-15.
  CHECK(worst <= 1e-15);
}

TEST_CASE("vertex_scaling_energy: triangle angles", "[structure]") {
  using structure::triangleAngles;
  const auto eq = triangleAngles(1, 1, 1);
  for (double a : eq) CHECK(a == Approx(kPi / 3).epsilon(1e-15));
  const auto right = triangleAngles(3, 4, 5);
  CHECK(right[0] == Approx(std::asin(0.6)).epsilon(1e-15));
  CHECK(right[1] == Approx(std::asin(0.8)).epsilon(1e-15));
  CHECK(right[2] == Approx(kPi / 2).epsilon(1e-15));
  // A needle: the small angle is ~ its opposite side, where the law of cosines loses all digits.
  const auto needle = triangleAngles(1e-9, 1.0, 1.0);
  CHECK(needle[0] == Approx(1e-9).epsilon(1e-12));
  CHECK(needle[0] + needle[1] + needle[2] == Approx(kPi).epsilon(1e-15));
  // Violating the triangle inequality: (0, 0, pi) with pi opposite the longest side.
  const auto broken = triangleAngles(1.0, 3.0, 1.5);
  CHECK(broken[0] == 0.0);
  CHECK(broken[1] == kPi);
  CHECK(broken[2] == 0.0);
  CHECK_FALSE(structure::satisfiesTriangleInequality(1.0, 3.0, 1.5));
  CHECK_FALSE(structure::satisfiesTriangleInequality(1.0, 2.0, 1.0));
  CHECK(structure::satisfiesTriangleInequality(1.0, 1.9, 1.0));
  // Continuous at the degenerate limit.
  const auto flat = triangleAngles(1.0, 2.0 - 1e-12, 1.0);
  CHECK(flat[1] == Approx(kPi).epsilon(1e-5));
}

TEST_CASE("vertex_scaling_energy: u = 0 reproduces the input, angle sums, Gauss-Bonnet",
          "[structure]") {
  std::vector<std::pair<std::string, TriMesh>> meshes = {
      {"torus", test::torus(24, 12)},
      {"icosphere", test::icosphere(3)},
      {"disk", test::gridDisk(8)},
      {"pair of pants", test::pairOfPants(2)},
      {"double torus", test::doubleTorus(2)},
      {"knot1.off", test::realMesh("knot1.off")},
      {"mannequin-devil.off", test::realMesh("mannequin-devil.off")}};
  for (const auto& [name, mesh] : meshes) {
    INFO(name);
    const Eigen::VectorXd l0 = structure::edgeLengths(mesh);
    const Eigen::VectorXd u0 = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
    const Eigen::VectorXd lengths = structure::scaledEdgeLengths(mesh, l0, u0);
    CHECK((lengths - l0).cwiseAbs().maxCoeff() == 0.0);
    // Scaling by a constant c multiplies every length by exp(c).
    const Eigen::VectorXd scaled =
        structure::scaledEdgeLengths(mesh, l0, Eigen::VectorXd::Constant(u0.size(), std::log(3.0)));
    CHECK((scaled - 3.0 * l0).cwiseAbs().maxCoeff() <= 1e-14 * 3.0 * l0.maxCoeff());

    const Eigen::VectorXd angles = structure::cornerAngles(mesh, l0);
    double worstFace = 0.0;
    for (const auto f : mesh.faces()) {
      double sum = 0.0;
      for (const auto h : mesh.fh_range(f)) sum += angles[h.idx()];
      worstFace = std::max(worstFace, std::abs(sum - kPi));
    }
    CHECK(worstFace <= 1e-13);
    // The corner angles agree with the ones of the embedded triangles.
    double worstCorner = 0.0;
    for (const auto f : mesh.faces()) {
      for (const auto h : mesh.fh_range(f)) {
        const auto opposite = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
        const auto d1 = mesh.point(mesh.from_vertex_handle(h)) - mesh.point(opposite);
        const auto d2 = mesh.point(mesh.to_vertex_handle(h)) - mesh.point(opposite);
        const double embedded = std::atan2(OpenMesh::cross(d1, d2).norm(), OpenMesh::dot(d1, d2));
        worstCorner = std::max(worstCorner, std::abs(embedded - angles[h.idx()]));
      }
    }
    CHECK(worstCorner <= 1e-9);

    const Eigen::VectorXd k = structure::vertexCurvatures(mesh, l0);
    const double chi = static_cast<double>(structure::analyzeTopology(mesh).euler);
    INFO("sum K = " << k.sum() << ", 2 pi chi = " << 2 * kPi * chi);
    CHECK(std::abs(k.sum() - 2 * kPi * chi) <= 1e-10 * std::max(1.0, std::abs(2 * kPi * chi)));
    CHECK(structure::degenerateFaces(mesh, l0).empty());
  }
}

TEST_CASE("vertex_scaling_energy: gradient and Hessian match finite differences", "[structure]") {
  SECTION("generated torus, every vertex") {
    const TriMesh mesh = test::torus(16, 8);
    const Eigen::VectorXd u = sampleU(mesh, 0.3, 1);
    REQUIRE(structure::degenerateFaces(
                mesh, structure::scaledEdgeLengths(mesh, structure::edgeLengths(mesh), u))
                .empty());
    std::vector<int> all(mesh.n_vertices());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    checkGradientAgainstEnergy(mesh, u, sampleTarget(mesh, 2), all);
    checkHessianAgainstGradient(mesh, u, all);
  }
  SECTION("knot1.off, sampled vertices") {
    const TriMesh mesh = test::realMesh("knot1.off");
    const Eigen::VectorXd u = sampleU(mesh, 0.05, 3);
    REQUIRE(structure::degenerateFaces(
                mesh, structure::scaledEdgeLengths(mesh, structure::edgeLengths(mesh), u))
                .empty());
    checkGradientAgainstEnergy(mesh, u, sampleTarget(mesh, 4), randomVertices(mesh, 40, 5));
    checkHessianAgainstGradient(mesh, u, randomVertices(mesh, 40, 6));
  }
  SECTION("disk with boundary") {
    const TriMesh mesh = test::gridDisk(6);
    const Eigen::VectorXd u = sampleU(mesh, 0.3, 7);
    std::vector<int> all(mesh.n_vertices());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    checkGradientAgainstEnergy(mesh, u, sampleTarget(mesh, 8), all);
    checkHessianAgainstGradient(mesh, u, all);
  }
  SECTION("the extended energy stays C1 across the triangle inequality") {
    const TriMesh mesh = singleTriangle();
    const Eigen::VectorXd l0 = structure::edgeLengths(mesh);
    const Eigen::VectorXd target = Eigen::VectorXd::Zero(3);
    // Shrinking the scale at vertex 2 shortens its two edges until they no longer span the third.
    for (double u2 : {0.0, -0.5, -1.0, -1.2, -2.0, -4.0}) {
      Eigen::VectorXd u = Eigen::VectorXd::Zero(3);
      u[2] = u2;
      const bool valid =
          structure::degenerateFaces(mesh, structure::scaledEdgeLengths(mesh, l0, u)).empty();
      INFO("u2 = " << u2 << (valid ? " (valid)" : " (degenerate)"));
      checkGradientAgainstEnergy(mesh, u, target, {0, 1, 2});
    }
    Eigen::VectorXd far = Eigen::VectorXd::Zero(3);
    far[2] = -4.0;
    CHECK_FALSE(
        structure::degenerateFaces(mesh, structure::scaledEdgeLengths(mesh, l0, far)).empty());
    // The degenerate face contributes zero to the Hessian but keeps its entries (fixed pattern).
    const Eigen::SparseMatrix<double> flat = structure::vertexScalingHessian(mesh, l0, far);
    CHECK(flat.nonZeros() == 9);
    CHECK(Eigen::MatrixXd(flat).cwiseAbs().maxCoeff() == 0.0);
    CHECK(structure::vertexScalingHessian(mesh, l0, Eigen::VectorXd::Zero(3)).nonZeros() == 9);
  }
}
