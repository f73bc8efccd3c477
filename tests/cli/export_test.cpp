// `mspline export`: normals, chart coordinates, --tolerance, the control net, the error map and
// the picture, on small models.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

#include <Eigen/Geometry>
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "mspline/io/read_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/structure/mesh/closest_point.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "support/test_data.h"

using mspline::test::realMeshPath;
using mspline::test::runJson;
using namespace mspline;

namespace {

struct ObjFile {
  std::vector<Eigen::Vector3d> positions, normals;
  std::vector<Eigen::Vector2d> uvs;
  std::vector<std::array<int, 3>> faces;  // position indices
  int lines = 0;
  bool cornersShareIndices = true;  // every corner's v, vt and vn indices are equal
};

ObjFile readObj(const std::string& path) {
  ObjFile obj;
  std::istringstream in(test::fileText(path));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "v" || keyword == "vn") {
      Eigen::Vector3d x;
      words >> x.x() >> x.y() >> x.z();
      (keyword == "v" ? obj.positions : obj.normals).push_back(x);
    } else if (keyword == "vt") {
      Eigen::Vector2d x;
      words >> x.x() >> x.y();
      obj.uvs.push_back(x);
    } else if (keyword == "l") {
      ++obj.lines;
    } else if (keyword == "f") {
      std::array<int, 3>& face = obj.faces.emplace_back();
      for (int& v : face) {
        std::string corner;
        words >> corner;
        int a = 0, b = 0, c = 0;
        REQUIRE(std::sscanf(corner.c_str(), "%d/%d/%d", &a, &b, &c) == 3);
        obj.cornersShareIndices = obj.cornersShareIndices && a == b && b == c;
        v = a - 1;
      }
    }
  }
  return obj;
}

// Share of triangle corners whose vertex normal agrees with the triangle (positive dot product
// with its normal).
double agreeingNormals(const std::vector<Eigen::Vector3d>& positions,
                       const std::vector<std::array<int, 3>>& faces,
                       const std::vector<Eigen::Vector3d>& normals) {
  int agreeing = 0;
  for (const auto& f : faces) {
    const Eigen::Vector3d n =
        (positions[std::size_t(f[1])] - positions[std::size_t(f[0])])
            .cross(positions[std::size_t(f[2])] - positions[std::size_t(f[0])]);
    for (int v : f) agreeing += normals[std::size_t(v)].dot(n) > 0.0;
  }
  return double(agreeing) / double(3 * faces.size());
}

// Small models of knot1.off (genus 1): a triangular B-spline (fewer control points fold the
// fitted surface more) and a T-spline.
std::string triModel(const std::string& dir) {
  const std::string model = dir + "/k.msp";
  runJson("spline -q " + realMeshPath("knot1.off") + " --cones none --control 1500 -o " + model);
  return model;
}

std::string tsplineModel(const std::string& dir) {
  const std::string model = dir + "/t.msp";
  runJson("spline -q " + realMeshPath("knot1.off") +
          " --kind tspline --cones none --control 500 -o " + model);
  return model;
}

}  // namespace

TEST_CASE("export: OBJ with unit normals facing like the triangles, chart coordinates, closed",
          "[cli]") {
  const std::string dir = test::scratchDirectory("cli_export_normals");
  const std::string model = triModel(dir);
  const auto exported = runJson("export " + model + " -o " + dir + "/s.obj --resolution 4");
  const ObjFile obj = readObj(dir + "/s.obj");
  REQUIRE(obj.positions.size() == exported["vertices"].get<std::size_t>());
  REQUIRE(obj.normals.size() == obj.positions.size());
  REQUIRE(obj.uvs.size() == obj.positions.size());
  CHECK(obj.cornersShareIndices);
  for (const auto& n : obj.normals) CHECK(n.norm() == Approx(1.0).margin(1e-12));
  CHECK(agreeingNormals(obj.positions, obj.faces, obj.normals) > 0.98);
  const auto info = runJson("info " + dir + "/s.obj");
  CHECK(info["closed"] == true);
  CHECK(info["genus"] == 1);
  CHECK(info["problems"].empty());
}

TEST_CASE("export: PLY with normals, STL, and a T-spline model", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_export_ply");
  const std::string model = tsplineModel(dir);
  const auto exported = runJson("export " + model + " -o " + dir + "/s.ply --resolution 2");
  const std::string text = test::fileText(dir + "/s.ply");
  CHECK(text.find("property double nx\nproperty double ny\nproperty double nz\n") !=
        std::string::npos);
  // Binary little-endian: x y z nx ny nz as doubles per vertex, after the header.
  const std::size_t start = text.find("end_header\n") + 11;
  const auto vertices = exported["vertices"].get<std::size_t>();
  std::vector<Eigen::Vector3d> positions(vertices), normals(vertices);
  for (std::size_t v = 0; v < vertices; ++v) {
    double x[6];
    std::memcpy(x, text.data() + start + 48 * v, sizeof x);
    positions[v] = {x[0], x[1], x[2]};
    normals[v] = {x[3], x[4], x[5]};
    CHECK(normals[v].norm() == Approx(1.0).margin(1e-12));
  }
  const auto read = io::readMesh(dir + "/s.ply");
  REQUIRE(read.soup.positions.size() == vertices);
  CHECK(agreeingNormals(positions, structure::triangleIndices(read.soup), normals) > 0.999);
  const auto info = runJson("info " + dir + "/s.ply");
  CHECK(info["closed"] == true);
  CHECK(info["problems"].empty());
  runJson("export " + model + " -o " + dir + "/s.stl --resolution 2");
  CHECK(runJson("info " + dir + "/s.stl")["closed"] == true);
}

TEST_CASE("export: --tolerance picks a finer resolution for a smaller tolerance", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_export_tolerance");
  for (const auto& [model, coarseTolerance, fineTolerance] :
       {std::tuple{triModel(dir), 0.3, 0.1}, std::tuple{tsplineModel(dir), 1e-3, 1e-4}}) {
    INFO(model);
    const auto coarse = runJson("export " + model + " -o " + dir + "/a.obj --tolerance " +
                                std::to_string(coarseTolerance));
    const auto fine = runJson("export " + model + " -o " + dir + "/b.obj --tolerance " +
                              std::to_string(fineTolerance));
    CHECK(fine["resolution"].get<int>() > coarse["resolution"].get<int>());
    for (const auto* r : {&coarse, &fine}) {
      CHECK((*r)["tolerance_met"] == true);
      const double estimate = (*r)["chord_error_estimate"].get<double>();
      CHECK(estimate <= (*r)["tolerance"].get<double>());
      // The smallest such resolution: one step coarser would not do (the estimate goes as 1/R^2).
      const double resolution = (*r)["resolution"].get<double>();
      if (resolution > 1)
        CHECK(estimate * std::pow(resolution / (resolution - 1), 2) >
              (*r)["tolerance"].get<double>());
    }
  }
}

TEST_CASE("export: the control net, the error map and the picture", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_export_extras");
  const std::string model = triModel(dir);
  const spline::SplineModel loaded = io::readSplineModel(model);
  const auto exported =
      runJson("export " + model + " -o " + dir + "/s.obj --resolution 2 --control-net " + dir +
              "/net.obj --error-map " + realMeshPath("knot1.off") + " " + dir + "/err.ply --png " +
              dir + "/s.png");
  const ObjFile net = readObj(dir + "/net.obj");
  CHECK(net.positions.size() == std::size_t(loaded.controlPoints.rows()));
  // Cubic: the edges of the triangular grid of multi-indices, 3 n (n + 1) / 2 = 18 per face.
  CHECK(net.lines == 18 * loaded.domain.faceCount());
  CHECK(exported["control_net"]["points"] == loaded.controlPoints.rows());

  // Error map: one color per scan vertex, the max equals brute force.
  const auto scan = io::readMesh(realMeshPath("knot1.off"));
  const std::string text = test::fileText(dir + "/err.ply");
  CHECK(text.find("element vertex " + std::to_string(scan.soup.positions.size()) +
                  "\nproperty double x\nproperty double y\nproperty double z\nproperty uchar "
                  "red\nproperty uchar green\nproperty uchar blue\n") != std::string::npos);
  const auto surface = io::readMesh(dir + "/s.obj");
  double largest = 0.0;
  for (const auto& p : scan.soup.positions) {
    const Eigen::Vector3d x(p[0], p[1], p[2]);
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& f : surface.soup.faces) {
      const auto corner = [&](int k) {
        const auto& q = surface.soup.positions[std::size_t(f[std::size_t(k)])];
        return Eigen::Vector3d(q[0], q[1], q[2]);
      };
      nearest = std::min(
          nearest, structure::closestPointOnTriangle(x, corner(0), corner(1), corner(2)).distance);
    }
    largest = std::max(largest, nearest);
  }
  CHECK(exported["error_map"]["max_absolute"].get<double>() == Approx(largest).epsilon(1e-9));
  CHECK(exported["error_map"]["vertices"] == scan.soup.positions.size());

  // The picture: a good share of the 800 x 800 pixels is the surface (not white).
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels = stbi_load((dir + "/s.png").c_str(), &width, &height, &channels, 3);
  REQUIRE(pixels != nullptr);
  CHECK(width == 800);
  int covered = 0;
  for (int i = 0; i < width * height; ++i)
    covered += pixels[3 * i] != 255 || pixels[3 * i + 1] != 255 || pixels[3 * i + 2] != 255;
  stbi_image_free(pixels);
  const double share = double(covered) / double(width * height);
  INFO("share of surface pixels " << share);
  CHECK(share > 0.1);
  CHECK(share < 0.95);
}

TEST_CASE("export: a failing output leaves every target as it was", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_export_all_or_none");
  const std::string model = triModel(dir);
  std::ofstream(dir + "/s.obj") << "old surface";
  // The picture comes last and cannot be written: the surface and the net must not change.
  const auto result = test::runCommand(test::cliPath() + " export " + model + " -o " + dir +
                                       "/s.obj --resolution 2 --control-net " + dir +
                                       "/net.obj --png " + dir + "/missing/s.png");
  CHECK(result.exitCode == 2);
  CHECK(test::fileText(dir + "/s.obj") == "old surface");
  CHECK(!std::filesystem::exists(dir + "/net.obj"));
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
  CHECK(files == 2);  // the model and the old surface
}
