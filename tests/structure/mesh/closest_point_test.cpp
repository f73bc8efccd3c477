#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/closest_point.h"
#include "support/test_data.h"

using namespace mspline;
using structure::ClosestPoint;
using structure::TriangleMeshDistance;

namespace {

ClosestPoint bruteForce(const TriangleMeshDistance& mesh, const Eigen::Vector3d& p) {
  ClosestPoint best;
  best.distance = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < mesh.triangles().size(); ++f) {
    const auto& t = mesh.triangles()[f];
    const ClosestPoint c = structure::closestPointOnTriangle(
        p, mesh.positions().row(t[0]).transpose(), mesh.positions().row(t[1]).transpose(),
        mesh.positions().row(t[2]).transpose());
    if (c.distance < best.distance) {
      best = c;
      best.face = int(f);
    }
  }
  return best;
}

// Every point's distance equals brute force; the reported closest point lies on the reported face
// at the reported barycentric coordinates and at the reported distance.
void checkAgainstBruteForce(const TriangleMeshDistance& mesh, const Eigen::MatrixX3d& points) {
  const auto results = mesh.queryAll(points);
  REQUIRE(results.size() == std::size_t(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Eigen::Vector3d p = points.row(i).transpose();
    const ClosestPoint& got = results[std::size_t(i)];
    const ClosestPoint expected = bruteForce(mesh, p);
    CHECK(got.distance == Approx(expected.distance).margin(1e-12));
    const auto& t = mesh.triangles()[std::size_t(got.face)];
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) x += got.barycentric[k] * mesh.positions().row(t[k]).transpose();
    CHECK((x - got.closest).norm() < 1e-12);
    CHECK((p - got.closest).norm() == Approx(got.distance).margin(1e-12));
    CHECK(got.barycentric.minCoeff() >= -1e-15);
    CHECK(got.barycentric.sum() == Approx(1.0).margin(1e-12));
  }
}

}  // namespace

TEST_CASE("closest_point: the regions of one triangle", "[structure]") {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  auto q = structure::closestPointOnTriangle({0.25, 0.25, 2.0}, a, b, c);
  CHECK(q.distance == Approx(2.0));
  CHECK((q.closest - Eigen::Vector3d(0.25, 0.25, 0)).norm() < 1e-15);
  q = structure::closestPointOnTriangle({-1, -1, 0}, a, b, c);
  CHECK((q.barycentric - Eigen::Vector3d(1, 0, 0)).norm() == 0.0);
  q = structure::closestPointOnTriangle({1, 1, 0}, a, b, c);
  CHECK((q.closest - Eigen::Vector3d(0.5, 0.5, 0)).norm() < 1e-15);
  CHECK(q.distance == Approx(std::sqrt(0.5)));
  q = structure::closestPointOnTriangle({0.5, -3, 4}, a, b, c);
  CHECK(q.distance == Approx(5.0));
  // Degenerate: all three corners on a line.
  q = structure::closestPointOnTriangle({0.5, 1, 0}, a, b, Eigen::Vector3d(2, 0, 0));
  CHECK(q.distance == Approx(1.0));
}

TEST_CASE("closest_point: random points near a small mesh equal brute force", "[structure]") {
  // An octahedron with one long thin triangle fan, so that triangle sizes differ a lot.
  Eigen::MatrixX3d positions(7, 3);
  positions << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 5, 0.01, 0;
  const std::vector<std::array<int, 3>> triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4},
                                                     {3, 0, 4}, {2, 0, 5}, {1, 2, 5},
                                                     {3, 1, 5}, {0, 3, 5}, {0, 6, 2}};
  const TriangleMeshDistance mesh(positions, triangles);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-2.0, 6.0);
  Eigen::MatrixX3d points(500, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int k = 0; k < 3; ++k) points(i, k) = coordinate(random) * (k == 0 ? 1.0 : 0.4);
  checkAgainstBruteForce(mesh, points);
  // Corners, and points on the faces, are at distance 0.
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    CHECK(mesh.query(positions.row(v).transpose()).distance == 0.0);
  const Eigen::Vector3d inside = (positions.row(0) + positions.row(2) + positions.row(4)) / 3.0;
  CHECK(mesh.query(inside).distance < 1e-15);
}

TEST_CASE("closest_point: knot1.off equals brute force, its own points at 0", "[structure]") {
  const structure::TriMesh surface = test::realMesh("knot1.off");
  Eigen::MatrixX3d positions(Eigen::Index(surface.n_vertices()), 3);
  for (auto v : surface.vertices())
    for (int k = 0; k < 3; ++k) positions(v.idx(), k) = surface.point(v)[k];
  std::vector<std::array<int, 3>> triangles;
  for (auto f : surface.faces()) {
    std::array<int, 3>& t = triangles.emplace_back();
    int k = 0;
    for (auto v : surface.fv_range(f)) t[std::size_t(k++)] = v.idx();
  }
  const TriangleMeshDistance mesh(positions, triangles);
  const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
  std::mt19937 random(11);
  std::uniform_real_distribution<double> offset(-0.05 * diagonal, 0.05 * diagonal);
  std::uniform_int_distribution<Eigen::Index> vertex(0, positions.rows() - 1);
  Eigen::MatrixX3d points(300, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    points.row(i) = positions.row(vertex(random)) +
                    Eigen::RowVector3d(offset(random), offset(random), offset(random));
  checkAgainstBruteForce(mesh, points);
  const auto own = mesh.queryAll(positions);
  double largest = 0.0;
  for (const auto& c : own) largest = std::max(largest, c.distance);
  CHECK(largest == 0.0);
}

TEST_CASE("closest_point: bad meshes are refused", "[structure]") {
  Eigen::MatrixX3d positions(3, 3);
  positions << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  CHECK_THROWS_AS(TriangleMeshDistance(positions, {}), structure::InputError);
  CHECK_THROWS_AS(TriangleMeshDistance(positions, {{0, 1, 3}}), structure::InputError);
}
