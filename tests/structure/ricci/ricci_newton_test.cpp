#include <catch2/catch.hpp>

#include <cmath>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::BoundaryCondition;
using structure::Cone;
using structure::RicciStatus;
using structure::TriMesh;

namespace {

// Solves, reports the run, and checks what every converged solve must satisfy, recomputing the
// curvatures independently from the returned edge lengths.
structure::RicciResult solveAndCheck(const std::string& name, const TriMesh& mesh,
                                     const structure::CurvatureTarget& target) {
  const auto result = structure::solveVertexScaling(mesh, target);
  WARN(name << ": " << result.message << ", " << result.iterations << " iterations, "
            << result.seconds << " s");
  INFO(name << ": " << result.message);
  REQUIRE(result.converged);
  CHECK(result.status == RicciStatus::Converged);
  CHECK(result.maxCurvatureError <= 1e-10 * 2 * kPi);
  CHECK(result.log.size() == static_cast<std::size_t>(result.iterations) + 1);
  CHECK(result.log.back().maxCurvatureError == result.maxCurvatureError);
  for (std::size_t i = 1; i < result.log.size(); ++i)
    CHECK(result.log[i].energy < result.log[i - 1].energy + 1e-9);
  CHECK(structure::degenerateFaces(mesh, result.edgeLengths).empty());
  const Eigen::VectorXd k = structure::vertexCurvatures(mesh, result.edgeLengths);
  double worst = 0.0;
  for (const auto v : mesh.vertices()) {
    if (target.fixed[v.idx()] || (v.idx() == 0 && !mesh.is_boundary(v))) continue;
    worst = std::max(worst, std::abs(k[v.idx()] - target.curvature[v.idx()]));
  }
  CHECK(worst <= 1e-10 * 2 * kPi);
  // Gauss-Bonnet holds for any metric, so the pinned vertex is right too when nothing is fixed.
  bool anyFixed = false;
  for (char f : target.fixed) anyFixed = anyFixed || f;
  if (!anyFixed) CHECK(std::abs(k[0] - target.curvature[0]) <= 1e-9);
  const Eigen::VectorXd l0 = structure::edgeLengths(mesh);
  CHECK((structure::scaledEdgeLengths(mesh, l0, result.u) - result.edgeLengths)
            .cwiseAbs()
            .maxCoeff() == 0.0);
  return result;
}

TriMesh bumpyDisk(int n) {
  TriMesh mesh = test::gridDisk(n);
  for (const auto v : mesh.vertices()) {
    auto p = mesh.point(v);
    p[2] = 0.4 * std::exp(-10.0 * ((p[0] - 0.5) * (p[0] - 0.5) + (p[1] - 0.4) * (p[1] - 0.4)));
    mesh.set_point(v, p);
  }
  return mesh;
}

}  // namespace

TEST_CASE("ricci_newton: flat torus without cones", "[structure]") {
  const TriMesh mesh = test::torus(32, 16);
  solveAndCheck("generated torus", mesh, structure::flatTarget(mesh, {}));
}

TEST_CASE("ricci_newton: knot1.off, genus 1, no cones", "[structure]") {
  const TriMesh mesh = test::realMesh("knot1.off");
  REQUIRE(structure::analyzeTopology(mesh).genus == 1);
  const auto result = solveAndCheck("knot1.off", mesh, structure::flatTarget(mesh, {}));
  CHECK(result.iterations <= 20);
}

TEST_CASE("ricci_newton: icosphere with eight cones of pi/2", "[structure]") {
  const TriMesh mesh = test::icosphere(3);
  const std::vector<Cone> cones = test::cubeCornerCones(mesh);
  const auto target = structure::flatTarget(mesh, cones);
  solveAndCheck("icosphere, 8 cones", mesh, target);
}

TEST_CASE("ricci_newton: disk with a bump", "[structure]") {
  const TriMesh mesh = bumpyDisk(16);
  SECTION("free boundary: u = 0 on the boundary, flat inside") {
    const auto result =
        solveAndCheck("bumpy disk, fixed boundary", mesh, structure::flatTarget(mesh, {}));
    const Eigen::VectorXd l0 = structure::edgeLengths(mesh);
    for (const auto e : mesh.edges())
      if (mesh.is_boundary(e)) CHECK(result.edgeLengths[e.idx()] == l0[e.idx()]);
  }
  SECTION("prescribed geodesic curvature: a rectangle") {
    std::vector<Cone> corners;
    for (const auto& c : {OpenMesh::Vec3d(0, 0, 0), OpenMesh::Vec3d(1, 0, 0),
                          OpenMesh::Vec3d(1, 1, 0), OpenMesh::Vec3d(0, 1, 0)})
      corners.push_back({test::nearestVertex(mesh, c), kPi / 2});
    const auto target =
        structure::flatTarget(mesh, corners, BoundaryCondition::PrescribedGeodesicCurvature);
    const auto result = solveAndCheck("bumpy disk, rectangle", mesh, target);
    const Eigen::VectorXd k = structure::vertexCurvatures(mesh, result.edgeLengths);
    for (const Cone& c : corners) CHECK(std::abs(k[c.vertex] - kPi / 2) <= 1e-9);
  }
}

TEST_CASE("ricci_newton: mannequin-devil.off needs flips with a fixed boundary",
          "[structure][slow]") {
  // Holding u = 0 on the boundary of this deep disk forces triangles against the triangle
  // inequality: without intrinsic Delaunay flips there is no solution in this triangulation, and
  // the solver must say so while returning its last valid metric.
  const TriMesh mesh = test::realMesh("mannequin-devil.off");
  REQUIRE(structure::analyzeTopology(mesh).boundaryLoops == 1);
  const auto result = structure::solveVertexScaling(mesh, structure::flatTarget(mesh, {}));
  WARN("mannequin-devil.off: " << result.message << ", " << result.seconds << " s");
  CHECK_FALSE(result.converged);
  CHECK(result.status == RicciStatus::DegenerateTriangles);
  CHECK_FALSE(result.degenerateFaces.empty());
  CHECK_THAT(result.message, Catch::Contains("flips"));
  CHECK(structure::degenerateFaces(mesh, result.edgeLengths).empty());
  CHECK(result.maxCurvatureError < result.log.front().maxCurvatureError);
  for (std::size_t i = 1; i < result.log.size(); ++i)
    CHECK(result.log[i].energy < result.log[i - 1].energy + 1e-9);
}

TEST_CASE("ricci_newton: Gauss-Bonnet violations are input errors", "[structure]") {
  const TriMesh torus = test::torus(16, 8);
  const auto bad = structure::flatTarget(torus, {{5, 0.5}});
  CHECK_THROWS_AS(structure::checkGaussBonnet(torus, bad), structure::InputError);
  CHECK_THROWS_WITH(structure::solveVertexScaling(torus, bad),
                    Catch::Contains("0.5") && Catch::Contains("2 pi chi = 0"));
  const TriMesh sphere = test::icosphere(2);
  std::vector<Cone> cones = {{0, kPi / 2}, {1, kPi / 2}, {2, kPi / 2}, {3, kPi / 2},
                             {4, kPi / 2}, {5, kPi / 2}, {6, kPi / 2}};
  CHECK_THROWS_AS(structure::solveVertexScaling(sphere, structure::flatTarget(sphere, cones)),
                  structure::InputError);
  cones.push_back({7, kPi / 2});
  CHECK_NOTHROW(structure::checkGaussBonnet(sphere, structure::flatTarget(sphere, cones)));
  // Bounded surfaces count the geodesic curvature: a disk needs 2 pi along its boundary.
  const TriMesh disk = test::gridDisk(4);
  CHECK_THROWS_AS(
      structure::checkGaussBonnet(
          disk, structure::flatTarget(disk, {}, BoundaryCondition::PrescribedGeodesicCurvature)),
      structure::InputError);
  // Bad cone lists.
  CHECK_THROWS_AS(structure::flatTarget(torus, {{-1, 0.0}}), structure::InputError);
  CHECK_THROWS_AS(structure::flatTarget(torus, {{3, 0.1}, {3, -0.1}}), structure::InputError);
  CHECK_THROWS_AS(structure::flatTarget(disk, {{0, kPi / 2}}), structure::InputError);
}

TEST_CASE("ricci_newton: failures are reported, not hidden", "[structure]") {
  SECTION("iteration limit") {
    const TriMesh mesh = test::realMesh("knot1.off");
    structure::RicciNewtonOptions options;
    options.maxIterations = 1;
    const auto result =
        structure::solveVertexScaling(mesh, structure::flatTarget(mesh, {}), options);
    CHECK_FALSE(result.converged);
    CHECK(result.status == RicciStatus::MaxIterations);
    CHECK(result.iterations == 1);
    CHECK(result.maxCurvatureError > 1e-10);
    CHECK_THAT(result.message, Catch::Contains("no convergence"));
  }
  SECTION("degenerate input triangle") {
    // A disk of three triangles, one of them with collinear corners.
    TriMesh mesh;
    const auto a = mesh.add_vertex({0, 0, 0});
    const auto b = mesh.add_vertex({2, 0, 0});
    const auto c = mesh.add_vertex({1, 0, 0});
    const auto d = mesh.add_vertex({1, 1, 0});
    mesh.add_face(a, c, d);
    mesh.add_face(c, b, d);
    mesh.add_face(a, b, c);
    const auto result = structure::solveVertexScaling(mesh, structure::flatTarget(mesh, {}));
    CHECK_FALSE(result.converged);
    CHECK(result.status == RicciStatus::DegenerateTriangles);
    CHECK(result.degenerateFaces == std::vector<int>{2});
    CHECK_THAT(result.message, Catch::Contains("face 2"));
  }
  SECTION("a target this triangulation cannot reach") {
    // A square fan around one interior vertex: its curvature cannot go below -2 pi (all four
    // angles at it reaching pi) before the triangles degenerate.
    TriMesh mesh;
    const auto center = mesh.add_vertex({0.5, 0.5, 0});
    std::vector<TriMesh::VertexHandle> ring = {
        mesh.add_vertex({0, 0, 0}), mesh.add_vertex({1, 0, 0}), mesh.add_vertex({1, 1, 0}),
        mesh.add_vertex({0, 1, 0})};
    for (int i = 0; i < 4; ++i) mesh.add_face(center, ring[i], ring[(i + 1) % 4]);
    const auto result = structure::solveVertexScaling(
        mesh, structure::flatTarget(mesh, {{center.idx(), -2.5 * kPi}}));
    WARN("square fan: " << result.message);
    CHECK_FALSE(result.converged);
    CHECK(result.status == RicciStatus::DegenerateTriangles);
    CHECK_FALSE(result.degenerateFaces.empty());
    CHECK_THAT(result.message, Catch::Contains("flips"));
    // The returned metric is the last valid one.
    CHECK(structure::degenerateFaces(mesh, result.edgeLengths).empty());
  }
}
