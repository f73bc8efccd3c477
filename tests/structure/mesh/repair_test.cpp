#include <catch2/catch.hpp>

#include "support/test_meshes.h"

#include <algorithm>
#include <cmath>

#include "mspline/io/read_mesh.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/repair.h"
#include "mspline/structure/mesh/validate.h"
#include "support/test_data.h"

using mspline::structure::InputError;
using mspline::structure::PolygonSoup;
using mspline::structure::repair;
using mspline::structure::RepairOptions;
using mspline::structure::RepairResult;
using mspline::structure::validate;
using mspline::structure::ValidationReport;

namespace test = mspline::test;

namespace {

using Face = std::vector<std::int64_t>;

bool hasKind(const ValidationReport& report, const std::string& kind) {
  return std::any_of(report.problems.begin(), report.problems.end(),
                     [&](const auto& p) { return p.kind == kind; });
}

// Every corner's UV is its vertex's (x, y): checks that UVs travel with their corners.
void setUVsFromPositions(PolygonSoup& soup) {
  soup.cornerUVs.clear();
  for (const auto& face : soup.faces) {
    std::vector<std::array<double, 2>> uvs;
    for (auto v : face) uvs.push_back({soup.positions[v][0], soup.positions[v][1]});
    soup.cornerUVs.push_back(uvs);
  }
}

bool uvsMatchPositions(const PolygonSoup& soup) {
  if (soup.cornerUVs.size() != soup.faces.size()) return false;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (soup.cornerUVs[f].size() != soup.faces[f].size()) return false;
    for (std::size_t i = 0; i < soup.faces[f].size(); ++i) {
      const auto& p = soup.positions[soup.faces[f][i]];
      if (soup.cornerUVs[f][i] != std::array<double, 2>{p[0], p[1]}) return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("repair: every requested repair is reported, in order, also when idle", "[structure]") {
  RepairOptions all;
  all.mergeDuplicateVertices = all.removeDegenerateFaces = all.removeDuplicateFaces = true;
  all.splitNonManifoldEdges = all.splitNonManifoldVertices = all.orientConsistently = true;
  all.keepLargestComponent = all.dropUnreferencedVertices = true;
  const RepairResult result = repair(test::tetrahedronSoup(), all);
  std::vector<std::string> names;
  for (const auto& action : result.actions) {
    names.push_back(action.repair);
    CHECK(action.count == 0);
    CHECK(action.message.rfind("tet.off: ", 0) == 0);
  }
  CHECK(names == std::vector<std::string>{"merge_duplicate_vertices", "remove_degenerate_faces",
                                          "remove_duplicate_faces", "split_non_manifold_edges",
                                          "split_non_manifold_vertices", "orient_consistently",
                                          "keep_largest_component", "drop_unreferenced_vertices"});
  CHECK(result.soup.faces == test::tetrahedronSoup().faces);
  CHECK(result.soup.positions == test::tetrahedronSoup().positions);

  CHECK(repair(test::tetrahedronSoup(), RepairOptions{}).actions.empty());
}

TEST_CASE("repair: merging bit-identical vertices joins an STL-style soup", "[structure]") {
  PolygonSoup s;
  s.sourceName = "pair.stl";
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {-0.0, 0, 0}};
  s.faces = {{0, 1, 2}, {3, 4, 5}, {6, 2, 1}};
  CHECK(hasKind(validate(s), "multiple_components"));
  RepairOptions options;
  options.mergeDuplicateVertices = true;
  const auto result = repair(s, options);
  REQUIRE(result.actions.size() == 1);
  CHECK(result.actions[0].count == 2);
  CHECK(result.actions[0].message ==
        "pair.stl: merged 2 vertices into 2 vertices with bit-identical coordinates");
  // -0.0 differs from 0.0 in its bits, so vertex 6 stays (renumbered to 4).
  CHECK(result.soup.positions.size() == 5);
  CHECK(result.soup.faces == std::vector<Face>{{0, 1, 2}, {2, 1, 3}, {4, 2, 1}});
  CHECK_FALSE(hasKind(validate(result.soup), "multiple_components"));
}

TEST_CASE("repair: removing degenerate faces", "[structure]") {
  PolygonSoup s;
  s.sourceName = "flat.off";
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {2, 0, 0}};
  s.faces = {{0, 1, 2}, {1, 0, 3}, {0, 2, 0}, {1, 2}};
  setUVsFromPositions(s);
  RepairOptions options;
  options.removeDegenerateFaces = true;
  const auto result = repair(s, options);
  CHECK(result.actions[0].count == 3);
  CHECK(result.soup.faces == std::vector<Face>{{0, 1, 2}});
  CHECK(uvsMatchPositions(result.soup));
  CHECK_FALSE(hasKind(validate(result.soup), "degenerate_face"));
}

TEST_CASE("repair: removing duplicate faces keeps the first", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.faces.insert(s.faces.begin() + 1, {1, 2, 0});
  s.faces.push_back({3, 2, 1});
  RepairOptions options;
  options.removeDuplicateFaces = true;
  const auto result = repair(s, options);
  CHECK(result.actions[0].count == 2);
  CHECK(result.soup.faces == test::tetrahedronSoup().faces);
  CHECK(validate(result.soup).ok());
}

TEST_CASE("repair: splitting a bow-tie gives one vertex per fan", "[structure]") {
  PolygonSoup s;
  s.sourceName = "bowtie.off";
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}, {0, -1, 0}, {1, -2, 0}};
  // Three fans at vertex 0.
  s.faces = {{0, 1, 2}, {0, 3, 4}, {5, 6, 0}};
  REQUIRE(validate(s).problems.front().kind == "non_manifold_vertex");
  RepairOptions options;
  options.splitNonManifoldVertices = true;
  const auto result = repair(s, options);
  CHECK(result.actions[0].count == 1);
  CHECK(result.actions[0].message ==
        "bowtie.off: split 1 non-manifold vertex, adding 2 vertices (one per extra fan)");
  REQUIRE(result.soup.positions.size() == 9);
  CHECK(result.soup.faces == std::vector<Face>{{0, 1, 2}, {7, 3, 4}, {5, 6, 8}});
  CHECK(result.soup.positions[7] == s.positions[0]);
  CHECK(result.soup.positions[8] == s.positions[0]);
  const auto after = validate(result.soup);
  CHECK_FALSE(hasKind(after, "non_manifold_vertex"));
  CHECK(after.components == 3);
}

TEST_CASE("repair: orienting flips faces to agree with the first face", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  std::reverse(s.faces[1].begin(), s.faces[1].end());
  std::reverse(s.faces[3].begin(), s.faces[3].end());
  setUVsFromPositions(s);
  REQUIRE(hasKind(validate(s), "inconsistent_orientation"));
  RepairOptions options;
  options.orientConsistently = true;
  const auto result = repair(s, options);
  CHECK(result.actions[0].count == 2);
  CHECK(validate(result.soup).ok());
  CHECK(result.soup.faces[0] == s.faces[0]);
  CHECK(uvsMatchPositions(result.soup));

  // When the first face is the odd one out, the others are flipped to agree with it.
  PolygonSoup inverted = test::tetrahedronSoup();
  std::reverse(inverted.faces[0].begin(), inverted.faces[0].end());
  const auto result2 = repair(inverted, options);
  CHECK(result2.actions[0].count == 3);
  CHECK(result2.soup.faces[0] == inverted.faces[0]);
  CHECK(validate(result2.soup).ok());
}

TEST_CASE("repair: a Moebius strip is left as it is and the action says why", "[structure]") {
  const PolygonSoup s = test::moebiusSoup();
  RepairOptions options;
  options.orientConsistently = true;
  const auto result = repair(s, options);
  CHECK(result.actions[0].count == 0);
  CHECK(result.actions[0].message.find("left 1 non-orientable patch as it is") !=
        std::string::npos);
  CHECK(result.soup.faces == s.faces);
}

TEST_CASE("repair: keeping the largest component and dropping unreferenced vertices",
          "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  test::appendSoup(s, test::octahedronSoup(5.0));
  RepairOptions options;
  options.keepLargestComponent = true;
  const auto kept = repair(s, options);
  CHECK(kept.actions[0].count == 4);
  CHECK(kept.actions[0].message ==
        "tet.off: kept the largest of 2 components (8 faces), removing 4 faces");
  const auto afterKeep = validate(kept.soup);
  CHECK(afterKeep.components == 1);
  CHECK(afterKeep.problems.front().kind == "unreferenced_vertex");
  CHECK(afterKeep.problems.front().count == 4);

  options.dropUnreferencedVertices = true;
  const auto clean = repair(s, options);
  CHECK(clean.actions[1].count == 4);
  CHECK(clean.soup.positions == test::octahedronSoup(5.0).positions);
  CHECK(clean.soup.faces == test::octahedronSoup(5.0).faces);
  CHECK(validate(clean.soup).ok());
}

TEST_CASE("repair: dropping unreferenced vertices renumbers faces", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.positions.insert(s.positions.begin(), {9, 9, 9});
  for (auto& face : s.faces)
    for (auto& v : face) ++v;
  s.positions.push_back({8, 8, 8});
  RepairOptions options;
  options.dropUnreferencedVertices = true;
  const auto result = repair(s, options);
  CHECK(result.actions[0].count == 2);
  CHECK(result.soup.positions == test::tetrahedronSoup().positions);
  CHECK(result.soup.faces == test::tetrahedronSoup().faces);
}

TEST_CASE("repair: all repairs together turn a defective soup into a clean mesh", "[structure]") {
  // An octahedron stored STL-style (three own vertices per face), with defects added.
  const PolygonSoup oct = test::octahedronSoup();
  PolygonSoup s;
  s.sourceName = "scan.stl";
  for (const auto& face : oct.faces) {
    Face own;
    for (auto v : face) {
      own.push_back(static_cast<std::int64_t>(s.positions.size()));
      s.positions.push_back(oct.positions[v]);
    }
    s.faces.push_back(own);
  }
  std::reverse(s.faces[2].begin(), s.faces[2].end());  // inconsistent orientation
  std::reverse(s.faces[5].begin(), s.faces[5].end());
  s.faces.push_back({s.faces[0][1], s.faces[0][2], s.faces[0][0]});  // duplicate
  s.faces.push_back({s.faces[1][0], s.faces[1][0], s.faces[1][2]});  // degenerate
  // A bow-tie wing at the octahedron's vertex (1, 0, 0), and a stray vertex.
  s.positions.push_back({2, 0, 0});
  s.positions.push_back({2, 1, 0});
  s.faces.push_back({s.faces[0][0], 24, 25});
  s.positions.push_back({3, 3, 3});
  setUVsFromPositions(s);

  const auto before = validate(s);
  CHECK(before.problems.size() >= 4);

  RepairOptions all;
  all.mergeDuplicateVertices = all.removeDegenerateFaces = all.removeDuplicateFaces = true;
  all.splitNonManifoldEdges = all.splitNonManifoldVertices = all.orientConsistently = true;
  all.keepLargestComponent = all.dropUnreferencedVertices = true;
  const auto result = repair(s, all);
  std::vector<std::size_t> counts;
  for (const auto& action : result.actions) counts.push_back(action.count);
  // 24 corner copies collapse to 6 vertices; 1 degenerate and 1 duplicate face; no edge is
  // shared by 3 faces; the wing's vertex is split off; faces 2 and 5 are flipped back; the wing
  // is removed; 3 vertices (the wing's two and its split copy) and the stray vertex are dropped.
  CHECK(counts == std::vector<std::size_t>{18, 1, 1, 0, 1, 2, 1, 4});
  const auto after = validate(result.soup);
  INFO(after.summary());
  CHECK(after.ok());
  CHECK(result.soup.positions.size() == 6);
  CHECK(result.soup.faces.size() == 8);
  CHECK(uvsMatchPositions(result.soup));
}

TEST_CASE("repair: out-of-range indices cannot be repaired", "[structure]") {
  PolygonSoup s = test::tetrahedronSoup();
  s.faces.push_back({0, 1, 4});
  RepairOptions options;
  options.removeDegenerateFaces = true;
  CHECK_THROWS_AS(repair(s, options), InputError);
  CHECK_THROWS_WITH(repair(s, options),
                    "tet.off: face 4 uses vertex 4 but there are 4 vertices; repair cannot fix "
                    "out-of-range indices");
}

TEST_CASE("repair: real meshes with flipped faces and touching parts", "[structure]") {
  using mspline::io::readMesh;
  using mspline::test::realMeshPath;
  RepairOptions orient;
  orient.orientConsistently = true;
  const auto blobby = repair(readMesh(realMeshPath("blobby-shuffled.off")).soup, orient);
  CHECK(blobby.actions[0].count > 0);
  CHECK(validate(blobby.soup).ok());

  // The STL pig's parts touch at single vertices; splitting them leaves separate closed parts.
  const auto pig = readMesh(realMeshPath("pig.stl")).soup;
  REQUIRE(hasKind(validate(pig), "non_manifold_vertex"));
  RepairOptions split;
  split.splitNonManifoldVertices = true;
  const auto fixed = repair(pig, split);
  const auto after = validate(fixed.soup);
  CHECK_FALSE(hasKind(after, "non_manifold_vertex"));
  CHECK(fixed.soup.positions.size() > pig.positions.size());
  CHECK(after.components > 1);
}
