#include "mspline/structure/core/index_map.h"

#include <catch2/catch.hpp>

#include "mspline/structure/core/errors.h"

using namespace mspline;
using structure::IndexMap;

TEST_CASE("index_map: unknowns skip excluded elements in order", "[structure]") {
  IndexMap map(6, {0, 1, 0, 0, 1, 0});
  REQUIRE(map.count() == 6);
  REQUIRE(map.size() == 4);
  const int expectedUnknown[] = {0, -1, 1, 2, -1, 3};
  for (std::size_t i = 0; i < 6; ++i) {
    CHECK(map.unknown(i) == expectedUnknown[i]);
    CHECK(map.excluded(i) == (expectedUnknown[i] < 0));
  }
  for (int k = 0; k < map.size(); ++k) CHECK(map.unknown(map.element(k)) == k);

  IndexMap all(3, {});
  CHECK(all.size() == 3);
  for (int k = 0; k < 3; ++k) CHECK(all.element(k) == std::size_t(k));
  CHECK(IndexMap(2, {1, 1}).size() == 0);
  CHECK_THROWS_AS(IndexMap(3, {0, 1}), structure::InternalError);
}

TEST_CASE("index_map: gather and scatter round-trip and keep excluded values", "[structure]") {
  IndexMap map(5, {1, 0, 0, 1, 0});
  Eigen::VectorXd perVertex(5);
  perVertex << 10, 11, 12, 13, 14;
  Eigen::VectorXd unknowns = map.gather(perVertex);
  REQUIRE(unknowns.size() == 3);
  CHECK(unknowns == Eigen::Vector3d(11, 12, 14));

  Eigen::VectorXd updated = perVertex;
  map.scatter(Eigen::Vector3d(-1, -2, -3), updated);
  Eigen::VectorXd expected(5);
  expected << 10, -1, -2, 13, -3;
  CHECK(updated == expected);
  map.scatter(unknowns, updated);
  CHECK(updated == perVertex);

  // std::vector storage goes through Eigen::Map.
  std::vector<double> values(5, 0.0);
  map.scatter(unknowns, Eigen::Map<Eigen::VectorXd>(values.data(), 5));
  CHECK(values == std::vector<double>{0, 11, 12, 0, 14});
  CHECK_THROWS_AS(map.gather(Eigen::VectorXd(4)), structure::InternalError);
}

TEST_CASE("index_map: restrict keeps the rows and columns of unknowns", "[structure]") {
  Eigen::MatrixXd dense(4, 4);
  dense << 1, 2, 0, 3,  //
      2, 4, 5, 0,       //
      0, 5, 6, 7,       //
      3, 0, 7, 8;
  Eigen::SparseMatrix<double> sparse = dense.sparseView();
  IndexMap map(4, {0, 1, 0, 0});
  Eigen::SparseMatrix<double> restricted = map.restrict(sparse);
  REQUIRE(restricted.rows() == 3);
  REQUIRE(restricted.cols() == 3);
  Eigen::MatrixXd expected(3, 3);
  expected << 1, 0, 3,  //
      0, 6, 7,          //
      3, 7, 8;
  CHECK(Eigen::MatrixXd(restricted) == expected);
  CHECK(restricted.nonZeros() == 7);
  CHECK(restricted.isCompressed());
  CHECK_THROWS_AS(map.restrict(Eigen::SparseMatrix<double>(3, 3)), structure::InternalError);
}
