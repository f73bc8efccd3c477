#include "mspline/io/write_mesh.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "mspline/io/read_mesh.h"
#include "mspline/structure/core/errors.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

namespace {

namespace fs = std::filesystem;
using mspline::io::MeshWriteOptions;
using mspline::io::readMesh;
using mspline::io::writeMesh;
using mspline::structure::PolygonSoup;
using Face = std::vector<std::int64_t>;
using UVs = std::vector<std::array<double, 2>>;

// Doubles that only survive with shortest-round-trip (or 17-digit) output.
PolygonSoup awkwardSoup() {
  PolygonSoup soup;
  soup.positions = {{0.1, 1.0 / 3.0, -0.0},
                    {std::acos(-1.0), 1e-300, -1e300},
                    {std::numeric_limits<double>::denorm_min(), 2.0 / 3.0, 123456789.123456789},
                    {-std::numeric_limits<double>::max(), std::nextafter(1.0, 2.0), 7}};
  soup.faces = {{0, 1, 2}, {0, 2, 3}, {1, 3, 2}};
  return soup;
}

bool bitIdentical(const std::vector<std::array<double, 3>>& a,
                  const std::vector<std::array<double, 3>>& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(std::array<double, 3>)) == 0;
}

}  // namespace

TEST_CASE("write_mesh: OBJ, OFF and PLY round trips are bit-exact", "[io]") {
  std::string dir = mspline::test::scratchDirectory("write_mesh_round_trip");
  PolygonSoup soup = awkwardSoup();
  struct Variant {
    std::string name;
    MeshWriteOptions options;
  };
  MeshWriteOptions ascii;
  ascii.binary = false;
  for (const Variant& v : {Variant{"m.obj", {}}, Variant{"m.off", {}}, Variant{"m.ply", {}},
                           Variant{"ascii.ply", ascii}}) {
    CAPTURE(v.name);
    std::string path = dir + "/" + v.name;
    writeMesh(path, soup, v.options);
    auto back = readMesh(path);
    CHECK(bitIdentical(back.soup.positions, soup.positions));
    CHECK(back.soup.faces == soup.faces);
    CHECK(back.warnings.empty());
  }
  CHECK(mspline::test::fileText(dir + "/m.ply").find("format binary_little_endian 1.0") !=
        std::string::npos);
  CHECK(mspline::test::fileText(dir + "/ascii.ply").find("format ascii 1.0") != std::string::npos);
}

TEST_CASE("write_mesh: non-finite coordinates are written as such, and read back refused", "[io]") {
  std::string dir = mspline::test::scratchDirectory("write_mesh_non_finite");
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {std::nan(""), HUGE_VAL, -HUGE_VAL}, {1, 0, 0}};
  soup.faces = {{0, 1, 2}};
  for (const char* name : {"nan.off", "nan.obj"}) {
    std::string path = dir + "/" + name;
    writeMesh(path, soup);
    CHECK_THAT(mspline::test::fileText(path), Catch::Contains("nan inf -inf"));
    CHECK_THROWS_WITH(readMesh(path), Catch::Contains(path) && Catch::Contains("vertex 1 "));
  }
}

TEST_CASE("write_mesh: OBJ writes per-corner UVs when asked", "[io]") {
  std::string dir = mspline::test::scratchDirectory("write_mesh_uvs");
  PolygonSoup soup = awkwardSoup();
  soup.cornerUVs = {{{0, 0}, {0.1, 0.2}, {1.0 / 3.0, 1}},
                    {{0, 0}, {1.0 / 3.0, 1}, {0.5, 0.5}},
                    {{0.7, 0.7}, {0.9, 0.1}, {1e-20, 1}}};
  std::string path = dir + "/uv.obj";
  writeMesh(path, soup);
  auto back = readMesh(path);
  CHECK(bitIdentical(back.soup.positions, soup.positions));
  CHECK(back.soup.faces == soup.faces);
  CHECK(back.soup.cornerUVs == soup.cornerUVs);

  MeshWriteOptions noUVs;
  noUVs.writeUVs = false;
  writeMesh(path, soup, noUVs);
  CHECK(mspline::test::fileText(path).find("vt") == std::string::npos);
  CHECK(readMesh(path).soup.cornerUVs.empty());

  soup.cornerUVs.pop_back();
  CHECK_THROWS_AS(writeMesh(dir + "/mismatch.obj", soup), mspline::structure::InputError);
  CHECK(!fs::exists(dir + "/mismatch.obj"));
}

TEST_CASE("write_mesh: binary STL rounds positions to float", "[io]") {
  std::string dir = mspline::test::scratchDirectory("write_mesh_stl");
  PolygonSoup soup = awkwardSoup();
  std::string path = dir + "/m.stl";
  // -1e300 and -max would become infinite floats.
  CHECK_THROWS_WITH(writeMesh(path, soup), Catch::Contains("m.stl") && Catch::Contains("vertex 1"));
  CHECK(!fs::exists(path));
  soup.positions[0] = {0.1, 0.2, 0.3};
  soup.positions[1][2] = -1e30;
  soup.positions[3] = {1, 2, 3};
  writeMesh(path, soup);
  CHECK(fs::file_size(path) == 84 + 50 * soup.faces.size());
  CHECK(mspline::test::fileText(path).compare(0, 5, "solid") != 0);
  auto back = readMesh(path).soup;
  REQUIRE(back.faces.size() == soup.faces.size());
  CHECK(back.positions.size() == soup.positions.size());  // shared corners merged again
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    for (std::size_t k = 0; k < 3; ++k) {
      const auto& written = soup.positions[static_cast<std::size_t>(soup.faces[f][k])];
      const auto& read = back.positions[static_cast<std::size_t>(back.faces[f][k])];
      for (int c = 0; c < 3; ++c) CHECK(read[c] == static_cast<float>(written[c]));
    }
  }

  PolygonSoup quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.faces = {{0, 1, 2, 3}};
  CHECK_THROWS_WITH(writeMesh(dir + "/quad.stl", quad),
                    Catch::Contains("quad.stl") && Catch::Contains("triangles only"));
  CHECK(!fs::exists(dir + "/quad.stl"));
}

TEST_CASE("write_mesh: a TriMesh round-trips through every format", "[io]") {
  std::string dir = mspline::test::scratchDirectory("write_mesh_trimesh");
  auto mesh = mspline::test::torus(24, 12);
  for (const char* name : {"torus.obj", "torus.off", "torus.ply", "torus.stl"}) {
    CAPTURE(name);
    std::string path = dir + "/" + name;
    writeMesh(path, mesh);
    auto back = mspline::structure::toTriMesh(readMesh(path).soup);
    REQUIRE(back.n_vertices() == mesh.n_vertices());
    REQUIRE(back.n_faces() == mesh.n_faces());
    bool stl = std::string(name) == "torus.stl";
    // STL renumbers vertices in order of first use; the others keep the order.
    for (auto f : mesh.faces()) {
      auto original = mesh.fv_range(f).begin();
      for (auto v : back.fv_range(back.face_handle(f.idx()))) {
        auto expected = mesh.point(*original++);
        for (int c = 0; c < 3; ++c) {
          if (stl) {
            CHECK(back.point(v)[c] == static_cast<float>(expected[c]));
          } else {
            CHECK(back.point(v)[c] == expected[c]);
          }
        }
      }
    }
  }
}

TEST_CASE("write_mesh: refusals leave nothing behind", "[io]") {
  std::string dir = mspline::test::scratchDirectory("write_mesh_refusals");
  PolygonSoup soup = awkwardSoup();
  soup.faces.push_back({0, 1, 4});
  CHECK_THROWS_AS(writeMesh(dir + "/bad.off", soup), mspline::structure::InputError);
  CHECK_THROWS_WITH(writeMesh(dir + "/bad.off", soup),
                    Catch::Contains("bad.off") && Catch::Contains("face 3"));
  CHECK_THROWS_AS(writeMesh(dir + "/m.xyz", awkwardSoup()), mspline::structure::InputError);
  CHECK_THROWS_AS(writeMesh(dir + "/missing/m.off", awkwardSoup()), mspline::structure::IoError);
  CHECK_THROWS_WITH(writeMesh(dir + "/missing/m.off", awkwardSoup()),
                    Catch::Contains(dir + "/missing/m.off"));
  CHECK(fs::is_empty(dir));
}

TEST_CASE("write_mesh: per-vertex normals, texture coordinates and colors", "[io]") {
  std::string dir = mspline::test::scratchDirectory("write_mesh_attributes");
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  soup.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  mspline::io::VertexAttributes attributes;
  attributes.normals = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0.6, 0, 0.8}};
  attributes.uvs = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0.5}};
  attributes.colors = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {1, 2, 3}};
  writeMesh(dir + "/a.obj", soup, attributes);
  const std::string obj = mspline::test::fileText(dir + "/a.obj");
  CHECK(obj.find("vt 0.5 0.5\n") != std::string::npos);
  CHECK(obj.find("vn 0.6 0 0.8\n") != std::string::npos);
  CHECK(obj.find("f 2/2/2 3/3/3 4/4/4\n") != std::string::npos);
  MeshWriteOptions ascii;
  ascii.binary = false;
  writeMesh(dir + "/a.ply", soup, attributes, ascii);
  const std::string ply = mspline::test::fileText(dir + "/a.ply");
  CHECK(ply.find("property double nz\nproperty uchar red\nproperty uchar green\nproperty uchar "
                 "blue\nelement face 4\n") != std::string::npos);
  CHECK(ply.find("\n0 0 1 0.6 0 0.8 1 2 3\n") != std::string::npos);
  // Binary and ASCII read back the same positions and faces (the reader skips the attributes).
  writeMesh(dir + "/b.ply", soup, attributes);
  for (const char* name : {"/a.obj", "/a.ply", "/b.ply"}) {
    const auto read = readMesh(dir + name);
    CHECK(read.soup.positions == soup.positions);
    CHECK(read.soup.faces == soup.faces);
  }
  // Normals only: OBJ faces `v//n`.
  mspline::io::VertexAttributes normalsOnly;
  normalsOnly.normals = attributes.normals;
  writeMesh(dir + "/n.obj", soup, normalsOnly);
  CHECK(mspline::test::fileText(dir + "/n.obj").find("f 1//1 3//3 2//2\n") != std::string::npos);
  attributes.normals.pop_back();
  CHECK_THROWS_AS(writeMesh(dir + "/c.ply", soup, attributes), mspline::structure::InputError);
  CHECK(!fs::exists(dir + "/c.ply"));
}

TEST_CASE("write_mesh: points and lines as OBJ", "[io]") {
  std::string dir = mspline::test::scratchDirectory("write_mesh_lines");
  mspline::io::writeObjLines(dir + "/l.obj", {{0, 0, 0}, {1, 2, 3}}, {{0, 1}});
  CHECK(mspline::test::fileText(dir + "/l.obj") == "v 0 0 0\nv 1 2 3\nl 1 2\n");
  CHECK_THROWS_AS(mspline::io::writeObjLines(dir + "/m.obj", {{0, 0, 0}}, {{0, 1}}),
                  mspline::structure::InputError);
  CHECK_THROWS_AS(mspline::io::writeObjLines(dir + "/m.ply", {{0, 0, 0}}, {}),
                  mspline::structure::InputError);
}
