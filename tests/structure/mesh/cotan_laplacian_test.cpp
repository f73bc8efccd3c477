#include "mspline/structure/mesh/cotan_laplacian.h"

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>

#include "mspline/structure/core/errors.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::TriMesh;

TEST_CASE("cotan_laplacian: right-triangle grid gives the 5-point stencil", "[structure]") {
  // Axis edges face two 45-degree angles (weight (1 + 1) / 2), diagonals two right angles (0).
  const int n = 6;
  TriMesh mesh = test::gridDisk(n);
  Eigen::SparseMatrix<double> l = structure::cotanLaplacian(mesh);
  REQUIRE(l.rows() == long(mesh.n_vertices()));
  REQUIRE(l.nonZeros() == long(mesh.n_vertices() + 2 * mesh.n_edges()));
  Eigen::MatrixXd dense(l);
  for (auto v : mesh.vertices()) {
    if (mesh.is_boundary(v)) continue;
    auto p = mesh.point(v);
    CHECK(dense(v.idx(), v.idx()) == Approx(4.0));
    for (auto w : mesh.vv_range(v)) {
      auto d = mesh.point(w) - p;
      bool axis = std::abs(d[0]) < 1e-12 || std::abs(d[1]) < 1e-12;
      CHECK(dense(v.idx(), w.idx()) == Approx(axis ? -1.0 : 0.0).margin(1e-12));
    }
  }
}

TEST_CASE("cotan_laplacian: symmetric, zero row sums, linear precision", "[structure]") {
  // A jittered flat grid: the Laplacian of a linear function vanishes at interior vertices.
  TriMesh mesh = test::gridDisk(8);
  int i = 0;
  for (auto v : mesh.vertices()) {
    if (mesh.is_boundary(v)) continue;
    mesh.point(v) += TriMesh::Point(0.02 * std::sin(3.0 * i), 0.02 * std::cos(5.0 * i), 0);
    ++i;
  }
  Eigen::SparseMatrix<double> l = structure::cotanLaplacian(mesh);
  Eigen::MatrixXd dense(l);
  CHECK((dense - dense.transpose()).norm() == 0);
  CHECK((dense * Eigen::VectorXd::Ones(dense.cols())).norm() < 1e-12);
  Eigen::VectorXd linear(dense.cols());
  for (auto v : mesh.vertices()) linear[v.idx()] = 2 * mesh.point(v)[0] - 3 * mesh.point(v)[1];
  Eigen::VectorXd lx = dense * linear;
  for (auto v : mesh.vertices())
    if (!mesh.is_boundary(v)) CHECK(lx[v.idx()] == Approx(0).margin(1e-12));

  // Positive semidefinite on a closed surface: x^T L x equals the Dirichlet energy, never negative.
  Eigen::MatrixXd sphere(structure::cotanLaplacian(test::icosphere(2)));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(sphere);
  CHECK(eigen.eigenvalues().minCoeff() > -1e-10);
  CHECK(eigen.eigenvalues()(1) > 1e-3);  // connected: a single zero eigenvalue
}

TEST_CASE("cotan_laplacian: a zero-area face is an input error", "[structure]") {
  TriMesh mesh = test::gridDisk(2);
  mesh.point(TriMesh::VertexHandle(4)) = mesh.point(TriMesh::VertexHandle(3));
  CHECK_THROWS_AS(structure::cotanLaplacian(mesh), structure::InputError);
}
