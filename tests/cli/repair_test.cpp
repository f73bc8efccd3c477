// `mspline repair --all` turns a scan with non-manifold edges, duplicates and bow-ties into a
// valid mesh that `fit` takes, and names what it cannot mend without writing anything.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "mspline/io/read_mesh.h"
#include "mspline/io/write_mesh.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

namespace fs = std::filesystem;
using mspline::structure::PolygonSoup;
using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;
using mspline::test::runJson;

namespace {

using Point = std::array<double, 3>;

std::int64_t addPoint(PolygonSoup& soup, const Point& p) {
  soup.positions.push_back(p);
  return static_cast<std::int64_t>(soup.positions.size() - 1);
}

std::vector<std::string> problemKinds(const nlohmann::json& report) {
  std::vector<std::string> kinds;
  for (const auto& problem : report["problems"]) kinds.push_back(problem["kind"]);
  return kinds;
}

}  // namespace

TEST_CASE("repair: --all mends non-manifold edges of a scan and fit runs on the result", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("repair_all");
  PolygonSoup knot = mspline::io::readMesh(realMeshPath("knot1.off")).soup;
  const std::size_t vertices = knot.positions.size(), faces = knot.faces.size();
  PolygonSoup scan = knot;
  // Fins standing out of the surface on the first edge of 2 faces: each edge is shared by 3 faces.
  for (std::size_t f : {0, 100}) {
    const auto a = scan.faces[f][0], b = scan.faces[f][1], c = scan.faces[f][2];
    const Point& pa = scan.positions[a];
    const Point& pb = scan.positions[b];
    const Point& pc = scan.positions[c];
    Point u, v, wing;
    for (int i = 0; i < 3; ++i) u[i] = pb[i] - pa[i], v[i] = pc[i] - pa[i];
    const Point normal{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
    const double length =
        std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    for (int i = 0; i < 3; ++i) wing[i] = (pa[i] + pb[i]) / 2 + normal[i] / std::sqrt(length);
    scan.faces.push_back({a, b, addPoint(scan, wing)});
  }
  scan.faces.push_back({knot.faces[7][1], knot.faces[7][2], knot.faces[7][0]});  // a duplicate
  // A bow-tie wing at vertex 5 and a stray vertex.
  const Point& p5 = scan.positions[5];
  scan.faces.push_back({5, addPoint(scan, {p5[0] + 1, p5[1], p5[2] + 3}),
                        addPoint(scan, {p5[0], p5[1] + 1, p5[2] + 3})});
  addPoint(scan, {50, 50, 50});
  const std::string input = dir + "/scan.off";
  mspline::io::writeMesh(input, scan);

  const auto before = runJson("info " + input, 2);
  CHECK(problemKinds(before) == std::vector<std::string>{"non_manifold_edge", "non_manifold_vertex",
                                                         "duplicate_face", "unreferenced_vertex"});
  CHECK(before["genus"].is_null());

  // Without the edge split nothing can be written: the edges stay shared by 3 faces.
  const std::string output = dir + "/repaired.off";
  const auto partial =
      runCommand(cliPath() + " repair " + input + " --remove-duplicate-faces -o " + output);
  CHECK(partial.exitCode == 2);
  CHECK(partial.err.find("2 non-manifold edges") != std::string::npos);
  CHECK_FALSE(fs::exists(output));

  const auto repaired = runJson("repair --all " + input + " -o " + output);
  CHECK(repaired["repairs"][3]["repair"] == "split_non_manifold_edges");
  CHECK(repaired["repairs"][3]["count"] == 2);
  // The knot comes back whole: every one of its vertices and faces, its genus, no boundary.
  const auto after = runJson("info " + output);
  CHECK(after["valid"] == true);
  CHECK(after["vertices"] == vertices);
  CHECK(after["faces"] == faces);
  CHECK(after["genus"] == 1);
  CHECK(after["boundaries"] == 0);

  const auto fit = runJson("fit " + output + " --kind subd --control 300 --max-control 500 " +
                           "--rounds 1 --max-refinements 0 -q -o " + dir + "/model.msp");
  CHECK(fit["rms_error"].get<double>() < 0.05);
}

TEST_CASE("repair: what --all cannot mend is named, and nothing is written", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("repair_unmendable");
  const PolygonSoup strip = mspline::test::moebiusSoup();
  const std::string input = dir + "/moebius.off", output = dir + "/out.off";
  mspline::io::writeMesh(input, strip);

  const auto text = runCommand(cliPath() + " repair --all " + input + " -o " + output);
  CHECK(text.exitCode == 2);
  const std::string error = text.err.substr(text.err.find("error:"));
  CHECK(error.find("moebius.off") != std::string::npos);
  CHECK(error.find("non-orientable") != std::string::npos);
  CHECK(error.find("nothing written") != std::string::npos);
  CHECK_FALSE(fs::exists(output));

  const auto json = runJson("repair --all " + input + " -o " + output, 2);
  CHECK(json["error"]["kind"] == "input");
  CHECK(problemKinds(json) == std::vector<std::string>{"inconsistent_orientation"});
  CHECK(json["problems"][0]["count"].get<int>() > 0);
  CHECK(json["repairs"].size() == 8);
  CHECK_FALSE(fs::exists(output));
}
