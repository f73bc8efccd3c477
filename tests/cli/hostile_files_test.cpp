// Issue 17: files the readers accepted and the commands then crashed on, wrote empty outputs from
// or measured wrongly. Each must now be refused with exit 2, naming the file, writing nothing.
#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "mspline/io/spline_model_file.h"
#include "support/test_data.h"

namespace fs = std::filesystem;
using mspline::test::cliPath;
using mspline::test::runCommand;

namespace {

std::string writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string u32(std::uint32_t value) {
  std::string bytes(4, '\0');
  for (int k = 0; k < 4; ++k) bytes[std::size_t(k)] = char((value >> (8 * k)) & 0xff);
  return bytes;
}

// `mspline <arguments>` exits 2 with a first stderr line that names `file`.
void expectRefused(const std::string& arguments, const std::string& file) {
  const auto result = runCommand(cliPath() + " " + arguments);
  INFO(arguments << "\nstderr: " << result.err);
  CHECK(result.exitCode == 2);
  CHECK_THAT(result.err.substr(0, result.err.find('\n')), Catch::Contains(file));
}

}  // namespace

TEST_CASE(
    "hostile_files: check and export refuse empty models and control points that are "
    "not 3D",
    "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("hostile_files_models");
  // The 48-byte model: a triangular B-spline header, every count 0, control points 0 x 3.
  const std::string empty = writeBytes(
      dir + "/empty.msp", std::string("MSPLINE\x1a", 8) + u32(3) + u32(1) + u32(0) + u32(0) +
                              u32(0) + u32(0) + u32(0) + u32(1) + u32(0) + u32(3));
  REQUIRE(fs::file_size(empty) == 48);
  std::vector<std::string> models = {empty};

  const std::string good = dir + "/good.msp";
  const auto built =
      runCommand(cliPath() + " spline " + mspline::test::realMeshPath("torus_quad.off") +
                 " --control 20 -q -o " + good);
  REQUIRE(built.exitCode == 0);
  const std::string bytes = mspline::test::fileText(good);
  const auto rows = std::size_t(mspline::io::readSplineModel(good).controlPoints.rows());
  const std::size_t columnsAt = bytes.size() - rows * 3 * 8 - 4;
  for (std::uint32_t columns : {0u, 1u, 2u, 4u})
    models.push_back(writeBytes(
        dir + "/columns" + std::to_string(columns) + ".msp",
        bytes.substr(0, columnsAt) + u32(columns) + std::string(rows * columns * 8, '\0')));

  for (const std::string& model : models) {
    expectRefused("check " + model, model);
    const std::string output = dir + "/out.obj";
    expectRefused("export " + model + " -o " + output, model);
    CHECK_FALSE(fs::exists(output));
  }
}

// Found by fuzz_model: a knot far outside the domain's grid overflowed an int in the DMS space's
// neighbourhood search (undefined behaviour, reported by UBSan in the sanitized build).
TEST_CASE("hostile_files: check and export take a model with a knot far away", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("hostile_files_knot");
  const std::string good = dir + "/good.msp";
  REQUIRE(runCommand(cliPath() + " spline " + mspline::test::realMeshPath("torus_quad.off") +
                     " --control 20 -q -o " + good)
              .exitCode == 0);
  const auto model = mspline::io::readSplineModel(good);
  REQUIRE(model.surfaceFaceFilled.empty());
  // The sections before the knots (io/spline_model_file.h), then knot 1 of corner 0 of face 0.
  const std::size_t vertices = std::size_t(model.surfaceVertices.rows());
  const std::size_t knots = 16 + 4 + 24 * vertices + 4 + 12 * model.surfaceFaces.size() + 4 +
                            28 * vertices + 4 + 5 * model.domain.cone.size() + 4 +
                            51 * model.domain.faces.size() + 4;
  std::string bytes = mspline::test::fileText(good);
  const double far = -3.36e58;
  std::memcpy(&bytes[knots + 16], &far, 8);
  const std::string path = writeBytes(dir + "/far.msp", bytes);
  REQUIRE(mspline::io::readSplineModel(path).knots[0][0][1].x() == far);
  for (const std::string& command : {"check " + path + " --samples 500 --knot-samples 50",
                                     "export " + path + " -o " + dir + "/out.obj"}) {
    const auto result = runCommand(cliPath() + " " + command);
    INFO(command << "\nstderr: " << result.err);
    CHECK(result.exitCode >= 0);  // no signal
    CHECK(result.exitCode != 1);
  }
}

TEST_CASE("hostile_files: export --error-map refuses a scan with a NaN vertex", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("hostile_files_scan");
  const std::string model = dir + "/model.msp";
  REQUIRE(runCommand(cliPath() + " spline " + mspline::test::realMeshPath("torus_quad.off") +
                     " --control 20 -q -o " + model)
              .exitCode == 0);
  const std::string scan =
      writeBytes(dir + "/scan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
  expectRefused(
      "export " + model + " -o " + dir + "/out.obj --error-map " + scan + " " + dir + "/errors.ply",
      scan);
  CHECK_FALSE(fs::exists(dir + "/errors.ply"));
}

TEST_CASE("hostile_files: a directory is not a cone file", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("hostile_files_cones");
  fs::create_directory(dir + "/cones");
  const auto result =
      runCommand(cliPath() + " flatten " + mspline::test::realMeshPath("torus_quad.off") +
                 " --cones " + dir + "/cones -o " + dir + "/flat.obj");
  INFO("stderr: " << result.err);
  CHECK(result.exitCode != 0);
  CHECK_THAT(result.err, Catch::Contains(dir + "/cones") && Catch::Contains(std::strerror(EISDIR)));
  CHECK_FALSE(fs::exists(dir + "/flat.obj"));
}
