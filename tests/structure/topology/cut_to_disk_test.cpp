#include <algorithm>
#include <catch2/catch.hpp>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "mspline/io/load_mesh.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/topology/cut_to_disk.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::CutOptions;
using structure::CutResult;
using structure::cutToDisk;
using structure::TriMesh;
using VH = TriMesh::VertexHandle;

namespace {

std::vector<int> segmentSurfaceVertices(const CutResult& r, const structure::BoundarySegment& s) {
  const std::size_t n = r.boundaryLoop.size();
  std::size_t count = (s.end + n - s.begin) % n;
  if (count == 0) count = n;
  std::vector<int> vertices;
  for (std::size_t k = 0; k <= count; ++k)
    vertices.push_back(r.surfaceVertex[r.boundaryLoop[(s.begin + k) % n]]);
  return vertices;
}

std::vector<std::string> words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> tokens;
  for (std::string t; in >> t;) tokens.push_back(t);
  return tokens;
}

double area(const TriMesh& mesh) {
  double sum = 0.0;
  for (auto f : mesh.faces()) {
    std::vector<OpenMesh::Vec3d> p;
    for (auto v : mesh.fv_range(f)) p.push_back(mesh.point(v));
    sum += 0.5 * OpenMesh::cross(p[1] - p[0], p[2] - p[0]).norm();
  }
  return sum;
}

// Properties every cut must have, checked from the meshes rather than from the reported numbers.
void checkDisk(const TriMesh& input, const CutResult& r) {
  const auto topology = structure::analyzeTopology(r.disk);
  CHECK(topology.euler == 1);
  CHECK(topology.boundaryLoops == 1);
  CHECK(topology.components == 1);
  CHECK(r.diskEuler == 1);
  CHECK(r.diskBoundaryLoops == 1);
  CHECK(r.diskComponents == 1);
  CHECK(structure::analyzeTopology(r.surface).euler == structure::analyzeTopology(input).euler);

  // Face f of the disk is face f of the surface, corner by corner, and copies sit where the
  // vertices they copy sit.
  REQUIRE(r.disk.n_faces() == r.surface.n_faces());
  REQUIRE(r.surfaceVertex.size() == r.disk.n_vertices());
  REQUIRE(r.inputVertex.size() == r.disk.n_vertices());
  for (auto f : r.disk.faces()) {
    std::vector<int> diskCorners, surfaceCorners;
    for (auto v : r.disk.fv_range(f)) diskCorners.push_back(r.surfaceVertex[v.idx()]);
    for (auto v : r.surface.fv_range(TriMesh::FaceHandle(f.idx())))
      surfaceCorners.push_back(v.idx());
    REQUIRE(surfaceCorners.size() == 3);
    const auto at = std::find(surfaceCorners.begin(), surfaceCorners.end(), diskCorners[0]);
    REQUIRE(at != surfaceCorners.end());
    std::rotate(surfaceCorners.begin(), at, surfaceCorners.end());
    CHECK(diskCorners == surfaceCorners);
  }
  for (auto v : r.disk.vertices()) {
    const int s = r.surfaceVertex[v.idx()];
    CHECK((r.disk.point(v) - r.surface.point(VH(s))).norm() == 0);
    CHECK(r.inputVertex[v.idx()] == (s < int(input.n_vertices()) ? s : -1));
    if (s < int(input.n_vertices()))
      CHECK((r.surface.point(VH(s)) - input.point(VH(s))).norm() == 0);
  }

  // The boundary loop follows the disk's boundary halfedges and visits every boundary vertex once.
  std::size_t boundaryVertices = 0;
  for (auto v : r.disk.vertices()) boundaryVertices += r.disk.is_boundary(v);
  REQUIRE(r.boundaryLoop.size() == boundaryVertices);
  for (std::size_t k = 0; k < r.boundaryLoop.size(); ++k) {
    const auto h = r.disk.find_halfedge(VH(r.boundaryLoop[k]),
                                        VH(r.boundaryLoop[(k + 1) % r.boundaryLoop.size()]));
    REQUIRE(h.is_valid());
    CHECK(r.disk.is_boundary(h));
  }

  // Segments tile the loop; each copies its curve in the stated direction; the word lists them.
  REQUIRE(!r.segments.empty());
  CHECK(r.segments.front().begin == 0);
  for (std::size_t k = 0; k < r.segments.size(); ++k)
    CHECK(r.segments[k].end == r.segments[(k + 1) % r.segments.size()].begin);
  std::map<std::size_t, std::vector<int>> orientations;
  for (const auto& s : r.segments) {
    REQUIRE(s.curve < r.curves.size());
    std::vector<int> vertices = segmentSurfaceVertices(r, s);
    if (s.orientation < 0) std::reverse(vertices.begin(), vertices.end());
    CHECK(vertices == r.curves[s.curve]);
    orientations[s.curve].push_back(s.orientation);
  }
  REQUIRE(r.curveNames.size() == r.curves.size());
  const auto tokens = words(r.word);
  REQUIRE(tokens.size() == r.segments.size());
  for (std::size_t k = 0; k < tokens.size(); ++k)
    CHECK(tokens[k] ==
          r.curveNames[r.segments[k].curve] + (r.segments[k].orientation < 0 ? "^-1" : ""));
  // Cut curves appear twice, once each way; boundary pieces once.
  for (const auto& s : r.segments) {
    const auto& o = orientations[s.curve];
    if (s.boundary) {
      CHECK(o.size() == 1);
    } else {
      REQUIRE(o.size() == 2);
      CHECK(o[0] == -o[1]);
    }
  }
}

// A closed surface cut along 2g loops at one vertex, in canonical order.
void checkSchema(const TriMesh& input, const CutResult& r, int genus) {
  checkDisk(input, r);
  CHECK(r.genus == genus);
  CHECK(r.oneVertexSchema);
  REQUIRE(r.segments.size() == std::size_t(4 * genus));
  REQUIRE(r.curves.size() == std::size_t(2 * genus));
  for (const auto& s : r.segments) {
    CHECK_FALSE(s.boundary);
    CHECK(r.surfaceVertex[r.boundaryLoop[s.begin]] == r.baseVertex);
  }
  // The loops are simple and meet only at the base vertex.
  std::map<int, int> owner;
  for (std::size_t i = 0; i < r.curves.size(); ++i) {
    const auto& loop = r.curves[i];
    CHECK(loop.front() == r.baseVertex);
    CHECK(loop.back() == r.baseVertex);
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
      CHECK(loop[k] != r.baseVertex);
      CHECK(owner.emplace(loop[k], int(i)).second);
    }
  }
  std::string canonical;
  for (int k = 1; k <= genus; ++k) {
    const std::string a = "a" + std::to_string(k), b = "b" + std::to_string(k);
    canonical += (k > 1 ? " " : "") + a + " " + b + " " + a + "^-1 " + b + "^-1";
  }
  CHECK(r.canonical);
  CHECK(r.word == canonical);
}

}  // namespace

TEST_CASE("cut_to_disk: torus gives a b a^-1 b^-1", "[structure]") {
  const TriMesh mesh = test::torus(16, 8);
  const CutResult r = cutToDisk(mesh);
  checkSchema(mesh, r, 1);
}

TEST_CASE("cut_to_disk: double torus", "[structure]") {
  const TriMesh mesh = test::doubleTorus(2);
  const CutResult r = cutToDisk(mesh);
  checkSchema(mesh, r, 2);
}

TEST_CASE("cut_to_disk: genus-3 generated surface", "[structure]") {
  const TriMesh mesh = test::genusSurface(3, 2);
  checkSchema(mesh, cutToDisk(mesh), 3);
}

TEST_CASE("cut_to_disk: genus-1 knot1", "[structure]") {
  const TriMesh mesh = test::realMesh("knot1.off");
  checkSchema(mesh, cutToDisk(mesh), 1);
}

TEST_CASE("cut_to_disk: genus-2 eight", "[structure]") {
  const TriMesh mesh = test::realMesh("eight.off");
  checkSchema(mesh, cutToDisk(mesh), 2);
}

TEST_CASE("cut_to_disk: genus-3 elephant", "[structure]") {
  const TriMesh mesh = test::realMesh("elephant.off");
  checkSchema(mesh, cutToDisk(mesh), 3);
}

TEST_CASE("cut_to_disk: genus-4 generated surface", "[structure]") {
  const TriMesh mesh = test::genusSurface(4, 2);
  checkSchema(mesh, cutToDisk(mesh), 4);
}

TEST_CASE("cut_to_disk: a very coarse genus-3 mesh is cut without refinement", "[structure]") {
  // 3torus.off has 19 vertices for 12 loop ends out of one vertex: the loops cross faces, several
  // abreast where they share a face of the dual tree, so no refinement is needed.
  const TriMesh mesh = test::realMesh("3torus.off");
  CutOptions options;
  options.maxRefinements = 0;
  const CutResult r = cutToDisk(mesh, options);
  checkSchema(mesh, r, 3);
  CHECK(r.refinements == 0);
  CHECK(r.edgeSplits > 0);
  CHECK(r.notCanonicalBecause.empty());
  CHECK(std::count(r.inputVertex.begin(), r.inputVertex.end(), -1) > 0);
  // The points added lie on the input's faces: the surface cut is the input surface.
  CHECK(area(r.surface) == Approx(area(mesh)).epsilon(1e-12));
}

TEST_CASE("cut_to_disk: genus 9 on 2,100 vertices", "[structure]") {
  // couplingdown.off: routing 36 loop ends one by one, each splitting the edges it touched, grew
  // the mesh past 64 times its size; crossing faces, the loops take about genus times its size.
  const TriMesh mesh = test::realMesh("couplingdown.off");
  const CutResult r = cutToDisk(mesh);
  checkSchema(mesh, r, 9);
  CHECK(r.refinements == 0);
  CHECK(area(r.surface) == Approx(area(mesh)).epsilon(1e-12));
  CHECK(r.surface.n_vertices() < 2 * 9 * mesh.n_vertices());
}

TEST_CASE("cut_to_disk: genus 133 on 8,600 vertices keeps the one-vertex schema it built",
          "[structure][slow]") {
  // cheese.off: canonical form outgrows the size budget, the 532-gon is kept in the order built.
  const TriMesh mesh = test::realMesh("cheese.off");
  const CutResult r = cutToDisk(mesh);
  checkDisk(mesh, r);
  CHECK(r.genus == 133);
  CHECK(r.oneVertexSchema);
  CHECK_FALSE(r.canonical);
  CHECK(r.segments.size() == 4 * 133);
  CHECK(r.notCanonicalBecause.find("vertices on this mesh") != std::string::npos);
  CHECK(r.word.find("x1") != std::string::npos);
}

TEST_CASE("cut_to_disk: without canonical form the one-vertex schema still has 4g sides",
          "[structure]") {
  const TriMesh mesh = test::genusSurface(3, 2);
  CutOptions options;
  options.canonicalSchema = false;
  const CutResult r = cutToDisk(mesh, options);
  checkDisk(mesh, r);
  CHECK(r.oneVertexSchema);
  CHECK(r.segments.size() == 12);
  CHECK(r.word.find(r.canonical ? "a1" : "x1") == 0);
}

TEST_CASE("cut_to_disk: general cut graph on original edges", "[structure]") {
  const TriMesh mesh = test::doubleTorus(2);
  CutOptions options;
  options.oneVertexSchema = false;
  const CutResult r = cutToDisk(mesh, options);
  checkDisk(mesh, r);
  CHECK_FALSE(r.oneVertexSchema);
  CHECK_FALSE(r.canonical);
  CHECK(r.refinements == 0);
  CHECK(r.edgeSplits == 0);
  CHECK(r.surface.n_vertices() == mesh.n_vertices());
  for (int v : r.inputVertex) CHECK(v >= 0);
  // Cutting along a graph with 2g independent cycles: E_cut - V_cut = 2g - 1.
  std::set<int> cutVertices;
  for (int e : r.cutEdges) {
    const auto h = r.surface.halfedge_handle(TriMesh::EdgeHandle(e), 0);
    cutVertices.insert(r.surface.from_vertex_handle(h).idx());
    cutVertices.insert(r.surface.to_vertex_handle(h).idx());
  }
  CHECK(long(r.cutEdges.size()) - long(cutVertices.size()) == 3);
  CHECK(r.disk.n_vertices() == mesh.n_vertices() + r.boundaryLoop.size() - cutVertices.size());
}

TEST_CASE("cut_to_disk: sphere is slit open", "[structure]") {
  const TriMesh mesh = test::icosphere(1);
  const CutResult r = cutToDisk(mesh);
  checkDisk(mesh, r);
  CHECK(r.genus == 0);
  CHECK(r.cutEdges.size() == 2);
  CHECK(r.word == "c1 c1^-1");
  CHECK_FALSE(r.canonical);
}

TEST_CASE("cut_to_disk: surfaces with boundary", "[structure]") {
  SECTION("disk needs no cut") {
    const TriMesh mesh = test::gridDisk(4);
    const CutResult r = cutToDisk(mesh);
    checkDisk(mesh, r);
    CHECK(r.cutEdges.empty());
    CHECK(r.disk.n_vertices() == mesh.n_vertices());
    CHECK(r.word == "d1");
  }
  SECTION("cylinder") {
    const TriMesh mesh = test::cylinder(12, 4);
    const CutResult r = cutToDisk(mesh);
    checkDisk(mesh, r);
    CHECK(words(r.word).size() == 4);
    CHECK(r.curveNames.size() == 3);
  }
  SECTION("pair of pants") {
    const TriMesh mesh = test::pairOfPants(2);
    const CutResult r = cutToDisk(mesh);
    checkDisk(mesh, r);
    std::size_t boundaryPieces = 0;
    for (const auto& s : r.segments) boundaryPieces += s.boundary;
    // Each of the three boundaries appears, split where the cut meets it.
    CHECK(boundaryPieces >= 3);
  }
  SECTION("torus with a hole") {
    TriMesh mesh = test::torus(12, 6);
    mesh.delete_face(TriMesh::FaceHandle(7), false);
    mesh.garbage_collection();
    const CutResult r = cutToDisk(mesh);
    checkDisk(mesh, r);
    CHECK(r.genus == 1);
    CHECK_FALSE(r.oneVertexSchema);
  }
}

TEST_CASE("cut_to_disk: real meshes with boundary", "[structure]") {
  // holes.off (7 boundaries) and elephant-with-holes.off (genus 3, 106 boundaries) need cut paths
  // that keep off the other boundaries.
  for (const char* name :
       {"head.off", "mannequin-devil.off", "holes.off", "elephant-with-holes.off"}) {
    INFO(name);
    const TriMesh mesh = test::realMesh(name);
    checkDisk(mesh, cutToDisk(mesh));
  }
}

TEST_CASE("cut_to_disk: rejects several components", "[structure]") {
  structure::PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
  soup.faces = {{0, 1, 2}, {3, 4, 5}};
  CHECK_THROWS_AS(cutToDisk(structure::toTriMesh(soup)), structure::TopologyError);
}
