#include <catch2/catch.hpp>

#include "support/test_meshes.h"

#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>

#include "mspline/io/read_mesh.h"
#include "mspline/structure/mesh/validate.h"
#include "support/test_data.h"

using mspline::structure::isDegenerateFace;
using mspline::structure::MeshProblem;
using mspline::structure::PolygonSoup;
using mspline::structure::validate;
using mspline::structure::ValidationOptions;
using mspline::structure::ValidationReport;

namespace test = mspline::test;

namespace {

using Elements = std::vector<std::int64_t>;

// Triangulated Moebius strip with n quads: vertex i (top) and n + i (bottom).
PolygonSoup moebius(int n) {
  PolygonSoup s;
  s.sourceName = "moebius";
  const double pi = std::acos(-1.0);
  for (double w : {0.3, -0.3})
    for (int i = 0; i < n; ++i) {
      const double u = 2 * pi * i / n;
      const double r = 1 + w * std::cos(u / 2);
      s.positions.push_back({r * std::cos(u), r * std::sin(u), w * std::sin(u / 2)});
    }
  for (int i = 0; i < n; ++i) {
    const std::int64_t t = i, b = n + i;
    // The last quad closes the strip with a half twist: top meets bottom.
    const std::int64_t t1 = i + 1 < n ? i + 1 : n, b1 = i + 1 < n ? n + i + 1 : 0;
    s.faces.push_back({t, b, b1});
    s.faces.push_back({t, b1, t1});
  }
  return s;
}

std::vector<std::string> kinds(const ValidationReport& report) {
  std::vector<std::string> out;
  for (const auto& p : report.problems) out.push_back(p.kind);
  return out;
}

MeshProblem only(const ValidationReport& report, const std::string& kind) {
  INFO(report.summary());
  REQUIRE(kinds(report) == std::vector<std::string>{kind});
  return report.problems.front();
}

}  // namespace

TEST_CASE("validate: clean closed and open meshes have no problems", "[structure]") {
  const auto tet = validate(test::tetrahedronSoup());
  CHECK(tet.ok());
  CHECK(tet.vertices == 4);
  CHECK(tet.faces == 4);
  CHECK(tet.edges == 6);
  CHECK(tet.components == 1);
  CHECK(tet.orientable);
  CHECK(tet.summary() == "no problems");

  const auto oct = validate(test::octahedronSoup());
  CHECK(oct.ok());
  CHECK(oct.edges == 12);

  for (bool quads : {false, true}) {
    const int n = 7;
    const auto report = validate(test::gridSoup(n, quads));
    INFO(report.summary());
    CHECK(report.ok());
    // Triangles add one diagonal per quad.
    CHECK(report.edges == std::size_t(2 * n * (n + 1) + (quads ? 0 : n * n)));
    CHECK(report.components == 1);
  }
}

TEST_CASE("validate: empty soups", "[structure]") {
  PolygonSoup none;
  none.sourceName = "empty.off";
  const auto& p = only(validate(none), "empty_mesh");
  CHECK(p.message == "empty.off: the mesh is empty (0 faces, 0 vertices)");

  PolygonSoup pointsOnly = test::tetrahedronSoup();
  pointsOnly.faces.clear();
  CHECK(only(validate(pointsOnly), "empty_mesh").message ==
        "tet.off: the mesh is empty (0 faces, 4 vertices)");
}

TEST_CASE("validate: out-of-range indices are reported and excluded from other checks",
          "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.faces.push_back({0, 1, 7});
  s.faces.push_back({-1, 2, 3});
  const auto report = validate(s);
  const auto& p = only(report, "face_index_out_of_range");
  CHECK(p.count == 2);
  CHECK(p.elements == Elements{4, 5});
  CHECK(p.message ==
        "tet.off: 2 faces with vertex indices out of range (valid indices are 0 to 3; face 4 "
        "uses 7), first at faces 4, 5");
  CHECK(report.edges == 6);
}

TEST_CASE("validate: faces with fewer than 3 vertices", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.faces.push_back({0, 1});
  s.faces.push_back({});
  const auto& p = only(validate(s), "too_few_face_vertices");
  CHECK(p.count == 2);
  CHECK(p.elements == Elements{4, 5});
}

TEST_CASE("validate: non-finite coordinates", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.positions[3][1] = std::numeric_limits<double>::quiet_NaN();
  s.positions[1][0] = std::numeric_limits<double>::infinity();
  const auto& p = only(validate(s), "non_finite_coordinate");
  CHECK(p.count == 2);
  CHECK(p.elements == Elements{1, 3});
  CHECK(p.message.find("tet.off: 2 vertices with a non-finite coordinate") == 0);
}

TEST_CASE("validate: an edge shared by three faces is a non-manifold edge, not a vertex",
          "[structure]") {
  PolygonSoup s;
  s.sourceName = "fin.off";
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  s.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const auto report = validate(s);
  const auto& p = only(report, "non_manifold_edge");
  CHECK(p.count == 1);
  CHECK(p.elements == Elements{0, 1, 2});
  CHECK(p.message ==
        "fin.off: 1 non-manifold edge (edges shared by 3 or more faces; the first joins vertices 0 "
        "and 1), first at faces 0, 1, 2");
  CHECK(report.edges == 7);
}

TEST_CASE("validate: a bow-tie is a non-manifold vertex", "[structure]") {
  PolygonSoup s;
  s.sourceName = "bowtie.off";
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  s.faces = {{0, 1, 2}, {0, 3, 4}};
  const auto report = validate(s);
  const auto& p = only(report, "non_manifold_vertex");
  CHECK(p.count == 1);
  CHECK(p.elements == Elements{0});
  CHECK(p.message ==
        "bowtie.off: 1 non-manifold vertex (faces around the vertex form 2 or more fans that meet "
        "only at it), at vertex 0");
  CHECK(report.components == 1);

  // Two closed surfaces touching at one vertex: each side is a full fan, still two fans.
  PolygonSoup touching = test::tetrahedronSoup();
  PolygonSoup other = test::tetrahedronSoup();
  for (auto& p3 : other.positions) p3 = {-p3[0], -p3[1], -p3[2]};
  for (auto& face : other.faces) std::swap(face[1], face[2]);
  test::appendSoup(touching, other);
  for (auto& face : touching.faces)
    for (auto& v : face)
      if (v == 4) v = 0;
  const auto report2 = validate(touching);
  INFO(report2.summary());
  REQUIRE(kinds(report2) == std::vector<std::string>{"non_manifold_vertex", "unreferenced_vertex"});
  CHECK(report2.problems[0].elements == Elements{0});
  CHECK(report2.problems[1].elements == Elements{4});
}

TEST_CASE("validate: degenerate faces by repeated index or zero area", "[structure]") {
  PolygonSoup s;
  s.sourceName = "flat.off";
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {2, 0, 0}};
  s.faces = {{0, 1, 2}, {1, 0, 3}, {0, 2, 0}};
  const auto& p = only(validate(s), "degenerate_face");
  CHECK(p.count == 2);
  CHECK(p.elements == Elements{1, 2});

  // A thin but honest sliver is not degenerate; the tolerance decides.
  PolygonSoup sliver;
  sliver.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1e-5, 0}};
  sliver.faces = {{0, 1, 2}};
  CHECK(validate(sliver).ok());
  ValidationOptions strict;
  strict.degenerateTolerance = 1e-4;
  CHECK(only(validate(sliver, strict), "degenerate_face").elements == Elements{0});

  // Polygons use the Newell normal: a collinear quad is degenerate, a bent one is not.
  PolygonSoup quads;
  quads.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {1, 1, 1}};
  quads.faces = {{0, 1, 2, 3}, {0, 1, 4, 2}};
  CHECK(isDegenerateFace(quads, 0, 1e-12));
  CHECK_FALSE(isDegenerateFace(quads, 1, 1e-12));
  // Far from the origin the cross product of edge vectors still sees the area.
  PolygonSoup far;
  far.positions = {{1e8, 1e8, 1e8}, {1e8 + 1, 1e8, 1e8}, {1e8, 1e8 + 1, 1e8}};
  far.faces = {{0, 1, 2}};
  CHECK_FALSE(isDegenerateFace(far, 0, 1e-12));
}

TEST_CASE("validate: duplicate faces in any order and orientation", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.faces.push_back({2, 1, 0});
  s.faces.push_back({3, 1, 0});
  const auto report = validate(s);
  const auto& p = only(report, "duplicate_face");
  CHECK(p.count == 2);
  CHECK(p.elements == Elements{4, 5});
  CHECK(p.message ==
        "tet.off: 2 duplicate faces (same vertices as an earlier face; face 4 repeats face 0), "
        "first at faces 4, 5");
  // Duplicates are left out of the edge checks, so no edge looks non-manifold.
  CHECK(report.edges == 6);
}

TEST_CASE("validate: inconsistent orientation that flipping fixes", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.faces[3] = {1, 3, 2};
  const auto report = validate(s);
  const auto& p = only(report, "inconsistent_orientation");
  CHECK(p.count == 3);
  CHECK(p.elements == Elements{0, 1, 2, 3});
  CHECK(report.orientable);
  CHECK(p.message.find("fixable by flipping") != std::string::npos);
}

TEST_CASE("validate: a Moebius strip is non-orientable", "[structure]") {
  const auto report = validate(moebius(8));
  const auto& p = only(report, "inconsistent_orientation");
  CHECK_FALSE(report.orientable);
  CHECK(p.count >= 1);
  CHECK(p.message.find("moebius: the surface is non-orientable (cannot be fixed by flipping") == 0);
  CHECK(report.edges == 8 * 3 + 8);
}

TEST_CASE("validate: unreferenced vertices and the listing limit", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  for (int i = 0; i < 15; ++i) s.positions.push_back({5.0 + i, 0, 0});
  const auto& p = only(validate(s), "unreferenced_vertex");
  CHECK(p.count == 15);
  CHECK(p.elements == Elements{4, 5, 6, 7, 8, 9, 10, 11, 12, 13});
  CHECK(p.message ==
        "tet.off: 15 unreferenced vertices (used by no valid face), first at vertices 4, 5, 6, 7, "
        "8, 9, 10, 11, 12, 13, ...");
  ValidationOptions two;
  two.maxListed = 2;
  CHECK(validate(s, two).problems.front().elements == Elements{4, 5});
}

TEST_CASE("validate: multiple components are counted with their sizes", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  test::appendSoup(s, test::octahedronSoup(5.0));
  PolygonSoup triangle;
  triangle.positions = {{9, 0, 0}, {10, 0, 0}, {9, 1, 0}};
  triangle.faces = {{0, 1, 2}};
  test::appendSoup(s, triangle);
  const auto report = validate(s);
  const auto& p = only(report, "multiple_components");
  CHECK(report.components == 3);
  CHECK(p.count == 3);
  CHECK(p.elements == Elements{4, 0, 12});
  CHECK(p.message ==
        "tet.off: 3 components (faces connected through shared vertices) with 8, 4, 1 faces, "
        "largest first, starting at faces 4, 0, 12");
}

TEST_CASE("validate: every problem is reported and summarised in a fixed order", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.faces[3] = {1, 3, 2};            // inconsistent orientation
  s.faces.push_back({0, 1});         // too few vertices
  s.positions.push_back({7, 7, 7});  // unreferenced
  const auto report = validate(s);
  REQUIRE(kinds(report) == std::vector<std::string>{"too_few_face_vertices",
                                                    "inconsistent_orientation",
                                                    "unreferenced_vertex"});
  CHECK(report.summary() ==
        report.problems[0].message + "; also: inconsistent_orientation, unreferenced_vertex");
}

TEST_CASE("validate: connectivity exposes fans, patches and flips", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.faces[1] = {0, 3, 1};
  const auto c = mspline::structure::analyzeConnectivity(s);
  CHECK(c.faceFlip == std::vector<std::uint8_t>{0, 1, 0, 0});
  CHECK(c.facePatch == std::vector<std::uint32_t>{0, 0, 0, 0});
  CHECK(c.fanCount == std::vector<std::uint32_t>{1, 1, 1, 1});
  // Every corner of vertex 0 is in one fan, whose id is its first corner (corner 0).
  CHECK(c.cornerFan[0] == 0);
  CHECK(c.cornerFan[3] == 0);
  CHECK(c.cornerFan[6] == 0);
}

TEST_CASE("validate: real meshes", "[structure]") {
  using mspline::io::readMesh;
  using mspline::test::realMeshPath;
  for (const char* name : {"knot1.off", "eight.off", "elephant.off", "mannequin-devil.off"}) {
    const auto report = validate(readMesh(realMeshPath(name)).soup);
    INFO(name << ": " << report.summary());
    CHECK(report.ok());
    CHECK(report.components == 1);
    // Euler characteristic V - E + F: genus 1, genus 2, genus 3, a disk.
    const auto euler = static_cast<long>(report.vertices) - static_cast<long>(report.edges) +
                       static_cast<long>(report.faces);
    CHECK(euler ==
          std::map<std::string, long>{
              {"knot1.off", 0}, {"eight.off", -2}, {"elephant.off", -4}, {"mannequin-devil.off", 1}}
              .at(name));
  }

  const auto degenerate = validate(readMesh(realMeshPath("degtri_sliding.off")).soup);
  CHECK(only(degenerate, "degenerate_face").elements == Elements{2, 3, 4, 5});

  const auto shuffled = validate(readMesh(realMeshPath("blobby-shuffled.off")).soup);
  CHECK(only(shuffled, "inconsistent_orientation").message.find("fixable by flipping") !=
        std::string::npos);
  CHECK(shuffled.orientable);

  const auto unreferenced = validate(readMesh(realMeshPath("prim.off")).soup);
  CHECK(only(unreferenced, "unreferenced_vertex").elements == Elements{8, 9, 10});
}

TEST_CASE("validate: a million-triangle grid [slow]", "[structure][slow]") {
  const int n = 708;  // 2 * 708^2 = 1,002,528 triangles, 502,681 vertices
  const PolygonSoup s = test::gridSoup(n);
  const auto start = std::chrono::steady_clock::now();
  const auto report = validate(s);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "validate: " << s.faces.size() << " triangles, " << s.positions.size()
            << " vertices in " << seconds << " s\n";
  CHECK(report.ok());
  CHECK(report.edges == std::size_t(3) * n * n + 2 * n);
}
