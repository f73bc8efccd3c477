// `mspline fit` end to end on real scans (small budgets to keep it quick): the tolerance and the
// budget are honoured, errors are reported both ways, holes are filled and trimmed away again at
// export, an unreachable tolerance is a warning, and the model files load.
#include <catch2/catch.hpp>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "mspline/io/spline_model_file.h"
#include "support/test_data.h"

namespace fs = std::filesystem;
using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;
using mspline::test::runJson;
using namespace mspline;

namespace {

// The errors and counts every fit reports, checked against each other.
void checkReport(const nlohmann::json& fit, const std::string& kind, int budget) {
  CHECK(fit["kind"] == kind);
  CHECK(fit["control_points"].get<int>() <= budget);
  for (const char* key :
       {"rms_error", "max_error", "rms_error_surface_to_scan", "max_error_surface_to_scan"}) {
    INFO(key);
    CHECK(fit[key].get<double>() >= 0.0);
    CHECK(fit[key].get<double>() < 0.05);
  }
  CHECK(fit["rms_error"].get<double>() <= fit["max_error"].get<double>());
  CHECK(fit["rms_error_surface_to_scan"].get<double>() <=
        fit["max_error_surface_to_scan"].get<double>());
  // The quality object holds the same distances; reached needs them both ways, and no folds.
  const auto& quality = fit["quality"];
  const auto& distances = quality["distances"];
  CHECK(distances["scan_to_surface"]["rms"] == fit["rms_error"]);
  CHECK(distances["surface_to_scan"]["max"] == fit["max_error_surface_to_scan"]);
  const double tolerance = fit["tolerance"].get<double>(), wanted = fit["max_error_wanted"];
  if (fit["reached_tolerance"].get<bool>()) {
    for (const char* way : {"scan_to_surface", "surface_to_scan"}) {
      CHECK(distances[way]["rms"].get<double>() <= tolerance);
      CHECK(distances[way]["max"].get<double>() <= wanted);
    }
    CHECK(quality["folds"]["total"] == 0);
  }
  CHECK(quality["smoothness"]["fine"]["resolution"] == 6);
  CHECK(fit["rounds"].get<int>() >= 1);
  CHECK(fit["seconds"].get<double>() > 0.0);
  for (const char* stage : {"load", "atlas", "fit", "measure", "write"})
    CHECK(fit["stage_seconds"].contains(stage));
}

// `mspline info` of an exported surface.
nlohmann::json meshInfo(const std::string& path) {
  return runJson("info " + path);
}

}  // namespace

TEST_CASE("fit: a T-spline on the genus-1 knot reaches the tolerance within the budget", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_fit_knot");
  const std::string model = dir + "/knot.msp";
  const auto fit = runJson("fit " + realMeshPath("knot1.off") + " -o " + model +
                           " --max-control 500 --tolerance 3e-3 --rounds 2 -q");
  checkReport(fit, "tspline", 500);
  CHECK(fit["reached_tolerance"].get<bool>());
  // Parameter correction moved the samples to their closest points.
  CHECK(fit["rms_error"].get<double>() < fit["rms_error_before_correction"].get<double>());
  const spline::SplineModel loaded = io::readSplineModel(model);
  CHECK(loaded.kind == spline::SplineKind::TSpline);
  CHECK(loaded.controlPoints.rows() == fit["control_points"].get<int>());
  // The evaluated surface of a torus without cones: closed, genus 1, valid.
  const auto exported = runJson("export " + model + " -o " + dir + "/knot.ply --resolution 3");
  const auto info = meshInfo(dir + "/knot.ply");
  CHECK(info["valid"].get<bool>());
  CHECK(info["genus"] == 1);
  CHECK(info["closed"].get<bool>());
}

TEST_CASE("fit: subd and tribspline on the knot", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_fit_kinds");
  const auto subd = runJson("fit " + realMeshPath("knot1.off") + " --kind subd -o " + dir +
                            "/subd.msp --max-control 500 --tolerance 3e-3 --rounds 1 -q");
  checkReport(subd, "subd", 500);
  CHECK(io::readSplineModel(dir + "/subd.msp").kind == spline::SplineKind::Subdivision);
  // No holes at all: the limit surface of the closed net exports closed and valid.
  runJson("export " + dir + "/subd.msp -o " + dir + "/subd.ply --resolution 2");
  const auto info = meshInfo(dir + "/subd.ply");
  CHECK(info["valid"].get<bool>());
  CHECK(info["closed"].get<bool>());
  const auto tri = runJson("fit " + realMeshPath("knot1.off") + " --kind tribspline -o " + dir +
                           "/tri.msp --max-control 500 --tolerance 3e-3 --rounds 1 -q");
  checkReport(tri, "tribspline", 500);
  CHECK(tri["space"]["domain_faces"].get<int>() * 10 == tri["control_points"].get<int>());
}

TEST_CASE("fit: a scan with holes is filled for the fit and trimmed at export", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_fit_head");
  // Subdivision: no holes at cones, so the trimmed export must be a valid mesh.
  const auto fit = runJson("fit " + realMeshPath("head.off") + " --kind subd -o " + dir +
                           "/head.msp --max-control 800 --tolerance 5e-3 --rounds 1 -q");
  checkReport(fit, "subd", 800);
  CHECK(fit["filled_holes"] == 3);
  CHECK(fit["scan_vertices"] == fit["scan_vertices_measured"]);
  const spline::SplineModel model = io::readSplineModel(dir + "/head.msp");
  REQUIRE(model.surfaceFaceFilled.size() == model.surfaceFaces.size());
  const auto exported =
      runJson("export " + dir + "/head.msp -o " + dir + "/head.obj --resolution 2");
  CHECK(exported["trimmed_faces"].get<int>() > 0);
  // The three holes are back as boundary loops.
  const auto info = meshInfo(dir + "/head.obj");
  CHECK(info["boundaries"] == 3);
  CHECK(info["valid"].get<bool>());
}

TEST_CASE("fit: an unreachable tolerance warns and still writes the best model", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_fit_unreachable");
  const std::string model = dir + "/knot.msp";
  const auto result =
      runCommand(cliPath() + " fit " + realMeshPath("knot1.off") + " -o " + model +
                 " --max-control 300 --tolerance 1e-6 --max-refinements 1 --rounds 1 --json");
  INFO(result.err);
  CHECK(result.exitCode == 0);
  CHECK(result.err.find("warning: the tolerance was not reached") != std::string::npos);
  const auto fit = nlohmann::json::parse(result.out);
  CHECK_FALSE(fit["reached_tolerance"].get<bool>());
  CHECK(fs::exists(model));
}

TEST_CASE("fit: a budget that cannot be met ends, and says so", "[cli]") {
  // The smallest budget: the sphere's cones kept apart need 16 domain faces (160 control points).
  // This once rebuilt the same domain forever.
  const std::string dir = test::scratchDirectory("cli_fit_budget");
  const auto result = runCommand(cliPath() + " fit " + realMeshPath("sphere.off") + " -o " + dir +
                                 "/sphere.msp --kind tribspline --max-control 50 --json");
  INFO(result.err);
  CHECK(result.exitCode == 0);
  CHECK(result.err.find("warning: 160 control points, over the budget of 50") != std::string::npos);
  const auto fit = nlohmann::json::parse(result.out);
  CHECK_FALSE(fit["within_budget"].get<bool>());
  CHECK(fit["max_control"] == 50);
  CHECK(fit["control_points"] == 160);
  REQUIRE(fit["warnings"].is_array());
  CHECK(fit["warnings"][0].get<std::string>().find("over the budget of 50") != std::string::npos);
  CHECK(fs::exists(dir + "/sphere.msp"));
}

TEST_CASE("fit: bad arguments leave no model", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_fit_bad");
  const auto kind = runCommand(cliPath() + " fit " + realMeshPath("knot1.off") + " -o " + dir +
                               "/a.msp --kind nurbs");
  CHECK(kind.exitCode != 0);
  CHECK_FALSE(fs::exists(dir + "/a.msp"));
  const auto missing = runCommand(cliPath() + " fit " + dir + "/nowhere.off -o " + dir + "/a.msp");
  CHECK(missing.exitCode == 2);
  CHECK(missing.err.find("nowhere.off") != std::string::npos);
  CHECK_FALSE(fs::exists(dir + "/a.msp"));
}
