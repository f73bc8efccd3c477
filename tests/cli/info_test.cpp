// `mspline info` on real meshes reports the topology the acceptance criteria name.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

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
