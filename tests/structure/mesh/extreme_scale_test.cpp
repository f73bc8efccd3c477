// Geometry that does not depend on the unit: a mesh at 1e300 or 1e-300 (squared lengths overflow
// or underflow) is valid, measured and flattened as at unit scale.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/flatten/flatten_surface.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/closest_point.h"
#include "mspline/structure/mesh/cotan_laplacian.h"
#include "mspline/structure/mesh/mesh_statistics.h"
#include "mspline/structure/mesh/validate.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::PolygonSoup;
using structure::TriMesh;

namespace {

PolygonSoup scaled(PolygonSoup soup, double factor) {
  for (auto& p : soup.positions)
    for (double& x : p) x *= factor;
  return soup;
}

TriMesh scaled(TriMesh mesh, double factor) {
  for (const auto v : mesh.vertices()) mesh.set_point(v, mesh.point(v) * factor);
  return mesh;
}

}  // namespace

TEST_CASE("extreme scale: a tetrahedron at 1e300 and 1e-300 is valid", "[structure]") {
  for (double factor : {1e300, 1e-300, 1e-307}) {
    INFO("scale " << factor);
    const PolygonSoup tet = scaled(test::tetrahedronSoup(), factor);
    CHECK(structure::validate(tet).ok());
    CHECK(structure::boundingBoxDiagonal(tet.positions) ==
          Approx(std::sqrt(3.0) * factor).epsilon(1e-15));

    const structure::MeshStatistics stats = structure::meshStatistics(structure::toTriMesh(tet));
    CHECK(stats.bboxDiagonal == Approx(std::sqrt(3.0) * factor).epsilon(1e-15));
    // Three right isosceles faces (45, 45, 90) and one equilateral (60).
    CHECK(stats.minAngleDegrees == Approx(45.0).epsilon(1e-12));
    CHECK(stats.medianAngleDegrees == Approx(52.5).epsilon(1e-12));
    CHECK(stats.minEdgeLength == Approx(factor).epsilon(1e-15));
    CHECK(stats.maxEdgeLength == Approx(std::sqrt(2.0) * factor).epsilon(1e-15));
  }
  // A face that is degenerate relative to its own size stays degenerate at any unit.
  PolygonSoup sliver;
  sliver.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1e-14, 0}};
  sliver.faces = {{0, 1, 2}};
  for (double factor : {1.0, 1e300, 1e-300}) {
    CHECK(structure::isDegenerateFace(scaled(sliver, factor), 0, 1e-12));
    CHECK_FALSE(structure::isDegenerateFace(scaled(test::tetrahedronSoup(), factor), 0, 1e-12));
  }
}

TEST_CASE("extreme scale: angles, areas and cotangents do not depend on the unit", "[structure]") {
  // Four times the area of a 3-4-5 triangle, 24 f^2, where f^4 overflows or underflows.
  for (double f : {1e150, 1e-150})
    CHECK(structure::fourTimesArea(3 * f, 4 * f, 5 * f) == Approx(24.0 * f * f).epsilon(1e-14));
  for (double factor : {1e300, 1e-300}) {
    INFO("scale " << factor);
    const auto angles = structure::triangleAngles(3 * factor, 4 * factor, 5 * factor);
    const auto unit = structure::triangleAngles(3, 4, 5);
    for (int k = 0; k < 3; ++k)
      CHECK(angles[std::size_t(k)] == Approx(unit[std::size_t(k)]).epsilon(1e-14));
    const TriMesh sphere = test::icosphere(1);
    const Eigen::MatrixXd plain = Eigen::MatrixXd(structure::cotanLaplacian(sphere));
    CHECK(
        Eigen::MatrixXd(structure::cotanLaplacian(scaled(sphere, factor))).isApprox(plain, 1e-14));
    // The flat metric's Hessian (cotangent weights from the edge lengths) likewise.
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(Eigen::Index(sphere.n_vertices()));
    const TriMesh big = scaled(sphere, factor);
    CHECK(Eigen::MatrixXd(structure::vertexScalingHessian(big, structure::edgeLengths(big), zero))
              .isApprox(Eigen::MatrixXd(structure::vertexScalingHessian(
                            sphere, structure::edgeLengths(sphere), zero)),
                        1e-14));
  }
}

TEST_CASE("extreme scale: flattening at 1e150 and 1e-150 as at unit scale", "[structure]") {
  const TriMesh torus = test::torus(16, 8);
  const structure::Flattening plain = structure::flattenSurface(torus);
  REQUIRE(plain.converged);
  for (double factor : {1e150, 1e-150}) {
    INFO("scale " << factor);
    const TriMesh big = scaled(torus, factor);
    const structure::Flattening flat = structure::flattenSurface(big);
    CHECK(flat.converged);
    CHECK(flat.flow.iterations == plain.flow.iterations);
    REQUIRE(flat.layout.hasPeriods);
    for (int k = 0; k < 2; ++k)
      CHECK(flat.layout.periods[std::size_t(k)].norm() ==
            Approx(plain.layout.periods[std::size_t(k)].norm() * factor).epsilon(1e-9));
  }
  // A needle cannot be flattened with cones that fit: the same error at any unit.
  std::string unitMessage;
  try {
    structure::flattenSurface(structure::toTriMesh(test::needleSoup()));
  } catch (const structure::Error& e) {
    unitMessage = e.what();
  }
  REQUIRE_FALSE(unitMessage.empty());
  for (double factor : {1e300, 1e-300})
    CHECK_THROWS_WITH(
        structure::flattenSurface(structure::toTriMesh(scaled(test::needleSoup(), factor))),
        unitMessage);
}

TEST_CASE("extreme scale: closest points at 1e300 and 1e-300 as at unit scale", "[structure]") {
  const structure::PolygonSoup sphere = structure::toSoup(test::icosphere(2));
  const std::vector<std::array<int, 3>> triangles = structure::triangleIndices(sphere);
  const Eigen::MatrixX3d positions = structure::pointMatrix(sphere.positions);
  const structure::TriangleMeshDistance unit(positions, triangles);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> coordinate(-1.5, 1.5);
  Eigen::MatrixX3d points(200, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int k = 0; k < 3; ++k) points(i, k) = coordinate(random);
  const std::vector<structure::ClosestPoint> expected = unit.queryAll(points);
  for (double factor : {1e300, 1e-300}) {
    INFO("scale " << factor);
    const structure::TriangleMeshDistance scaledMesh(positions * factor, triangles);
    const std::vector<structure::ClosestPoint> found = scaledMesh.queryAll(points * factor);
    for (std::size_t i = 0; i < found.size(); ++i) {
      // Up to the rounding of the scaled coordinates (1e300 is no power of two).
      CHECK(found[i].distance / factor == Approx(expected[i].distance).margin(1e-14));
      CHECK((found[i].closest / factor - expected[i].closest).norm() <= 1e-14);
    }
  }
}
