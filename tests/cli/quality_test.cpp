// The quality object of `check` and `export`, and `check --scan`'s bad input: exit 2 and a message
// that names the scan.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "support/test_data.h"

using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;
using mspline::test::runJson;
using namespace mspline;

namespace {

// A small T-spline fit of the knot, shared by the cases of this file run in one process (ctest
// runs cases in parallel processes: a directory of this process's own).
const std::string& knotModel() {
  static const std::string path = test::fitModel(
      "knot1.off", "tspline",
      test::scratchDirectory("cli_quality_" + std::to_string(getpid())) + "/knot.msp");
  return path;
}

// A figure of the quality object that every report shares.
void checkQuality(const nlohmann::json& quality, bool withScan) {
  CHECK(quality["with_scan"] == withScan);
  CHECK(quality.contains("distances") == withScan);
  CHECK(quality["folds"]["total"].get<int>() == quality["folds"]["against_scan"].get<int>() +
                                                    quality["folds"]["adjacent_pairs"].get<int>());
  CHECK(quality["folds"]["at_scan_folds"].is_number_integer());
  const auto& smooth = quality["smoothness"];
  CHECK(smooth["coarse"]["resolution"] == 3);
  CHECK(smooth["fine"]["resolution"] == 6);
  CHECK(smooth["fine"]["pairs"].get<int>() > smooth["coarse"]["pairs"].get<int>());
  for (const char* level : {"coarse", "fine"}) {
    const auto& d = smooth[level];
    CHECK(d["p50"].get<double>() <= d["p99"].get<double>());
    CHECK(d["p99"].get<double>() <= d["p99_9"].get<double>());
    CHECK(d["p99_9"].get<double>() <= d["max"].get<double>());
  }
  CHECK(smooth["p99_ratio"].get<double>() ==
        Approx(smooth["coarse"]["p99"].get<double>() / smooth["fine"]["p99"].get<double>()));
  CHECK(quality["regularity"]["min_relative_jacobian"].get<double>() <= 1.0);
  CHECK(quality["seconds"].get<double>() > 0.0);
}

}  // namespace

TEST_CASE("quality: check reports it, against the scan when given", "[cli]") {
  const auto alone = runJson("check " + knotModel() + " --samples 100 --knot-samples 0");
  checkQuality(alone["quality"], false);
  const auto withScan = runJson("check " + knotModel() + " --scan " + realMeshPath("knot1.off") +
                                " --samples 100 --knot-samples 0");
  CHECK(withScan["scan"] == realMeshPath("knot1.off"));
  const auto& quality = withScan["quality"];
  checkQuality(quality, true);
  // The fit's own tolerance was 1e-3 of the diagonal with a small budget: close both ways.
  for (const char* way : {"scan_to_surface", "surface_to_scan"}) {
    const auto& d = quality["distances"][way];
    CHECK(d["rms"].get<double>() <= d["max"].get<double>());
    CHECK(d["max"].get<double>() < 0.05);
    CHECK(d["max_at"]["position"].size() == 3);
  }
  // Without the scan the same surface: the same smoothness.
  CHECK(quality["smoothness"] == alone["quality"]["smoothness"]);
}

TEST_CASE("quality: export reports it and marks creases in its picture", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_quality_export");
  const auto exported = runJson("export " + knotModel() + " -o " + dir + "/knot.ply --png " + dir +
                                "/knot.png --mark-defects --crease-degrees 5 --resolution 4");
  checkQuality(exported["quality"], false);
  // At 5 degrees a coarse knot has creases to mark; at 180 nothing is marked.
  CHECK(exported["marked_faces"].get<int>() > 0);
  const auto none = runJson("export " + knotModel() + " -o " + dir + "/knot.ply --png " + dir +
                            "/knot.png --mark-defects --crease-degrees 180 --resolution 4");
  CHECK(none["marked_faces"] == 0);
  // Marks need a picture.
  CHECK(runCommand(cliPath() + " export " + knotModel() + " -o " + dir + "/knot.ply --mark-defects")
            .exitCode == 1);
}

TEST_CASE("quality: check --scan refuses a scan that is not the model's, naming it", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_quality_bad_scan");
  const std::string broken = dir + "/broken.off";
  std::ofstream(broken) << "OFF\n4 4 0\n0 0 0\n1 0 nan\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n";
  for (const std::string& scan : {realMeshPath("eight.off"), broken, dir + "/missing.off"}) {
    INFO(scan);
    const auto result = runCommand(cliPath() + " check " + knotModel() + " --scan " + scan);
    CHECK(result.exitCode == 2);
    CHECK(result.err.find(scan) != std::string::npos);
    const auto json = runJson("check " + knotModel() + " --scan " + scan, 2);
    CHECK(json["error"]["message"].get<std::string>().find(scan) != std::string::npos);
  }
}

TEST_CASE("quality: check of a subdivision model reports its quality only", "[cli]") {
  const std::string model = test::fitModel(
      "knot1.off", "subd", test::scratchDirectory("cli_quality_subd") + "/knot-subd.msp");
  const auto checked = runJson("check " + model + " --scan " + realMeshPath("knot1.off") +
                               " --quality-resolution 2");
  CHECK(checked["kind"] == "subd");
  CHECK(checked["passed"].get<bool>());
  CHECK_FALSE(checked.contains("max_chart_discrepancy"));
  const auto& quality = checked["quality"];
  CHECK(quality["with_scan"].get<bool>());
  CHECK(quality["smoothness"]["coarse"]["resolution"] == 2);
  CHECK(quality["smoothness"]["fine"]["resolution"] == 4);
  // The knot has no cones: the limit surface is a bicubic B-spline, C2, fold-free.
  CHECK(quality["folds"]["total"] == 0);
  CHECK(quality["smoothness"]["p99_ratio"].get<double>() > 1.7);
}
