// `mspline flatten` end to end on real scans: convergence, cones, layout, failure reports.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "mspline/structure/core/constants.h"
#include "support/test_data.h"

namespace fs = std::filesystem;
using mspline::kPi;
using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;

namespace {

nlohmann::json flatten(const std::string& arguments, int expectedExit = 0) {
  auto result = runCommand(cliPath() + " flatten --json -q " + arguments);
  INFO("flatten " << arguments << "\nstderr: " << result.err);
  REQUIRE(result.exitCode == expectedExit);
  return nlohmann::json::parse(result.out);
}

}  // namespace

TEST_CASE("flatten: genus-1 knot without cones is a flat torus", "[cli]") {
  std::string dir = mspline::test::scratchDirectory("cli_flatten_knot");
  std::string out = dir + "/knot1.obj", svg = dir + "/knot1.svg";
  auto report =
      flatten(realMeshPath("knot1.off") + " --cones none -o " + out + " --svg " + svg + " --cover");
  CHECK(report["converged"] == true);
  CHECK(report["max_curvature_error"].get<double>() <= 1e-10);
  CHECK(report["flipped_triangles"] == 0);
  CHECK(report["cones"].empty());
  REQUIRE(report.contains("periods"));
  CHECK(report["max_period_residual"].get<double>() <= 1e-9);
  CHECK(report["max_seam_residual"].get<double>() <= 1e-9);

  // The written OBJ is a valid mesh with the input's topology, and carries UVs.
  auto info = runCommand(cliPath() + " info --json " + out);
  REQUIRE(info.exitCode == 0);
  CHECK(nlohmann::json::parse(info.out)["genus"] == 1);
  std::ifstream obj(out);
  std::string text((std::istreambuf_iterator<char>(obj)), std::istreambuf_iterator<char>());
  CHECK(text.find("\nvt ") != std::string::npos);
  std::ifstream picture(svg);
  std::string head(4, ' ');
  picture.read(head.data(), 4);
  CHECK(head == "<svg");
}

TEST_CASE("flatten: bunny with quantized automatic cones", "[cli][slow]") {
  std::string dir = mspline::test::scratchDirectory("cli_flatten_bunny");
  auto report = flatten(realMeshPath("bunny00.off") + " --quantize -o " + dir + "/bunny.obj");
  CHECK(report["converged"] == true);
  CHECK(report["iterations"].get<int>() <= 20);
  CHECK(report["max_curvature_error"].get<double>() <= 1e-10);
  CHECK(report["flipped_triangles"] == 0);
  double sum = 0;
  for (const auto& cone : report["cones"]) {
    double quarterTurns = cone["curvature"].get<double>() / (kPi / 2);
    CHECK(std::abs(quarterTurns - std::round(quarterTurns)) <= 1e-12);
    sum += cone["curvature"].get<double>();
  }
  CHECK(sum == Approx(4 * kPi).epsilon(1e-12));  // Gauss-Bonnet for a sphere
  // Every seam transition is a rotation by a multiple of 90 degrees (radians off, below).
  CHECK(report["seam_rotations"]["rotated"].get<int>() > 0);
  CHECK(report["seam_rotations"]["max_quarter_turn_error"].get<double>() <= 1e-9);
}

TEST_CASE("flatten: where the input triangulation degenerates, the overlay is laid out", "[cli]") {
  // mannequin-devil's fixed (circular) boundary makes some input triangles degenerate: the
  // metric is reached with intrinsic Delaunay flips and the common subdivision is written.
  std::string dir = mspline::test::scratchDirectory("cli_flatten_flips");
  std::string out = dir + "/devil.obj";
  auto report = flatten(realMeshPath("mannequin-devil.off") + " --boundary fixed -o " + out);
  CHECK(report["converged"] == true);
  CHECK(report["max_curvature_error"].get<double>() <= 1e-10);
  CHECK(report["flips"].get<long>() > 0);
  CHECK(report["flipped_triangles"] == 0);
  REQUIRE(report.contains("overlay"));
  CHECK(report["overlay"]["length_mismatch"].get<double>() <= 1e-9);

  auto input = nlohmann::json::parse(
      runCommand(cliPath() + " info --json " + realMeshPath("mannequin-devil.off")).out);
  auto info = runCommand(cliPath() + " info --json " + out);
  REQUIRE(info.exitCode == 0);
  auto written = nlohmann::json::parse(info.out);
  CHECK(written["faces"] == report["overlay"]["faces"]);
  CHECK(written["vertices"].get<long>() == input["vertices"].get<long>() +
                                               report["overlay"]["crossings"].get<long>() +
                                               report["overlay"]["split_edges"].get<long>());
  CHECK(written["euler"] == input["euler"]);
  CHECK(written["boundaries"] == input["boundaries"]);
}

TEST_CASE("flatten: circle-packing schemes", "[cli]") {
  std::string dir = mspline::test::scratchDirectory("cli_flatten_schemes");
  for (const char* scheme : {"tangential", "inversive"}) {
    INFO(scheme);
    auto report = flatten(realMeshPath("knot1.off") + " --cones none --scheme " + scheme + " -o " +
                          dir + "/knot1.obj");
    CHECK(report["converged"] == true);
    CHECK(report["flipped_triangles"] == 0);
  }
}

TEST_CASE("flatten: bad targets and non-convergence are reported", "[cli]") {
  std::string dir = mspline::test::scratchDirectory("cli_flatten_bad");
  std::string out = dir + "/out.obj";

  // A single cone on a torus violates Gauss-Bonnet (the sum must be 0).
  std::ofstream(dir + "/cones.txt") << "# vertex curvature\n5 1.5707963267948966\n";
  auto gaussBonnet = runCommand(cliPath() + " flatten -q " + realMeshPath("knot1.off") +
                                " --cones " + dir + "/cones.txt -o " + out);
  CHECK(gaussBonnet.exitCode == 2);
  CHECK(gaussBonnet.err.find("Gauss-Bonnet") != std::string::npos);

  // Too few Newton steps: exit 3, the partial report says why, nothing is written.
  auto report = flatten(realMeshPath("eight.off") + " --max-iterations 2 -o " + out, 3);
  CHECK(report["converged"] == false);
  CHECK(report["error"]["kind"] == "solver");
  CHECK_FALSE(fs::exists(out));

  // Both solvers out of steps: the report carries the plain solver's diagnosis and the flips.
  auto disk = flatten(realMeshPath("mannequin-devil.off") + " --max-iterations 2 -o " + out, 3);
  CHECK(disk["converged"] == false);
  CHECK(disk.contains("plain_solver"));
  CHECK(disk["flips"].get<long>() > 0);
  CHECK_FALSE(fs::exists(out));

  auto notObj = runCommand(cliPath() + " flatten -q " + realMeshPath("knot1.off") + " -o " + dir +
                           "/out.ply");
  CHECK(notObj.exitCode == 2);
}
