// `mspline info` on real meshes reports the topology the acceptance criteria name.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "mspline/io/read_mesh.h"
#include "mspline/io/write_mesh.h"
#include "support/test_data.h"

using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;

namespace {

nlohmann::json infoJson(const std::string& meshName) {
  auto result = runCommand(cliPath() + " info --json " + realMeshPath(meshName));
  INFO(meshName << " stderr: " << result.err);
  REQUIRE(result.exitCode == 0);
  return nlohmann::json::parse(result.out);
}

}  // namespace

TEST_CASE("info: genus and boundaries of real meshes", "[cli]") {
  struct Expected {
    const char* mesh;
    int genus;
    int boundaries;
  };
  for (Expected expected :
       {Expected{"knot1.off", 1, 0}, Expected{"eight.off", 2, 0}, Expected{"elephant.off", 3, 0},
        Expected{"head.off", 0, 3}, Expected{"mannequin-devil.off", 0, 1}}) {
    INFO(expected.mesh);
    auto info = infoJson(expected.mesh);
    CHECK(info["genus"] == expected.genus);
    CHECK(info["boundaries"] == expected.boundaries);
    CHECK(info["components"] == 1);
    CHECK(info["closed"] == (expected.boundaries == 0));
    CHECK(info["valid"] == true);
    CHECK(info["problems"].empty());
    // Euler's formula ties the reported numbers together.
    long v = info["vertices"], e = info["edges"], f = info["faces"];
    CHECK(info["euler"] == v - e + f);
    CHECK(info["euler"] == 2 - 2 * expected.genus - expected.boundaries);
  }
}

TEST_CASE("info: text output names the file and the genus", "[cli]") {
  auto result = runCommand(cliPath() + " info " + realMeshPath("eight.off"));
  REQUIRE(result.exitCode == 0);
  CHECK(result.out.find("eight.off") != std::string::npos);
  CHECK(result.out.find("genus                 2") != std::string::npos);
}

TEST_CASE("info: json has the documented keys", "[cli]") {
  auto info = infoJson("bunny00.off");
  for (const char* key :
       {"vertices", "edges", "faces", "components", "boundaries", "euler", "genus", "closed",
        "orientable", "bbox_diagonal", "min_angle_degrees", "median_angle_degrees",
        "max_dihedral_degrees", "folded_edges", "problems"})
    CHECK(info.contains(key));
  CHECK(info["vertices"] == 37706);
  CHECK(info["faces"] == 75408);
  // A scan: no neighbouring triangles folded against each other.
  CHECK(info["folded_edges"] == 0);
  CHECK(info["max_dihedral_degrees"].get<double>() < 90.0);
}

TEST_CASE("info: figures an invalid mesh cannot have are unknown, with the defect and an error",
          "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("info_invalid");
  // A scan with holes and 1112 stray points: V - E + F would count each point, genus 556.
  mspline::structure::PolygonSoup scan = mspline::io::readMesh(realMeshPath("head.off")).soup;
  for (int i = 0; i < 1112; ++i) scan.positions.push_back({i * 1e-3, 0, 0});
  const std::string path = dir + "/stray.off";
  mspline::io::writeMesh(path, scan);

  auto json = runCommand(cliPath() + " info --json " + path);
  CHECK(json.exitCode == 2);
  const auto info = nlohmann::json::parse(json.out);  // one JSON object
  CHECK(info["valid"] == false);
  CHECK(info["euler"].is_null());
  CHECK(info["genus"].is_null());
  CHECK(info["topology_unknown_because"] == nlohmann::json::array({"unreferenced_vertex"}));
  // Boundary loops and components do not depend on the stray points.
  CHECK(info["boundaries"] == 3);
  CHECK(info["closed"] == false);
  CHECK(info["components"] == 1);
  CHECK(info["problems"][0]["kind"] == "unreferenced_vertex");
  CHECK(info["problems"][0]["count"] == 1112);
  CHECK(info["error"]["kind"] == "input");
  CHECK(info["error"]["message"].get<std::string>().find("1112 unreferenced vertices") !=
        std::string::npos);

  auto text = runCommand(cliPath() + " info " + path);
  CHECK(text.exitCode == 2);
  CHECK(text.out.find("genus                 unknown (unreferenced_vertex)") != std::string::npos);
  CHECK(text.out.find("boundaries            3") != std::string::npos);
  CHECK(text.err.find("error: " + path + ": 1112 unreferenced vertices") != std::string::npos);

  // Without a manifold mesh no boundary is known either.
  const std::string bowtie = dir + "/bowtie.off";
  std::ofstream(bowtie) << "OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n-1 0 0\n0 -1 0\n3 0 1 2\n3 0 3 4\n";
  const auto pinched = nlohmann::json::parse(runCommand(cliPath() + " info --json " + bowtie).out);
  for (const char* key : {"boundaries", "euler", "genus", "closed"}) CHECK(pinched[key].is_null());
  CHECK(pinched["topology_unknown_because"] == nlohmann::json::array({"non_manifold_vertex"}));
  CHECK(pinched.contains("error"));

  // A face repeating a vertex keeps the mesh from being built: that defect is named.
  const std::string repeated = dir + "/repeated.off";
  std::ofstream(repeated) << "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                             "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n3 0 0 1\n";
  const auto degenerate =
      nlohmann::json::parse(runCommand(cliPath() + " info --json " + repeated).out);
  CHECK(degenerate["genus"].is_null());
  CHECK(degenerate["topology_unknown_because"] == nlohmann::json::array({"degenerate_face"}));

  // Several components leave every figure known: the genus is the sum of theirs.
  const std::string pair = dir + "/pair.off";
  std::ofstream(pair) << "OFF\n8 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n5 0 0\n6 0 0\n5 1 0\n5 0 1\n"
                         "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 4 6 5\n3 4 5 7\n3 4 7 6\n3 5 6 7\n";
  const auto two = nlohmann::json::parse(runCommand(cliPath() + " info --json " + pair).out);
  CHECK(two["components"] == 2);
  CHECK(two["euler"] == 4);
  CHECK(two["genus"] == 0);
  CHECK_FALSE(two.contains("topology_unknown_because"));
  CHECK(two["error"]["message"].get<std::string>().find("2 components") != std::string::npos);
}

TEST_CASE("info: a tetrahedron at 1e300 or 1e-300 is valid", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_info_scale");
  for (const char* scale : {"1e300", "1e-300"}) {
    INFO(scale);
    const std::string path = dir + "/tet-" + scale + ".off";
    std::ofstream(path) << "OFF\n4 4 0\n0 0 0\n"
                        << scale << " 0 0\n0 " << scale << " 0\n0 0 " << scale
                        << "\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const nlohmann::json info = mspline::test::runJson("info " + path);
    CHECK(info["valid"] == true);
    CHECK(info["problems"].empty());
    CHECK(info["genus"] == 0);
    CHECK(info["bbox_diagonal"].get<double>() ==
          Approx(std::sqrt(3.0) * std::stod(scale)).epsilon(1e-15));
    CHECK(info["min_angle_degrees"].get<double>() == Approx(45.0).epsilon(1e-12));
  }
}
