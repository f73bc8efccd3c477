// `mspline atlas` on real meshes: transition kinds, residuals, the written file read back.
#include <catch2/catch.hpp>

#include <cmath>

#include <nlohmann/json.hpp>

#include "support/test_data.h"

using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;

namespace {

nlohmann::json atlas(const std::string& arguments, int expectedExit = 0) {
  auto result = runCommand(cliPath() + " atlas --json -q " + arguments);
  INFO("atlas " << arguments << "\nstderr: " << result.err);
  REQUIRE(result.exitCode == expectedExit);
  return nlohmann::json::parse(result.out);
}

}  // namespace

TEST_CASE("atlas: knot1 without cones is a translation structure", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_atlas_knot");
  auto report = atlas(realMeshPath("knot1.off") + " --cones none --check -o " + dir + "/k.json");
  CHECK(report["transition_kind"] == "translation");
  CHECK(report["max_transition_residual"].get<double>() <= 1e-10);
  CHECK(report["max_cocycle_residual"].get<double>() <= 1e-10);
  CHECK(report["uncovered_faces"] == 0);
  CHECK(report["charts"] == 3200);
  CHECK(report["check"]["identical"] == true);
  CHECK(report["check"]["max_cocycle_residual"] == report["max_cocycle_residual"]);
}

TEST_CASE("atlas: bunny00 with quantized cones turns by quarter turns", "[cli][slow]") {
  const std::string dir = mspline::test::scratchDirectory("cli_atlas_bunny");
  auto report = atlas(realMeshPath("bunny00.off") + " --quantize -o " + dir + "/b.json");
  CHECK(report["transition_kind"] == "rotation90");
  // Quarter turns up to the curvature the flow leaves at the flat vertices.
  CHECK(report["max_kind_angle_error"].get<double>() <=
        1e-9 + report["flatness_defect"].get<double>());
  CHECK(report["max_transition_residual"].get<double>() <= 1e-10);
  CHECK(report["max_cocycle_residual"].get<double>() <= 1e-10);
  CHECK(report["uncovered_faces"] == 0);
  // Every cone a multiple of pi/2 up to the flow's tolerance (1e-10), in all 2 pi chi = 4 pi
  // (Gauss-Bonnet on a sphere).
  REQUIRE(!report["cones"].empty());
  double total = 0.0;
  for (const auto& cone : report["cones"]) {
    const double quarters = cone["curvature"].get<double>() / 1.5707963267948966;
    CHECK(std::abs(quarters - std::round(quarters)) <= 1e-9);
    CHECK(std::round(quarters) != 0.0);
    total += cone["curvature"].get<double>();
  }
  CHECK(std::abs(total - 4.0 * 3.141592653589793) <= 1e-9);
}

TEST_CASE("atlas: eight with quantized cones and handles turns by quarter turns", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_atlas_eight");
  auto report = atlas(realMeshPath("eight.off") + " --quantize --check -o " + dir + "/e.json");
  CHECK(report["transition_kind"] == "rotation90");
  CHECK(report["max_transition_residual"].get<double>() <= 1e-10);
  CHECK(report["max_cocycle_residual"].get<double>() <= 1e-10);
  CHECK(report["uncovered_faces"] == 0);
  CHECK(report["check"]["identical"] == true);
  const auto& holonomy = report["flatten"]["holonomy"];
  CHECK(holonomy["loops"] == 4);
  CHECK(holonomy["converged"] == true);
  for (const auto& rotation : holonomy["target_rotations"]) {
    const double quarters = rotation.get<double>() / 1.5707963267948966;
    CHECK(std::abs(quarters - std::round(quarters)) <= 1e-12);
  }
}

TEST_CASE("atlas: bad input", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_atlas_bad");
  auto missing = runCommand(cliPath() + " atlas " + dir + "/none.off -o " + dir + "/a.json");
  CHECK(missing.exitCode == 2);
  CHECK(missing.err.find("none.off") != std::string::npos);
}
