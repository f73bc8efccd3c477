#include "mspline/structure/mesh/mesh_statistics.h"
#include "mspline/structure/core/constants.h"

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
  CHECK(fine.area == Approx(4 * kPi).epsilon(2e-3));
  CHECK(fine.area < 4 * kPi);  // inscribed polyhedra have less area than the sphere
}

TEST_CASE("mesh_statistics: empty mesh gives zeros", "[structure]") {
  auto stats = structure::meshStatistics(structure::TriMesh());
  CHECK(stats.area == 0);
  CHECK(stats.bboxDiagonal == 0);
}

TEST_CASE("mesh_statistics: icosahedron edge, area and bounding box", "[structure]") {
  auto stats = structure::meshStatistics(test::icosphere(0));
  const double edge = 1 / std::sin(2 * kPi / 5);  // circumradius 1
  const double golden = (1 + std::sqrt(5.0)) / 2;
  const double extent = golden / std::sqrt(1 + golden * golden);
  CHECK(stats.minEdgeLength == Approx(edge));
  CHECK(stats.maxEdgeLength == Approx(edge));
  CHECK(stats.area == Approx(5 * std::sqrt(3.0) * edge * edge));
  CHECK(stats.bboxMax[0] == Approx(extent));
  CHECK(stats.bboxMin[2] == Approx(-extent));
  CHECK(stats.bboxDiagonal == Approx(2 * std::sqrt(3.0) * extent));
}

TEST_CASE("mesh_statistics: median of an even number of corners averages the middle two",
          "[structure]") {
  // Two separate triangles, 30-60-90 and 45-45-90: sorted corners 30 45 45 60 90 90.
  structure::TriMesh mesh;
  using P = structure::TriMesh::Point;
  auto a = mesh.add_vertex(P(0, 0, 0)), b = mesh.add_vertex(P(std::sqrt(3.0), 0, 0)),
       c = mesh.add_vertex(P(0, 1, 0));
  auto d = mesh.add_vertex(P(5, 0, 0)), e = mesh.add_vertex(P(6, 0, 0)),
       f = mesh.add_vertex(P(5, 1, 0));
  mesh.add_face(a, b, c);
  mesh.add_face(d, e, f);
  auto stats = structure::meshStatistics(mesh);
  CHECK(stats.minAngleDegrees == Approx(30.0));
  CHECK(stats.medianAngleDegrees == Approx(52.5));
  CHECK(stats.minEdgeLength == Approx(1.0));
  CHECK(stats.maxEdgeLength == Approx(2.0));
  CHECK(stats.area == Approx(std::sqrt(3.0) / 2 + 0.5));
  CHECK(stats.bboxDiagonal == Approx(std::sqrt(37.0)));
}

TEST_CASE("mesh_statistics: collinear triangle has zero corners and zero area", "[structure]") {
  structure::TriMesh mesh;
  using P = structure::TriMesh::Point;
  mesh.add_face(mesh.add_vertex(P(0, 0, 0)), mesh.add_vertex(P(1, 0, 0)),
                mesh.add_vertex(P(3, 0, 0)));
  auto stats = structure::meshStatistics(mesh);
  CHECK(stats.minAngleDegrees == 0.0);  // corners 0, 180, 0
  CHECK(stats.medianAngleDegrees == 0.0);
  CHECK(stats.area == 0.0);
  CHECK(stats.minEdgeLength == Approx(1.0));
  CHECK(stats.maxEdgeLength == Approx(3.0));
}

TEST_CASE("mesh_statistics: dihedral angles and folded edges", "[structure]") {
  // Two triangles hinged on the x-axis: the second one's normal turned by `turn` degrees.
  const auto hinge = [](double turn) {
    structure::TriMesh mesh;
    using P = structure::TriMesh::Point;
    const double t = turn * kPi / 180.0;
    const auto a = mesh.add_vertex(P(0, 0, 0)), b = mesh.add_vertex(P(1, 0, 0)),
               c = mesh.add_vertex(P(0.5, 1, 0)),
               d = mesh.add_vertex(P(0.5, -std::cos(t), std::sin(t)));
    mesh.add_face(a, b, c);
    mesh.add_face(b, a, d);
    return structure::meshStatistics(mesh);
  };
  for (const double turn : {0.0, 60.0, 89.0, 91.0, 150.0}) {
    INFO("turned by " << turn);
    const auto stats = hinge(turn);
    CHECK(stats.maxDihedralDegrees == Approx(turn).margin(1e-9));
    CHECK(stats.foldedEdges == (turn > 90.0 ? 1 : 0));
  }
  // The icosahedron's dihedral angle is 138.19 degrees: its normals turn by 41.81.
  const auto ico = structure::meshStatistics(test::icosphere(0));
  CHECK(ico.maxDihedralDegrees == Approx(180.0 - std::acos(-std::sqrt(5.0) / 3.0) * 180.0 / kPi));
  CHECK(ico.foldedEdges == 0);
  CHECK(structure::meshStatistics(test::gridDisk(4)).maxDihedralDegrees == Approx(0.0).margin(1e-12));
}
