#include <catch2/catch.hpp>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "support/test_meshes.h"

namespace {

using mspline::structure::PolygonSoup;
using mspline::structure::toSoup;
using mspline::structure::toTriMesh;
using mspline::structure::triangulatePolygons;
using Face = std::vector<std::int64_t>;
using UVs = std::vector<std::array<double, 2>>;

PolygonSoup square() {
  PolygonSoup soup;
  soup.sourceName = "square.obj";
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {5, 5, 5}};
  soup.faces = {{0, 1, 2}, {0, 2, 3}};
  return soup;
}

}  // namespace

TEST_CASE("soup_conversion: TriMesh to soup and back keeps indices and positions", "[io]") {
  auto torus = mspline::test::torus(16, 8);
  PolygonSoup soup = toSoup(torus, "torus");
  CHECK(soup.sourceName == "torus");
  REQUIRE(soup.positions.size() == torus.n_vertices());
  REQUIRE(soup.faces.size() == torus.n_faces());
  CHECK(soup.cornerUVs.empty());
  auto back = toTriMesh(soup);
  CHECK(toSoup(back, "torus").faces == soup.faces);
  for (auto v : torus.vertices()) CHECK(back.point(v) == torus.point(v));
  // The torus is closed: every edge has two faces.
  for (auto e : back.edges()) CHECK(!back.is_boundary(e));
}

TEST_CASE("soup_conversion: unreferenced vertices keep their index", "[io]") {
  auto mesh = toTriMesh(square());
  CHECK(mesh.n_vertices() == 5);
  CHECK(mesh.point(mesh.vertex_handle(4)) == mspline::structure::TriMesh::Point(5, 5, 5));
  CHECK(toSoup(mesh).faces == square().faces);
}

TEST_CASE("soup_conversion: corner UVs become halfedge texcoords and come back", "[io]") {
  PolygonSoup soup = square();
  soup.cornerUVs = {{{0, 0}, {1, 0}, {1, 1}}, {{0.5, 0.5}, {1, 1}, {0, 1}}};
  auto mesh = toTriMesh(soup);
  REQUIRE(mesh.has_halfedge_texcoords2D());
  // The halfedge into vertex 0 inside face 1 carries face 1's first corner.
  auto h = mesh.find_halfedge(mesh.vertex_handle(3), mesh.vertex_handle(0));
  REQUIRE(h.is_valid());
  CHECK(mesh.face_handle(h).idx() == 1);
  CHECK(mesh.texcoord2D(h) == mspline::structure::TriMesh::TexCoord2D(0.5, 0.5));
  PolygonSoup back = toSoup(mesh);
  CHECK(back.faces == soup.faces);
  CHECK(back.cornerUVs == soup.cornerUVs);
}

TEST_CASE("soup_conversion: faces OpenMesh cannot add throw TopologyError", "[io]") {
  PolygonSoup fin = square();
  fin.faces.push_back({0, 2, 4});  // a third face on edge 0-2
  CHECK_THROWS_AS(toTriMesh(fin), mspline::structure::TopologyError);
  CHECK_THROWS_WITH(toTriMesh(fin), Catch::Contains("square.obj") && Catch::Contains("face 2"));

  PolygonSoup flipped = square();
  flipped.faces[1] = {2, 0, 3};  // runs along 2->0 like face 0: orientations disagree
  CHECK_THROWS_AS(toTriMesh(flipped), mspline::structure::TopologyError);

  PolygonSoup repeated = square();
  repeated.faces[1] = {0, 2, 2};
  CHECK_THROWS_WITH(toTriMesh(repeated), Catch::Contains("face 1"));

  PolygonSoup outside = square();
  outside.faces[1] = {0, 2, 9};
  CHECK_THROWS_AS(toTriMesh(outside), mspline::structure::InputError);
}

TEST_CASE("soup_conversion: triangulatePolygons fans polygons and their UVs", "[io]") {
  PolygonSoup soup;
  soup.positions.resize(7);
  soup.faces = {{0, 1, 2, 3, 4}, {4, 5, 6}, {0, 1}};
  soup.cornerUVs = {
      {{0, 0}, {1, 0}, {2, 1}, {1, 2}, {0, 1}}, {{9, 9}, {8, 8}, {7, 7}}, {{3, 3}, {4, 4}}};
  CHECK(triangulatePolygons(soup) == 1);
  CHECK(soup.faces == std::vector<Face>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {4, 5, 6}, {0, 1}});
  REQUIRE(soup.cornerUVs.size() == 5);
  CHECK(soup.cornerUVs[1] == UVs{{0, 0}, {2, 1}, {1, 2}});
  CHECK(soup.cornerUVs[2] == UVs{{0, 0}, {1, 2}, {0, 1}});
  CHECK(soup.cornerUVs[3] == UVs{{9, 9}, {8, 8}, {7, 7}});
  CHECK(triangulatePolygons(soup) == 0);
}
