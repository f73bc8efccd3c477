#include <catch2/catch.hpp>
#include <set>

#include "mspline/io/load_mesh.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/topology/homotopy_basis.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::computeHomotopyBasis;
using structure::HomotopyBasis;
using structure::TriMesh;

namespace {

// Every loop closed at the base, walking along mesh edges, containing its leftover edge, with the
// reported length; the leftover edges are distinct.
void checkLoops(const TriMesh& mesh, const HomotopyBasis& basis, int genus) {
  REQUIRE(basis.genus == genus);
  REQUIRE(basis.loops.size() == std::size_t(2 * genus));
  REQUIRE(basis.lengths.size() == basis.loops.size());
  REQUIRE(basis.leftoverEdges.size() == basis.loops.size());
  CHECK(std::set<int>(basis.leftoverEdges.begin(), basis.leftoverEdges.end()).size() ==
        basis.leftoverEdges.size());
  for (std::size_t i = 0; i < basis.loops.size(); ++i) {
    const auto& loop = basis.loops[i];
    REQUIRE(loop.size() >= 4);
    CHECK(loop.front() == basis.baseVertex);
    CHECK(loop.back() == basis.baseVertex);
    double length = 0;
    bool usesLeftover = false;
    for (std::size_t k = 0; k + 1 < loop.size(); ++k) {
      const auto h =
          mesh.find_halfedge(TriMesh::VertexHandle(loop[k]), TriMesh::VertexHandle(loop[k + 1]));
      REQUIRE(h.is_valid());
      length += mesh.calc_edge_length(h);
      usesLeftover = usesLeftover || mesh.edge_handle(h).idx() == basis.leftoverEdges[i];
    }
    CHECK(usesLeftover);
    CHECK(length == Approx(basis.lengths[i]).epsilon(1e-9));
  }
}

}  // namespace

TEST_CASE("homotopy_basis: torus loops are closed and the shortest is the tube's circle",
          "[structure]") {
  const TriMesh mesh = test::torus(16, 8);
  const HomotopyBasis basis = computeHomotopyBasis(mesh);
  CHECK(basis.baseVertex == 0);
  checkLoops(mesh, basis, 1);
  CHECK(basis.boundaryLoops.empty());
  // The minor circle (8 edges of 2 * 0.4 * sin(pi / 8)) is the shortest non-contractible loop
  // through any vertex; the greedy basis must find it.
  const double minor = 8 * 2 * 0.4 * std::sin(kPi / 8);
  CHECK(std::min(basis.lengths[0], basis.lengths[1]) == Approx(minor).epsilon(1e-9));
  CHECK(std::max(basis.lengths[0], basis.lengths[1]) > minor);
}

TEST_CASE("homotopy_basis: base vertex option and tree", "[structure]") {
  const TriMesh mesh = test::doubleTorus(2);
  structure::HomotopyBasisOptions options;
  options.baseVertex = 17;
  const HomotopyBasis basis = computeHomotopyBasis(mesh, options);
  CHECK(basis.baseVertex == 17);
  checkLoops(mesh, basis, 2);
  CHECK(basis.distance[17] == 0);
  CHECK(basis.parent[17] == -1);
  const auto path = structure::treePath(basis, 5);
  CHECK(path.front() == 17);
  CHECK(path.back() == 5);
  options.baseVertex = int(mesh.n_vertices());
  CHECK_THROWS_AS(computeHomotopyBasis(mesh, options), structure::InputError);
}

TEST_CASE("homotopy_basis: real closed meshes", "[structure]") {
  checkLoops(test::realMesh("knot1.off"), computeHomotopyBasis(test::realMesh("knot1.off")), 1);
  const TriMesh eight = test::realMesh("eight.off");
  checkLoops(eight, computeHomotopyBasis(eight), 2);
  const TriMesh elephant = test::realMesh("elephant.off");
  checkLoops(elephant, computeHomotopyBasis(elephant), 3);
}

TEST_CASE("homotopy_basis: boundaries are capped and reported", "[structure]") {
  SECTION("pair of pants") {
    const TriMesh mesh = test::pairOfPants(2);
    const HomotopyBasis basis = computeHomotopyBasis(mesh);
    checkLoops(mesh, basis, 0);
    REQUIRE(basis.boundaryLoops.size() == 3);
    REQUIRE(basis.boundaryAnchors.size() == 3);
    CHECK(mesh.is_boundary(TriMesh::VertexHandle(basis.baseVertex)));
    for (std::size_t b = 0; b < 3; ++b) {
      const auto& loop = basis.boundaryLoops[b];
      CHECK(std::find(loop.begin(), loop.end(), basis.boundaryAnchors[b]) != loop.end());
      for (int v : loop) CHECK(basis.distance[v] >= basis.distance[basis.boundaryAnchors[b]]);
    }
  }
  SECTION("torus with a hole") {
    TriMesh mesh = test::torus(12, 6);
    mesh.delete_face(TriMesh::FaceHandle(7), false);
    mesh.garbage_collection();
    const HomotopyBasis basis = computeHomotopyBasis(mesh);
    checkLoops(mesh, basis, 1);
    CHECK(basis.boundaryLoops.size() == 1);
    CHECK(basis.boundaryLoops[0].size() == 3);
  }
}

TEST_CASE("homotopy_basis: rejects several components", "[structure]") {
  structure::PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
  soup.faces = {{0, 1, 2}, {3, 4, 5}};
  CHECK_THROWS_AS(computeHomotopyBasis(structure::toTriMesh(soup)), structure::TopologyError);
}

TEST_CASE("homotopy_basis: rejects a non-manifold vertex", "[structure]") {
  // Two triangles sharing only vertex 0 (a bow-tie): one component, but not a surface at 0.
  structure::PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  soup.faces = {{0, 1, 2}, {0, 3, 4}};
  const TriMesh mesh = structure::toTriMesh(soup);
  REQUIRE(mesh.n_faces() == 2);
  CHECK_THROWS_AS(computeHomotopyBasis(mesh), structure::TopologyError);
}
