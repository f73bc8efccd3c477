#include <catch2/catch.hpp>

#include "mspline/io/load_mesh.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::analyzeTopology;
using structure::TriMesh;

namespace {}  // namespace

TEST_CASE("topology: generated meshes", "[structure]") {
  SECTION("disk") {
    const auto t = analyzeTopology(test::gridDisk(4));
    CHECK(t.vertices == 25);
    CHECK(t.faces == 32);
    CHECK(t.edges == 56);
    CHECK(t.components == 1);
    CHECK(t.boundaryLoops == 1);
    CHECK(t.euler == 1);
    CHECK(t.genus == 0);
    CHECK_FALSE(t.closed);
  }
  SECTION("cylinder") {
    const auto t = analyzeTopology(test::cylinder(12, 4));
    CHECK(t.boundaryLoops == 2);
    CHECK(t.euler == 0);
    CHECK(t.genus == 0);
  }
  SECTION("sphere") {
    const auto t = analyzeTopology(test::icosphere(2));
    CHECK(t.faces == 320);
    CHECK(t.euler == 2);
    CHECK(t.genus == 0);
    CHECK(t.closed);
  }
  SECTION("torus") {
    const auto t = analyzeTopology(test::torus(16, 8));
    CHECK(t.euler == 0);
    CHECK(t.genus == 1);
    CHECK(t.closed);
  }
  SECTION("double torus and genus 3") {
    CHECK(analyzeTopology(test::doubleTorus(2)).genus == 2);
    const auto t = analyzeTopology(test::genusSurface(3, 2));
    CHECK(t.euler == -4);
    CHECK(t.genus == 3);
  }
  SECTION("pair of pants") {
    const auto t = analyzeTopology(test::pairOfPants(2));
    CHECK(t.boundaryLoops == 3);
    CHECK(t.euler == -1);
    CHECK(t.genus == 0);
  }
}

TEST_CASE("topology: several components and isolated vertices", "[structure]") {
  structure::PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}, {9, 9, 9}};
  soup.faces = {{0, 1, 2}, {3, 4, 5}};
  const auto t = analyzeTopology(structure::toTriMesh(soup));
  CHECK(t.components == 3);
  CHECK(t.boundaryLoops == 2);
  CHECK(t.euler == 3);
  // Two triangles (genus 0 each, one boundary each) and a point (a sphere without its surface
  // counts as a component of euler 1): (2 * 3 - 3 - 2) / 2 = 0 in integer arithmetic.
  CHECK(t.genus == 0);
}

TEST_CASE("topology: real meshes", "[structure]") {
  struct Expected {
    const char* name;
    long genus;
    std::size_t boundaries;
  };
  const Expected cases[] = {{"knot1.off", 1, 0},
                            {"eight.off", 2, 0},
                            {"elephant.off", 3, 0},
                            {"head.off", 0, 3},
                            {"mannequin-devil.off", 0, 1}};
  for (const auto& expected : cases) {
    INFO(expected.name);
    const auto t = analyzeTopology(test::realMesh(expected.name));
    CHECK(t.components == 1);
    CHECK(t.genus == expected.genus);
    CHECK(t.boundaryLoops == expected.boundaries);
    CHECK(t.euler == 2 - 2 * expected.genus - static_cast<long>(expected.boundaries));
  }
}
