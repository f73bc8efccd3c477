#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "mspline/spline/subd/subd_fit_space.h"
#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tmesh_walk.h"
#include "mspline/structure/core/errors.h"
#include "support/test_tmeshes.h"

using namespace mspline;
using spline::FacePoint;
using spline::TMesh;
using spline::walkTMesh;

TEST_CASE("tmesh_walk: on a planar T-mesh the walk is the straight segment", "[spline]") {
  // T-junctions on the way: a side made of several edges.
  const TMesh mesh = test::gridWithMerges(8, {{2, 2, 5, 4}, {0, 5, 3, 8}});
  // Face 0 is the first merged rectangle, at (2, 2).
  const std::vector<Eigen::Vector2d> origin = test::faceOrigins(mesh, {2.0, 2.0});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int crossings = 0;
  for (int k = 0; k < 300; ++k) {
    const int f = int(rng() % unsigned(mesh.numFaces()));
    const FacePoint start{f, test::randomPointIn(mesh.faces[std::size_t(f)], rng, 0.05, 0.95)};
    const Eigen::Vector2d global = origin[std::size_t(f)] + start.position;
    // A target inside the square [0, 8]^2: the walk does not reach the boundary.
    const Eigen::Vector2d target(0.01 + 7.98 * unit(rng), 0.01 + 7.98 * unit(rng));
    bool boundary = true;
    const FacePoint end = walkTMesh(mesh, start, target - global, &boundary);
    CHECK_FALSE(boundary);
    const Eigen::Vector2d reached = origin[std::size_t(end.face)] + end.position;
    REQUIRE((reached - target).norm() < 1e-12);
    crossings += end.face != f;
    // And back.
    const FacePoint back = walkTMesh(mesh, end, global - target);
    CHECK(back.face == f);
    CHECK((back.position - start.position).norm() < 1e-12);
  }
  CHECK(crossings > 200);
}

TEST_CASE("tmesh_walk: a whole period of a periodic grid comes back to the start", "[spline]") {
  const TMesh mesh = spline::gridTMesh({0, 1, 2.5, 3, 4}, {0, 2, 3, 4}, true, true);
  std::mt19937 rng(5);
  for (int k = 0; k < 50; ++k) {
    const int f = int(rng() % unsigned(mesh.numFaces()));
    const FacePoint start{f, test::randomPointIn(mesh.faces[std::size_t(f)], rng, 0.05, 0.95)};
    for (const Eigen::Vector2d& period :
         {Eigen::Vector2d(4, 0), Eigen::Vector2d(0, -4), Eigen::Vector2d(8, 4)}) {
      bool boundary = true;
      const FacePoint end = walkTMesh(mesh, start, period, &boundary);
      CHECK_FALSE(boundary);
      CHECK(end.face == f);
      CHECK((end.position - start.position).norm() < 1e-12);
    }
  }
}

TEST_CASE("tmesh_walk: an open boundary stops the walk on it", "[spline]") {
  const TMesh mesh = spline::gridTMesh(test::unitKnots(3), test::unitKnots(3));
  bool boundary = false;
  // The segment leaves the grid through x = 3 halfway, at y = 0.25 + 0.5 * 0.5.
  const FacePoint end = walkTMesh(mesh, {0, {0.5, 0.25}}, {5.0, 0.5}, &boundary);
  CHECK(boundary);
  CHECK(end.face == 2);
  CHECK((end.position - Eigen::Vector2d(1.0, 0.5)).norm() < 1e-12);
}

TEST_CASE("tmesh_walk: segments through vertices are moved off them", "[spline]") {
  // Unit cells of a 4 x 4 torus: face f = (i, j) starts at (i, j), f = 4 j + i.
  const TMesh mesh = spline::gridTMesh(test::unitKnots(4), test::unitKnots(4), true, true);
  const auto offset = [](const FacePoint& point, const Eigen::Vector2d& expected) {
    const Eigen::Vector2d global =
        Eigen::Vector2d(point.face % 4, point.face / 4) + point.position - expected;
    return Eigen::Vector2d(global.x() - 4.0 * std::round(global.x() / 4.0),
                           global.y() - 4.0 * std::round(global.y() / 4.0))
        .norm();
  };
  // Along the diagonal through vertices, along a grid line, out through a corner.
  CHECK(offset(walkTMesh(mesh, {0, {0.5, 0.5}}, {2, 2}), {2.5, 2.5}) < 1e-6);
  CHECK(offset(walkTMesh(mesh, {0, {0.5, 0.0}}, {3, 0}), {3.5, 0.0}) < 1e-6);
  CHECK(offset(walkTMesh(mesh, {5, {0.0, 1.0}}, {0, 2.5}), {1.0, 4.5}) < 1e-6);
  const FacePoint corner = walkTMesh(mesh, {0, {0.0, 0.0}}, {-0.5, -0.25});
  CHECK(corner.face == 15);
  CHECK((corner.position - Eigen::Vector2d(0.5, 0.75)).norm() < 1e-6);
}

TEST_CASE("tmesh_walk: across the cube's quarter-turn seams the surface is continuous",
          "[spline]") {
  const test::CubeTMesh cube = test::cubeTMesh(3);
  const TMesh& mesh = cube.mesh;
  const spline::SubdSpace space(mesh);
  int turned = 0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const spline::TMeshFace& face = mesh.faces[std::size_t(f)];
    for (int k = 0; k < 4; ++k) {
      const spline::QuarterMotion across = mesh.acrossEdge(f, k);
      turned += across.quarterTurns != 0;
      // From just inside the middle of edge k, a short step straight out across it.
      const Eigen::Vector2d a = face.positions[std::size_t(k)];
      const Eigen::Vector2d b = face.positions[std::size_t((k + 1) % 4)];
      const Eigen::Vector2d inward = Eigen::Vector2d(-(b - a).y(), (b - a).x()).normalized();
      const double h = 1e-6;
      const FacePoint start{f, 0.5 * (a + b) + 0.3 * h * inward};
      const FacePoint end = walkTMesh(mesh, start, -h * inward);
      REQUIRE(end.face == face.twinFace[std::size_t(k)]);
      // The end is the start moved into the neighbour's frame, then 0.7 h further in.
      const Eigen::Vector2d expected = across.apply(0.5 * (a + b) - 0.7 * h * inward);
      CHECK((end.position - expected).norm() < 1e-12);
      Eigen::Vector3d x, y;
      REQUIRE(space.evaluate(cube.vertexPoints, start.face, start.position, x));
      REQUIRE(space.evaluate(cube.vertexPoints, end.face, end.position, y));
      CHECK((x - y).norm() < 10 * h);
      const FacePoint back = walkTMesh(mesh, end, across.rotate(h * inward));
      CHECK(back.face == f);
      CHECK((back.position - start.position).norm() < 1e-12);
    }
  }
  CHECK(turned > 0);
}

TEST_CASE("tmesh_walk: bad starts are refused", "[spline]") {
  const TMesh mesh = spline::gridTMesh(test::unitKnots(2), test::unitKnots(2));
  CHECK_THROWS_AS(walkTMesh(mesh, {4, {0, 0}}, {1, 0}), structure::InputError);
  CHECK_THROWS_AS(walkTMesh(mesh, {0, {NAN, 0}}, {1, 0}), structure::InputError);
}
