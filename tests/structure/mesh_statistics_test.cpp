#include "structure/mesh_statistics.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "support/test_meshes.h"

using namespace mspline;

TEST_CASE("mesh_statistics: unit grid has right angles and a known diagonal", "[structure]") {
  auto stats = structure::meshStatistics(test::gridDisk(4));
  CHECK(stats.bboxDiagonal == Approx(std::sqrt(2.0)).epsilon(1e-14));
  CHECK(stats.area == Approx(1.0).epsilon(1e-14));
  // Every triangle is half a square: corners of 45, 45 and 90 degrees, so the median is 45.
  CHECK(stats.minAngleDegrees == Approx(45.0).epsilon(1e-12));
  CHECK(stats.medianAngleDegrees == Approx(45.0).epsilon(1e-12));
  CHECK(stats.minEdgeLength == Approx(0.25).epsilon(1e-14));
  CHECK(stats.maxEdgeLength == Approx(std::sqrt(2.0) / 4).epsilon(1e-14));
}

TEST_CASE("mesh_statistics: icosphere approaches the unit sphere", "[structure]") {
  auto coarse = structure::meshStatistics(test::icosphere(0));
  // The icosahedron's faces are equilateral.
  CHECK(coarse.minAngleDegrees == Approx(60.0).epsilon(1e-12));
  CHECK(coarse.medianAngleDegrees == Approx(60.0).epsilon(1e-12));
  auto fine = structure::meshStatistics(test::icosphere(4));
  CHECK(fine.bboxDiagonal == Approx(2 * std::sqrt(3.0)).epsilon(1e-3));
  CHECK(fine.area == Approx(4 * M_PI).epsilon(2e-3));
  CHECK(fine.area < 4 * M_PI);  // inscribed polyhedra have less area than the sphere
}

TEST_CASE("mesh_statistics: empty mesh gives zeros", "[structure]") {
  auto stats = structure::meshStatistics(structure::TriMesh());
  CHECK(stats.area == 0);
  CHECK(stats.bboxDiagonal == 0);
}
