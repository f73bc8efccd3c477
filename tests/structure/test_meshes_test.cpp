// Checks the shared generated meshes against their documented topology, computed here directly
// with OpenMesh so that the generators do not depend on the library's topology code.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/mesh_statistics.h"
#include "support/test_meshes.h"

using mspline::structure::TriMesh;
namespace test = mspline::test;

namespace {

struct Shape {
  long euler = 0;
  int boundaryLoops = 0;
  int components = 0;
  bool everyVertexManifold = true;
  bool isolatedVertices = false;
  double minAngleDegrees = 180;
  double signedVolume = 0;
};

Shape shapeOf(const TriMesh& mesh) {
  Shape s;
  s.euler = long(mesh.n_vertices()) - long(mesh.n_edges()) + long(mesh.n_faces());

  std::vector<char> seen(mesh.n_halfedges(), 0);
  for (const auto h : mesh.halfedges()) {
    if (!mesh.is_boundary(h) || seen[h.idx()]) continue;
    ++s.boundaryLoops;
    for (auto g = h; !seen[g.idx()]; g = mesh.next_halfedge_handle(g)) seen[g.idx()] = 1;
  }

  std::vector<int> component(mesh.n_vertices(), -1);
  for (const auto start : mesh.vertices()) {
    if (component[start.idx()] >= 0) continue;
    std::vector<TriMesh::VertexHandle> stack{start};
    component[start.idx()] = s.components;
    while (!stack.empty()) {
      const auto v = stack.back();
      stack.pop_back();
      for (const auto w : mesh.vv_range(v))
        if (component[w.idx()] < 0) {
          component[w.idx()] = s.components;
          stack.push_back(w);
        }
    }
    ++s.components;
  }

  for (const auto v : mesh.vertices()) {
    s.everyVertexManifold = s.everyVertexManifold && mesh.is_manifold(v);
    s.isolatedVertices = s.isolatedVertices || mesh.is_isolated(v);
  }

  for (const auto f : mesh.faces()) {
    std::vector<TriMesh::Point> p;
    for (const auto v : mesh.fv_range(f)) p.push_back(mesh.point(v));
    s.signedVolume += OpenMesh::dot(p[0], OpenMesh::cross(p[1], p[2])) / 6;
    for (int k = 0; k < 3; ++k) {
      const auto a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
      const double angle =
          std::acos(std::clamp(OpenMesh::dot(a, b) / (a.norm() * b.norm()), -1.0, 1.0));
      s.minAngleDegrees = std::min(s.minAngleDegrees, angle * 180 / mspline::kPi);
    }
  }
  return s;
}

void requireClean(const Shape& s, long euler, int boundaryLoops, double minAngle) {
  CHECK(s.euler == euler);
  CHECK(s.boundaryLoops == boundaryLoops);
  CHECK(s.components == 1);
  CHECK(s.everyVertexManifold);
  CHECK_FALSE(s.isolatedVertices);
  CHECK(s.minAngleDegrees > minAngle);
}

}  // namespace

TEST_CASE("test_meshes: gridDisk is a flat unit-square disk", "[structure]") {
  for (int n : {1, 2, 7}) {
    const TriMesh mesh = test::gridDisk(n);
    CHECK(mesh.n_faces() == std::size_t(2 * n * n));
    CHECK(mesh.n_vertices() == std::size_t((n + 1) * (n + 1)));
    requireClean(shapeOf(mesh), 1, 1, 44.9);
    for (const auto f : mesh.faces()) CHECK(mesh.calc_face_normal(f)[2] == Approx(1.0));
  }
}

TEST_CASE("test_meshes: cylinder is an annulus with outward normals", "[structure]") {
  const TriMesh mesh = test::cylinder(24, 6);
  CHECK(mesh.n_faces() == 2u * 24 * 6);
  requireClean(shapeOf(mesh), 0, 2, 20);
  for (const auto f : mesh.faces()) {
    const auto c = mesh.calc_face_centroid(f);
    const auto n = mesh.calc_face_normal(f);
    CHECK(n[0] * c[0] + n[1] * c[1] > 0);
  }
  for (const auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    CHECK(std::hypot(p[0], p[1]) == Approx(0.5 + 0.5 * p[2]));
  }
}

TEST_CASE("test_meshes: torus is a closed genus-1 surface", "[structure]") {
  const TriMesh mesh = test::torus(32, 12);
  CHECK(mesh.n_faces() == 2u * 32 * 12);
  const Shape s = shapeOf(mesh);
  requireClean(s, 0, 0, 20);
  // Enclosed volume of the exact torus is 2 pi^2 R r^2; the polyhedron is slightly smaller.
  const double exact = 2 * mspline::kPi * mspline::kPi * 1.0 * 0.4 * 0.4;
  CHECK(s.signedVolume > 0.9 * exact);
  CHECK(s.signedVolume < exact);
}

TEST_CASE("test_meshes: icosphere is a closed outward unit sphere", "[structure]") {
  for (int level : {0, 1, 3}) {
    const TriMesh mesh = test::icosphere(level);
    CHECK(mesh.n_faces() == 20u << (2 * level));
    const Shape s = shapeOf(mesh);
    requireClean(s, 2, 0, 50);
    CHECK(s.signedVolume > 0);
    CHECK(s.signedVolume < 4 * mspline::kPi / 3);
    for (const auto v : mesh.vertices()) CHECK(mesh.point(v).norm() == Approx(1.0));
  }
  CHECK(test::icosphere(3).n_vertices() == 642u);
}

TEST_CASE("test_meshes: genusSurface has genus g, is closed and well shaped", "[structure]") {
  for (int genus : {1, 2, 3}) {
    for (int resolution : {1, 2, 4}) {
      CAPTURE(genus, resolution);
      const TriMesh mesh = test::genusSurface(genus, resolution);
      CHECK(mesh.n_faces() == std::size_t((36 * genus + 28) * resolution * resolution));
      const Shape s = shapeOf(mesh);
      requireClean(s, 2 - 2 * genus, 0, 15);
      CHECK(s.signedVolume > 0);
    }
  }
}

TEST_CASE("test_meshes: doubleTorus is the genus-2 surface", "[structure]") {
  const TriMesh mesh = test::doubleTorus(3);
  const TriMesh same = test::genusSurface(2, 3);
  REQUIRE(mesh.n_vertices() == same.n_vertices());
  CHECK(mesh.n_faces() == same.n_faces());
  requireClean(shapeOf(mesh), -2, 0, 15);
  const auto stats = mspline::structure::meshStatistics(mesh);
  // A rounded 5 x 3 x 1 slab, centred at the origin.
  CHECK(stats.bboxMax[0] == Approx(-stats.bboxMin[0]));
  CHECK(stats.bboxMax[0] - stats.bboxMin[0] > 4);
  CHECK(stats.bboxMax[0] - stats.bboxMin[0] < 5.5);
  CHECK(stats.bboxMax[2] - stats.bboxMin[2] < 1.2);
}

TEST_CASE("test_meshes: pairOfPants is a disk with two holes", "[structure]") {
  for (int resolution : {1, 2, 5}) {
    CAPTURE(resolution);
    const TriMesh mesh = test::pairOfPants(resolution);
    CHECK(mesh.n_faces() == std::size_t(26 * resolution * resolution));
    requireClean(shapeOf(mesh), -1, 3, 30);
    for (const auto f : mesh.faces()) CHECK(mesh.calc_face_normal(f)[2] > 0.5);
  }
}

TEST_CASE("test_meshes: generators reject sizes too small for their topology", "[structure]") {
  using mspline::structure::InputError;
  CHECK_THROWS_AS(test::gridDisk(0), InputError);
  CHECK_THROWS_AS(test::cylinder(2, 1), InputError);
  CHECK_THROWS_AS(test::torus(3, 2), InputError);
  CHECK_THROWS_AS(test::icosphere(-1), InputError);
  CHECK_THROWS_AS(test::genusSurface(0, 2), InputError);
  CHECK_THROWS_AS(test::pairOfPants(0), InputError);
}
