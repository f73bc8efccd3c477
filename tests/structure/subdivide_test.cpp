#include "structure/subdivide.h"

#include <catch2/catch.hpp>

#include "structure/errors.h"
#include "structure/mesh_statistics.h"
#include "structure/topology.h"
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
