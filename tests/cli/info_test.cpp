// `mspline info` on real meshes reports the topology the acceptance criteria name.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

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
        "orientable", "bbox_diagonal", "min_angle_degrees", "median_angle_degrees", "problems"})
    CHECK(info.contains(key));
  CHECK(info["vertices"] == 37706);
  CHECK(info["faces"] == 75408);
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
