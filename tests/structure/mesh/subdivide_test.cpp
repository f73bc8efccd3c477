#include "mspline/structure/mesh/subdivide.h"

#include <catch2/catch.hpp>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/mesh_statistics.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::TriMesh;

namespace {

void checkSubdivision(const TriMesh& coarse) {
  TriMesh fine = structure::subdivideMidpoint(coarse);
  REQUIRE(fine.n_faces() == 4 * coarse.n_faces());
  REQUIRE(fine.n_vertices() == coarse.n_vertices() + coarse.n_edges());

  // Old vertices keep their index; vertex V + e is the midpoint of edge e.
  for (auto v : coarse.vertices()) CHECK(fine.point(v) == coarse.point(v));
  const int V = int(coarse.n_vertices());
  for (auto e : coarse.edges()) {
    auto h = coarse.halfedge_handle(e, 0);
    auto mid = 0.5 * (coarse.point(coarse.from_vertex_handle(h)) +
                      coarse.point(coarse.to_vertex_handle(h)));
    CHECK(fine.point(TriMesh::VertexHandle(V + e.idx())) == mid);
  }

  // Topology and the surface itself are unchanged.
  auto before = structure::analyzeTopology(coarse), after = structure::analyzeTopology(fine);
  CHECK(after.euler == before.euler);
  CHECK(after.boundaryLoops == before.boundaryLoops);
  CHECK(after.components == before.components);
  auto areaBefore = structure::meshStatistics(coarse).area;
  CHECK(structure::meshStatistics(fine).area == Approx(areaBefore).epsilon(1e-12));

  // Children keep the parent's orientation: their normals agree with the parent face's normal.
  for (auto f : coarse.faces()) {
    auto parentNormal = coarse.calc_face_normal(f);
    for (int child = 0; child < 4; ++child) {
      auto childNormal = fine.calc_face_normal(TriMesh::FaceHandle(4 * f.idx() + child));
      CHECK(OpenMesh::dot(parentNormal, childNormal) > 0.999);
    }
  }
}

}  // namespace

TEST_CASE("subdivide: midpoint split of closed and bounded meshes", "[structure]") {
  checkSubdivision(test::icosphere(1));
  checkSubdivision(test::torus(12, 8));
  checkSubdivision(test::pairOfPants(2));
  checkSubdivision(test::cylinder(10, 3));
}

TEST_CASE("subdivide: to at least a face count", "[structure]") {
  TriMesh sphere = test::icosphere(0);
  TriMesh fine = structure::subdivideToAtLeast(sphere, 1000);
  CHECK(fine.n_faces() == 20 * 64);  // 20 -> 80 -> 320 -> 1280
  CHECK(structure::subdivideToAtLeast(sphere, 10).n_faces() == 20);
  CHECK_THROWS_AS(structure::subdivideToAtLeast(TriMesh(), 10), structure::InputError);
}

TEST_CASE("subdivide: vertex V + e splits edge e into two output edges", "[structure]") {
  // The promise another algorithm relies on to carry marked (cut) edges to the finer mesh.
  for (const TriMesh& coarse : {test::gridDisk(3), test::doubleTorus(1)}) {
    TriMesh fine = structure::subdivideMidpoint(coarse);
    const int V = int(coarse.n_vertices());
    CHECK(fine.n_edges() == 2 * coarse.n_edges() + 3 * coarse.n_faces());
    for (auto e : coarse.edges()) {
      auto h = coarse.halfedge_handle(e, 0);
      TriMesh::VertexHandle mid(V + e.idx());
      auto first = fine.find_halfedge(coarse.from_vertex_handle(h), mid);
      auto second = fine.find_halfedge(mid, coarse.to_vertex_handle(h));
      REQUIRE(first.is_valid());
      REQUIRE(second.is_valid());
      CHECK(fine.is_boundary(fine.edge_handle(first)) == coarse.is_boundary(e));
      CHECK(fine.is_boundary(fine.edge_handle(second)) == coarse.is_boundary(e));
    }
  }
}

TEST_CASE("subdivide: subdivideToAtLeast stops at the first level reaching the target",
          "[structure]") {
  TriMesh sphere = test::icosphere(0);
  CHECK(structure::subdivideToAtLeast(sphere, 20).n_faces() == 20);
  CHECK(structure::subdivideToAtLeast(sphere, 21).n_faces() == 80);
  CHECK(structure::subdivideToAtLeast(sphere, 1281).n_faces() == 5120);
  // Repeated steps keep the numbering of single steps.
  TriMesh twice = structure::subdivideMidpoint(structure::subdivideMidpoint(sphere));
  TriMesh target = structure::subdivideToAtLeast(sphere, 300);
  REQUIRE(target.n_vertices() == twice.n_vertices());
  for (auto v : twice.vertices()) CHECK(target.point(v) == twice.point(v));
}

TEST_CASE("subdivide: a million output faces", "[structure]") {
  // 327,680 -> 1,310,720 faces: about 0.3 s in a Release build.
  TriMesh coarse = test::icosphere(7);
  TriMesh fine = structure::subdivideMidpoint(coarse);
  CHECK(fine.n_faces() == 4 * coarse.n_faces());
  CHECK(long(fine.n_vertices()) - long(fine.n_edges()) + long(fine.n_faces()) == 2);
  auto lastEdge = coarse.halfedge_handle(TriMesh::EdgeHandle(int(coarse.n_edges()) - 1), 0);
  auto lastMid = 0.5 * (coarse.point(coarse.from_vertex_handle(lastEdge)) +
                        coarse.point(coarse.to_vertex_handle(lastEdge)));
  CHECK(fine.point(TriMesh::VertexHandle(int(fine.n_vertices()) - 1)) == lastMid);
}
