#include "mspline/structure/core/sparse_cholesky.h"

#include <catch2/catch.hpp>
#include <random>
#include <string>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/index_map.h"
#include "mspline/structure/mesh/cotan_laplacian.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::CholeskyBackend;
using structure::choleskyBackendName;
using structure::CholeskyOptions;
using structure::SparseCholesky;
using SparseMatrix = Eigen::SparseMatrix<double>;

namespace {

const CholeskyBackend kBackends[] = {CholeskyBackend::CholmodSupernodal,
                                     CholeskyBackend::CholmodSimplicial,
                                     CholeskyBackend::EigenSimplicial};

// Cotangent Laplacian of a randomly jittered n x n grid (irregular, non-uniform weights) plus a
// random positive diagonal: symmetric positive definite.
SparseMatrix randomSpd(int n, unsigned seed, double shift) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3 / n, 0.3 / n), diag(0.5 * shift, shift);
  structure::TriMesh mesh = test::gridDisk(n);
  for (auto v : mesh.vertices())
    mesh.point(v) += structure::TriMesh::Point(jitter(rng), jitter(rng), 0);
  SparseMatrix a = structure::cotanLaplacian(mesh);
  for (int i = 0; i < a.rows(); ++i) a.coeffRef(i, i) += diag(rng);
  return a;
}

Eigen::VectorXd randomVector(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = normal(rng);
  return v;
}

double relativeResidual(const SparseMatrix& a, const Eigen::VectorXd& x, const Eigen::VectorXd& b) {
  return (a * x - b).norm() / b.norm();
}

// The same matrix with column/row j decoupled and a negative diagonal: the only bad pivot is j.
SparseMatrix withNegativeColumn(SparseMatrix a, int j) {
  for (int k = 0; k < a.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(a, k); it; ++it)
      if ((it.row() == j) != (it.col() == j)) it.valueRef() = 0;
  a.coeffRef(j, j) = -1;
  return a;
}

}  // namespace

TEST_CASE("sparse_cholesky: solves SPD Laplacian systems and refactorizes on the same pattern",
          "[structure]") {
  SparseMatrix a = randomSpd(60, 1, 1e-3), a2 = randomSpd(60, 2, 1.0);
  REQUIRE(a.rows() == 61 * 61);
  Eigen::VectorXd b = randomVector(a.rows(), 3), b2 = randomVector(a.rows(), 4);
  Eigen::VectorXd reference;
  for (CholeskyBackend backend : kBackends) {
    INFO(choleskyBackendName(backend));
    SparseCholesky solver(CholeskyOptions{backend});
    solver.analyze(a);
    CHECK(solver.size() == a.rows());
    solver.factorize(a);
    Eigen::VectorXd x = solver.solve(b);
    CHECK(relativeResidual(a, x, b) < 1e-10);
    // Fill-in: L has at least the lower triangle of A and, with a fill-reducing ordering, far
    // fewer than the dense n^2 / 2 entries.
    CHECK(solver.factorNonZeros() >= (a.nonZeros() + a.rows()) / 2);
    CHECK(solver.factorNonZeros() < a.rows() * a.rows() / 20);
    if (reference.size() == 0)
      reference = x;
    else
      CHECK((x - reference).norm() <= 1e-9 * reference.norm());

    // New values, same pattern: numeric factorization only, with a new right-hand side too.
    solver.factorize(a2);
    CHECK(relativeResidual(a2, solver.solve(b2), b2) < 1e-10);
    CHECK(relativeResidual(a2, solver.solve(b), b) < 1e-10);
    CHECK(solver.lastAnalyzeSeconds() >= 0);
    CHECK(solver.lastFactorizeSeconds() >= 0);
  }
}

TEST_CASE("sparse_cholesky: reads only the lower triangle", "[structure]") {
  SparseMatrix a = randomSpd(20, 5, 0.1);
  SparseMatrix lower = a.triangularView<Eigen::Lower>();
  Eigen::VectorXd b = randomVector(a.rows(), 6);
  for (CholeskyBackend backend : kBackends) {
    INFO(choleskyBackendName(backend));
    SparseCholesky solver(CholeskyOptions{backend});
    solver.compute(lower);
    CHECK(relativeResidual(a, solver.solve(b), b) < 1e-10);
  }
}

TEST_CASE("sparse_cholesky: a Laplacian with a pinned vertex is definite", "[structure]") {
  // The pure cotangent Laplacian is singular; removing one vertex of a connected mesh fixes that.
  structure::TriMesh mesh = test::torus(30, 12);
  SparseMatrix full = structure::cotanLaplacian(mesh);
  std::vector<char> pinned(mesh.n_vertices(), 0);
  pinned[7] = 1;
  structure::IndexMap map(mesh.n_vertices(), pinned);
  SparseMatrix a = map.restrict(full);
  Eigen::VectorXd b = randomVector(a.rows(), 7);
  for (CholeskyBackend backend : kBackends) {
    INFO(choleskyBackendName(backend));
    SparseCholesky solver(CholeskyOptions{backend});
    solver.compute(a);
    CHECK(relativeResidual(a, solver.solve(b), b) < 1e-10);
  }
}

TEST_CASE("sparse_cholesky: a matrix that is not positive definite throws SolverError",
          "[structure]") {
  SparseMatrix good = randomSpd(15, 8, 0.1);
  const int bad = 37;
  SparseMatrix negative = withNegativeColumn(good, bad);
  Eigen::VectorXd b = randomVector(good.rows(), 9);
  for (CholeskyBackend backend : kBackends) {
    INFO(choleskyBackendName(backend));
    SparseCholesky solver(CholeskyOptions{backend});
    solver.analyze(good);
    CHECK_THROWS_WITH(solver.factorize(negative),
                      Catch::Contains("not positive definite") && Catch::Contains("column 37 "));
    CHECK_THROWS_AS(solver.factorize(negative), structure::SolverError);
    // No factor to solve with until a factorization succeeds; then it works again.
    CHECK_THROWS_AS(solver.solve(b), structure::InternalError);
    solver.factorize(good);
    CHECK(relativeResidual(good, solver.solve(b), b) < 1e-10);

    // Indefinite with all couplings kept: the negated matrix fails at its first pivot.
    SparseMatrix negated = -good;
    CHECK_THROWS_AS(solver.factorize(negated), structure::SolverError);
  }
}

TEST_CASE("sparse_cholesky: misuse is reported", "[structure]") {
  SparseCholesky solver;
  CHECK(solver.options().backend == CholeskyBackend::CholmodSupernodal);
  CHECK_THROWS_AS(solver.analyze(SparseMatrix(3, 4)), structure::InputError);
  SparseMatrix a = randomSpd(5, 10, 1.0);
  CHECK_THROWS_AS(solver.factorize(a), structure::InternalError);  // before analyze()
  solver.analyze(a);
  SparseMatrix other = randomSpd(6, 10, 1.0);
  CHECK_THROWS_AS(solver.factorize(other), structure::InternalError);  // another pattern
  Eigen::VectorXd wrongSize = Eigen::VectorXd::Ones(3);
  solver.factorize(a);
  CHECK_THROWS_AS(solver.solve(wrongSize), structure::InternalError);
}

TEST_CASE("sparse_cholesky: a moved solver keeps its factor", "[structure]") {
  SparseMatrix a = randomSpd(10, 11, 1.0);
  Eigen::VectorXd b = randomVector(a.rows(), 12);
  for (CholeskyBackend backend : kBackends) {
    INFO(choleskyBackendName(backend));
    SparseCholesky first(CholeskyOptions{backend});
    first.compute(a);
    SparseCholesky second(std::move(first));
    CHECK(relativeResidual(a, second.solve(b), b) < 1e-10);
    SparseCholesky third;
    third = std::move(second);
    CHECK(third.options().backend == backend);
    CHECK(relativeResidual(a, third.solve(b), b) < 1e-10);
  }
}

TEST_CASE("sparse_cholesky: the empty system", "[structure]") {
  SparseCholesky solver;
  solver.compute(SparseMatrix(0, 0));
  CHECK(solver.size() == 0);
  CHECK(solver.solve(Eigen::VectorXd()).size() == 0);
}
