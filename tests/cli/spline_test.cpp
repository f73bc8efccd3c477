// `mspline spline`, `check` and `export` end to end on real meshes.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "mspline/io/load_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"

namespace fs = std::filesystem;
using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;
using mspline::test::runJson;
using namespace mspline;

namespace {

nlohmann::json checkModel(const std::string& name, const std::string& model) {
  // The knot route re-evaluates every simplex spline from scratch: a few hundred samples show it.
  const auto check = runJson("check " + model + " --samples 10000 --knot-samples 100");
  WARN(name << ": " << check.dump());
  CHECK(check["samples"] == 10000);
  CHECK(check["charts_per_sample"].get<double>() >= 2.0);
  CHECK(check["max_chart_discrepancy"].get<double>() <= 1e-12);
  CHECK(check["knot_route_samples"] == 100);
  CHECK(check["knot_route_discrepancy"].get<double>() <= 1e-12);
  CHECK(check["normalized_partition_of_unity_error"].get<double>() <= 1e-13);
  CHECK(check["partition_of_unity_error"].get<double>() <= 1e-11);
  CHECK(check["min_denominator"].get<double>() > 0.0);
  CHECK(check["passed"] == true);
  return check;
}

}  // namespace

TEST_CASE("spline: knot1 without cones, checked in every chart", "[cli][slow]") {
  const std::string dir = mspline::test::scratchDirectory("cli_spline_knot");
  const auto built =
      runJson("spline -q " + realMeshPath("knot1.off") + " --cones none -o " + dir + "/k.msp");
  CHECK(built["cones"] == 0);
  CHECK(built["control_points"] == 6000);
  CHECK(built["domain_flatness"]["after"].get<double>() <= 1e-13);
  CHECK(built["fit_rms_error"].get<double>() <= 1e-3);
  const auto check = checkModel("knot1", dir + "/k.msp");
  // Away from cones (here: everywhere) the DMS identity holds without normalization.
  CHECK(check["partition_of_unity_samples"] == 10000);
  CHECK(check["partition_of_unity_error"].get<double>() <= 1e-12);
}

TEST_CASE("spline: bunny00 and eight with quantized cones, checked in every chart", "[cli][slow]") {
  const std::string dir = mspline::test::scratchDirectory("cli_spline_cones");
  for (const std::string name : {"bunny00", "eight"}) {
    const std::string model = dir + "/" + name + ".msp";
    const auto built =
        runJson("spline -q " + realMeshPath(name + ".off") + " --quantize -o " + model);
    CHECK(built["cones"].get<int>() > 0);
    CHECK(built["fit_rms_error"].get<double>() <= 2e-3);
    checkModel(name, model);
  }
}

TEST_CASE("spline: save, load and save again give the same bytes and values", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_spline_roundtrip");
  runJson("spline -q " + realMeshPath("eight.off") + " --quantize --control 2000 -o " + dir +
          "/a.msp");
  const spline::SplineModel model = io::readSplineModel(dir + "/a.msp");
  io::writeSplineModel(dir + "/b.msp", model);
  CHECK(mspline::test::fileText(dir + "/a.msp") == mspline::test::fileText(dir + "/b.msp"));
  const spline::SplineModel again = io::readSplineModel(dir + "/b.msp");
  const spline::TriBSplineSpace first(model.domain, model.knots);
  const spline::TriBSplineSpace second(again.domain, again.knots);
  std::mt19937 random(8);
  std::uniform_int_distribution<int> face(0, model.domain.faceCount() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::SurfacePoint> points;
  for (int k = 0; k < 1000; ++k) {
    Eigen::Vector3d b(unit(random), unit(random), unit(random));
    points.push_back({face(random), b / b.sum()});
  }
  const auto a = first.evaluateBatch(model.controlPoints, points, 2);
  const auto b = second.evaluateBatch(again.controlPoints, points, 2);
  for (const auto& [x, y] : {std::pair{&a.position, &b.position},
                             {&a.du, &b.du},
                             {&a.dv, &b.dv},
                             {&a.duu, &b.duu},
                             {&a.dvv, &b.dvv}})
    CHECK(std::memcmp(x->data(), y->data(), sizeof(double) * std::size_t(x->size())) == 0);
}

TEST_CASE("spline: export writes a watertight surface", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_spline_export");
  runJson("spline -q " + realMeshPath("eight.off") + " --quantize --control 2000 -o " + dir +
          "/e.msp");
  for (const std::string extension : {"obj", "ply", "stl"}) {
    const std::string out = dir + "/e." + extension;
    const auto exported = runJson("export " + dir + "/e.msp -o " + out + " --resolution 4");
    CHECK(exported["faces"].get<int>() == 16 * exported["faces"].get<int>() / 16);
    CHECK(exported["min_denominator"].get<double>() > 0.0);
    const auto loaded = io::loadMesh(out);
    const auto topology = structure::analyzeTopology(*loaded.mesh);
    INFO(extension);
    CHECK(topology.closed);
    CHECK(topology.components == 1);
    CHECK(topology.genus == 2);
  }
}

TEST_CASE("spline: bad input exits 2 naming the file, writing nothing", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_spline_bad");
  auto bounded = runCommand(cliPath() + " spline -q " + realMeshPath("mannequin-devil.off") +
                            " -o " + dir + "/m.msp");
  CHECK(bounded.exitCode == 2);
  CHECK_THAT(bounded.err, Catch::Contains("mannequin-devil.off") && Catch::Contains("closed"));
  CHECK(!fs::exists(dir + "/m.msp"));

  std::ofstream(dir + "/not.msp") << "solid nothing\n";
  auto notModel = runCommand(cliPath() + " check " + dir + "/not.msp");
  CHECK(notModel.exitCode == 2);
  CHECK_THAT(notModel.err, Catch::Contains("not.msp"));
  auto exportBad = runCommand(cliPath() + " export " + dir + "/not.msp -o " + dir + "/x.obj");
  CHECK(exportBad.exitCode == 2);
  CHECK(!fs::exists(dir + "/x.obj"));
  auto wrongFormat = runCommand(cliPath() + " export " + dir + "/not.msp -o " + dir + "/x.xyz");
  CHECK(wrongFormat.exitCode == 2);
  CHECK_THAT(wrongFormat.err, Catch::Contains("x.xyz"));
}
