// `mspline voronoi` end to end: cells on knot1.off, sites files, bad input.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/test_data.h"

namespace fs = std::filesystem;
using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;

namespace {

nlohmann::json voronoi(const std::string& arguments) {
  auto result = runCommand(cliPath() + " voronoi --json -q " + arguments);
  INFO("voronoi " << arguments << "\nstderr: " << result.err);
  REQUIRE(result.exitCode == 0);
  return nlohmann::json::parse(result.out);
}

}  // namespace

TEST_CASE("voronoi: 20 random sites on knot1.off", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_voronoi_knot");
  const std::string out = dir + "/cells.obj", svg = dir + "/cells.svg", png = dir + "/cells.png";
  auto report = voronoi(realMeshPath("knot1.off") + " --sites 20 -o " + out + " --svg " + svg +
                        " --png " + png);
  WARN("knot1.off, 20 sites: " << report.dump());
  CHECK(report["sites"] == 20);
  CHECK(report["cells"] == 20);
  CHECK(report["faces_per_cell"]["min"].get<int>() > 0);
  CHECK(report["faces_per_cell"]["max"].get<int>() < 6400);
  CHECK(report["replicated_sites"] == 180);
  CHECK(report["max_equidistance_error"].get<double>() <= 1e-12);
  const std::string obj = mspline::test::fileText(out);
  CHECK(mspline::test::countOf(obj, "\ng cell_") == 20);
  CHECK(mspline::test::countOf(obj, "\nf ") == 6400);
  CHECK(mspline::test::countOf(obj, "\nl ") == report["boundary_polylines"].get<std::size_t>());
  CHECK(report["boundary_polylines"].get<int>() > 20);
  CHECK(mspline::test::fileText(svg).rfind("<svg", 0) == 0);
  CHECK(mspline::test::fileText(png).rfind("\x89PNG\r\n\x1a\n", 0) == 0);

  // The default seed makes the output reproducible; another seed moves the sites.
  const std::string again = dir + "/again.obj", other = dir + "/other.obj";
  voronoi(realMeshPath("knot1.off") + " --sites 20 -o " + again);
  voronoi(realMeshPath("knot1.off") + " --sites 20 --seed 9 -o " + other);
  CHECK(mspline::test::fileText(again) == obj);
  CHECK(mspline::test::fileText(other) != obj);
}

TEST_CASE("voronoi: sites from a file", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_voronoi_file");
  const std::string sites = dir + "/sites.txt";
  std::ofstream(sites) << "# face b0 b1 b2\n10 0.2 0.3 0.5\n\n3000 1 0 0  # a vertex\n"
                          "5000 0.3333333333333333 0.3333333333333333 0.3333333333333334\n";
  auto report = voronoi(realMeshPath("knot1.off") + " --sites " + sites + " -o " + dir + "/a.obj");
  CHECK(report["sites"] == 3);
  CHECK(report["cells"] == 3);
  // elk.off needs intrinsic flips: the sites move onto the common subdivision that is written.
  std::ofstream(sites) << "10 0.2 0.3 0.5\n3000 1 0 0\n2000 0.1 0.1 0.8\n";
  auto elk = voronoi(realMeshPath("elk.off") + " --sites " + sites + " -o " + dir + "/elk.obj");
  CHECK(elk["cells"] == 3);
  CHECK(mspline::test::countOf(mspline::test::fileText(dir + "/elk.obj"), "\nf ") > 3290);
}

TEST_CASE("voronoi: bad input exits 2 and says why", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_voronoi_bad");
  const std::string out = dir + "/out.obj";
  auto run = [&](const std::string& arguments) {
    return runCommand(cliPath() + " voronoi -q " + arguments + " -o " + out);
  };
  const std::string knot = realMeshPath("knot1.off");
  const std::string malformed = dir + "/malformed.txt";
  std::ofstream(malformed) << "# sites\n12 0.5 0.5\n";
  auto result = run(knot + " --sites " + malformed);
  CHECK(result.exitCode == 2);
  CHECK(result.err.find(malformed + ":2: expected 'face b0 b1 b2'") != std::string::npos);

  const std::string range = dir + "/range.txt";
  std::ofstream(range) << "6400 0.5 0.5 0\n";
  result = run(knot + " --sites " + range);
  CHECK(result.exitCode == 2);
  CHECK(result.err.find(range + ":1: face 6400 is out of range") != std::string::npos);

  const std::string weights = dir + "/weights.txt";
  std::ofstream(weights) << "5 0.5 0.7 -0.2\n";
  result = run(knot + " --sites " + weights);
  CHECK(result.exitCode == 2);
  CHECK(result.err.find(weights + ":1: barycentric") != std::string::npos);

  result = run(knot + " --sites " + dir + "/missing.txt");
  CHECK(result.exitCode == 2);
  CHECK(result.err.find("missing.txt") != std::string::npos);

  result = run(knot + " --sites 0");
  CHECK(result.exitCode == 2);

  result = run(realMeshPath("eight.off") + " --sites 5");
  CHECK(result.exitCode == 2);
  CHECK(result.err.find("eight.off: voronoi needs a closed genus-1 surface") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
}
