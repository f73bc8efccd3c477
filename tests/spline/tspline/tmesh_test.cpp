#include <catch2/catch.hpp>

#include <vector>

#include "mspline/spline/tspline/tmesh.h"
#include "mspline/structure/core/errors.h"
#include "support/test_tmeshes.h"

using namespace mspline;
using spline::QuarterMotion;
using spline::TMesh;
using test::unitKnots;

TEST_CASE("tmesh: quarter motions compose and invert exactly", "[spline]") {
  const QuarterMotion a{1, Eigen::Vector2d(2.0, -3.0)}, b{3, Eigen::Vector2d(-1.0, 5.0)};
  const Eigen::Vector2d p(0.25, 7.5);
  CHECK(a.then(b).apply(p) == b.apply(a.apply(p)));
  CHECK(a.inverse().apply(a.apply(p)) == p);
  CHECK(a.then(a).then(a).then(a).quarterTurns == 0);
  CHECK(QuarterMotion{1, Eigen::Vector2d::Zero()}.rotate(Eigen::Vector2d(1.0, 0.0)) ==
        Eigen::Vector2d(0.0, 1.0));
}

TEST_CASE("tmesh: a grid's faces, vertex angles and frame changes", "[spline]") {
  const TMesh grid = spline::gridTMesh(unitKnots(4), unitKnots(3));
  CHECK(grid.numVertices == 20);
  CHECK(grid.numFaces() == 12);
  int boundary = 0, regularInterior = 0;
  for (int v = 0; v < grid.numVertices; ++v) {
    boundary += grid.onBoundary[v];
    regularInterior += !grid.onBoundary[v] && grid.quarterTurnsAround[v] == 4;
    CHECK_FALSE(grid.isExtraordinary(v));
  }
  CHECK(boundary == 14);
  CHECK(regularInterior == 6);
  // Face 0's right side (edge 1) is face 1's left side (edge 3); crossing it moves by -1 in x.
  CHECK(grid.faces[0].twinFace[1] == 1);
  CHECK(grid.faces[0].twinEdge[1] == 3);
  const QuarterMotion across = grid.acrossEdge(0, 1);
  CHECK(across.quarterTurns == 0);
  CHECK(across.translation == Eigen::Vector2d(-1.0, 0.0));
  CHECK_THROWS_AS(grid.acrossEdge(0, 0), structure::InputError);
}

TEST_CASE("tmesh: a periodic grid is a closed torus of regular vertices", "[spline]") {
  const TMesh torus = spline::gridTMesh(unitKnots(5), unitKnots(4), true, true);
  CHECK(torus.numVertices == 20);
  for (int v = 0; v < torus.numVertices; ++v) {
    CHECK_FALSE(torus.onBoundary[v]);
    CHECK(torus.quarterTurnsAround[v] == 4);
  }
  // Crossing the seam from the last column to the first: a translation by the period.
  CHECK(torus.acrossEdge(4, 1).translation == Eigen::Vector2d(-1.0, 0.0));
  CHECK(torus.faces[4].twinFace[1] == 0);
  CHECK_THROWS_AS(spline::gridTMesh(unitKnots(2), unitKnots(4), true, false),
                  structure::InputError);
}

TEST_CASE("tmesh: rectangles with T-junctions", "[spline]") {
  // A 2 x 2 block of a 4 x 4 grid made one face: four T-junctions on its sides, centre gone.
  std::vector<Eigen::Vector4d> rectangles;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      if (!(i >= 1 && i <= 2 && j >= 1 && j <= 2)) rectangles.emplace_back(i, j, i + 1, j + 1);
  rectangles.emplace_back(1, 1, 3, 3);
  Eigen::MatrixX2d lo(rectangles.size(), 2), hi(rectangles.size(), 2);
  for (std::size_t r = 0; r < rectangles.size(); ++r) {
    lo.row(Eigen::Index(r)) << rectangles[r][0], rectangles[r][1];
    hi.row(Eigen::Index(r)) << rectangles[r][2], rectangles[r][3];
  }
  const TMesh mesh = spline::planarTMesh(lo, hi);
  CHECK(mesh.numVertices == 24);
  const auto& big = mesh.faces.back();
  CHECK(big.vertices.size() == 8);
  CHECK(big.width == 2.0);
  int tJunctions = 0;
  for (int v = 0; v < mesh.numVertices; ++v)
    if (!mesh.onBoundary[v] && mesh.quarterTurnsAround[v] == 4) {
      // Regular interior vertices and T-junctions both turn fully (2 corners + 1 straight side).
      int facesAt = 0;
      for (const auto& face : mesh.faces)
        for (int id : face.vertices) facesAt += id == v;
      tJunctions += facesAt == 3;
    }
  CHECK(tJunctions == 4);
  // The big face's bottom T-junction at (2, 1) has the face below-right across its side.
  CHECK(mesh.acrossEdge(int(mesh.faces.size()) - 1, 0).translation == Eigen::Vector2d(0.0, 1.0));
}

TEST_CASE("tmesh: invalid faces are refused with the face named", "[spline]") {
  spline::TMeshFace face;
  face.vertices = {0, 1, 2, 3};
  face.positions = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  CHECK_NOTHROW(spline::buildTMesh(4, {face}));
  spline::TMeshFace clockwise = face;
  clockwise.positions = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  CHECK_THROWS_WITH(spline::buildTMesh(4, {clockwise}), Catch::Contains("T-mesh face 0"));
  spline::TMeshFace notRectangle = face;
  notRectangle.positions[2] = {1.0, 0.5};
  CHECK_THROWS_AS(spline::buildTMesh(4, {notRectangle}), structure::InputError);
  spline::TMeshFace repeated = face;
  repeated.vertices[3] = 0;
  CHECK_THROWS_WITH(spline::buildTMesh(4, {repeated}), Catch::Contains("repeats"));
  CHECK_THROWS_WITH(spline::buildTMesh(5, {face}), Catch::Contains("vertex 4"));
  spline::TMeshFace twin = face;
  // Its left side (2 -> 1) has length 2, face 0's right side (1 -> 2) has 1.
  twin.vertices = {1, 4, 5, 2};
  twin.positions = {{0, 0}, {1, 0}, {1, 2}, {0, 2}};
  CHECK_THROWS_WITH(spline::buildTMesh(6, {face, twin}), Catch::Contains("length"));
}
