#include "mspline/io/read_mesh.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "mspline/io/write_mesh.h"
#include "mspline/structure/core/errors.h"
#include "support/test_data.h"

namespace {

namespace fs = std::filesystem;
using mspline::io::readMesh;
using mspline::structure::InputError;
using mspline::structure::IoError;
using Face = std::vector<std::int64_t>;
using Position = std::array<double, 3>;

std::string writeFile(const std::string& dir, const std::string& name, const std::string& bytes) {
  std::string path = dir + "/" + name;
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  return path;
}

// Appends a value's bytes in little- or big-endian order, independently of the reader's code.
template <typename T>
void put(std::string& bytes, T value, bool bigEndian = false) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i)
    bytes += static_cast<char>(raw[bigEndian ? sizeof(T) - 1 - i : i]);
}

std::string binaryStl(const std::string& header80, const std::vector<std::array<float, 9>>& tris,
                      std::uint32_t declared) {
  std::string bytes = header80;
  bytes.resize(80, ' ');
  put(bytes, declared);
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) put(bytes, 0.0f);
    for (float c : t) put(bytes, c);
    put(bytes, std::uint16_t{0});
  }
  return bytes;
}

// A tetrahedron as STL stores it: 4 triangles, 12 corners, 4 distinct points.
const std::vector<std::array<float, 9>> kTetrahedron = {{0, 0, 0, 0, 1, 0, 1, 0, 0},
                                                        {0, 0, 0, 0, 0, 1, 0, 1, 0},
                                                        {0, 0, 0, 1, 0, 0, 0, 0, 1},
                                                        {1, 0, 0, 0, 1, 0, 0, 0, 1}};

void checkTetrahedron(const mspline::structure::PolygonSoup& soup) {
  REQUIRE(soup.positions.size() == 4);
  REQUIRE(soup.faces.size() == 4);
  for (std::size_t f = 0; f < 4; ++f) {
    REQUIRE(soup.faces[f].size() == 3);
    for (std::size_t k = 0; k < 3; ++k) {
      const Position& p = soup.positions[static_cast<std::size_t>(soup.faces[f][k])];
      CHECK(p[0] == kTetrahedron[f][3 * k]);
      CHECK(p[1] == kTetrahedron[f][3 * k + 1]);
      CHECK(p[2] == kTetrahedron[f][3 * k + 2]);
    }
  }
}

}  // namespace

TEST_CASE("read_mesh: OFF with comments, colors and counts on the header line", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_off");
  std::string path = writeFile(dir, "colored.off",
                               "# leading comment\n"
                               "COFF 4 2 5\n"
                               "\n"
                               "0 0 0 0.9 0 0 1 # red\r\n"
                               "1 0 0 0 0.9 0#blue\n"
                               "  # a comment between vertices\n"
                               "0 1 0   1 1 1\n"
                               "+1.5 -2.5e3 .25\n"
                               "3 0 1 2 255 0 0\n"
                               "3 2 1 3\n");
  auto result = readMesh(path);
  CHECK(result.soup.sourceName == path);
  CHECK(result.warnings.empty());
  REQUIRE(result.soup.positions.size() == 4);
  CHECK(result.soup.positions[1] == Position{1, 0, 0});
  CHECK(result.soup.positions[3] == Position{1.5, -2500, 0.25});
  CHECK(result.soup.faces == std::vector<Face>{{0, 1, 2}, {2, 1, 3}});
  CHECK(result.soup.cornerUVs.empty());
}

TEST_CASE("read_mesh: OFF polygons are fan-triangulated with a warning", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_off_quads");
  std::string path = writeFile(dir, "quads.off",
                               "OFF\n6 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n2 1 0\n"
                               "4 0 1 2 3\n4 1 4 5 2\n");
  auto result = readMesh(path);
  CHECK(result.soup.faces == std::vector<Face>{{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}});
  CHECK(result.warnings == std::vector<std::string>{"2 polygons were triangulated"});
}

TEST_CASE("read_mesh: geometrically bad content is stored as-is for validation", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_bad_content");
  std::string off = writeFile(dir, "bad.off",
                              "OFF\n3 4 0\n0 0 0\n1 0 1\n0 1 0\n"
                              "3 0 1 7\n3 0 -2 1\n2 0 1\n0\n");
  auto result = readMesh(off);
  REQUIRE(result.soup.positions.size() == 3);
  CHECK(result.soup.faces == std::vector<Face>{{0, 1, 7}, {0, -2, 1}, {0, 1}, {}});

  // An OBJ relative index reaching before the first vertex stays negative; index 0 is invalid
  // and becomes -1.
  std::string obj = writeFile(dir, "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 -5\nf 0 1 2\n");
  CHECK(readMesh(obj).soup.faces == std::vector<Face>{{0, 1, -3}, {-1, 0, 1}});

  // Values below double's range round to zero, as strtod would.
  std::string tiny = writeFile(dir, "tiny.off", "OFF\n1 0 0\n1e-999 -1e-999 1\n");
  CHECK(readMesh(tiny).soup.positions[0] == Position{0.0, 0.0, 1.0});
}

// Issue 17: a NaN vertex passed through to `export --error-map` as a distance of 0.
TEST_CASE(
    "read_mesh: a coordinate that is not finite is refused in every format, naming the "
    "file and the vertex",
    "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_non_finite");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (float c : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, nan}) put(ply, c);
  put(ply, std::uint8_t{3});
  for (int v : {0, 1, 2}) put(ply, v);
  const std::vector<std::array<std::string, 3>> cases = {
      {"inf.off", "OFF\n3 1 0\n0 0 0\ninf -inf 1\n0 1 0\n3 0 1 2\n", "vertex 1 "},
      {"huge.off", "OFF\n3 1 0\n0 0 1e999\n1 0 0\n0 1 0\n3 0 1 2\n", "vertex 0 "},
      {"w.off", "4OFF\n3 1 0\n0 0 0 1\n1 0 0 1\n0 1 0 0\n3 0 1 2\n", "vertex 2 "},
      {"nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n", "vertex 2 "},
      {"nan.ply", ply, "vertex 2 "},
      {"inf.stl", binaryStl("", {{0, 0, 0, 1, 0, 0, 0, inf, 0}}, 1), "vertex 2 "},
  };
  for (const auto& [name, bytes, vertex] : cases) {
    const std::string path = writeFile(dir, name, bytes);
    INFO(name);
    CHECK_THROWS_AS(readMesh(path), InputError);
    CHECK_THROWS_WITH(readMesh(path), Catch::Contains(path) && Catch::Contains(vertex) &&
                                          Catch::Contains("not finite"));
  }
}

TEST_CASE("read_mesh: OBJ face forms, relative indices and per-corner UVs", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_obj");
  std::string path = writeFile(dir, "uv.obj",
                               "# exported\nmtllib scene.mtl\no square\ng group\ns 1\n"
                               "v 0 0 0\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0 0.5 0.5 0.5\n"
                               "vn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl paper\n"
                               "f 1/1/1 2/2/1 3/3/1\n"
                               "f -4/-4 -2/-2 -1/-1\n"
                               "l 1 2\n");
  auto result = readMesh(path);
  CHECK(result.warnings.empty());
  REQUIRE(result.soup.positions.size() == 4);
  CHECK(result.soup.positions[2] == Position{1, 1, 0});
  CHECK(result.soup.faces == std::vector<Face>{{0, 1, 2}, {0, 2, 3}});
  using UVs = std::vector<std::array<double, 2>>;
  REQUIRE(result.soup.cornerUVs.size() == 2);
  CHECK(result.soup.cornerUVs[0] == UVs{{0, 0}, {1, 0}, {1, 1}});
  CHECK(result.soup.cornerUVs[1] == UVs{{0, 0}, {1, 1}, {0, 1}});

  SECTION("a quad with UVs is split with its UVs") {
    std::string quad = writeFile(dir, "quad.obj",
                                 "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                 "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
    auto split = readMesh(quad);
    CHECK(split.soup.faces == std::vector<Face>{{0, 1, 2}, {0, 2, 3}});
    CHECK(split.soup.cornerUVs ==
          std::vector<UVs>{{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}});
    CHECK(split.warnings == std::vector<std::string>{"1 polygon was triangulated"});
  }
  SECTION("UVs on only some faces are dropped with a warning") {
    std::string mixed = writeFile(dir, "mixed.obj",
                                  "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\n"
                                  "f 1/1 2/1 3/1\nf 1//1 3 4\n");
    auto partial = readMesh(mixed);
    CHECK(partial.soup.faces == std::vector<Face>{{0, 1, 2}, {0, 2, 3}});
    CHECK(partial.soup.cornerUVs.empty());
    REQUIRE(partial.warnings.size() == 1);
    CHECK_THAT(partial.warnings[0], Catch::Contains("texture coordinates ignored"));
  }
}

TEST_CASE("read_mesh: ASCII PLY skips other properties, lists and elements", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_ply_ascii");
  std::string path = writeFile(dir, "colored.ply",
                               "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\n"
                               "element vertex 4\r\nproperty uchar red\r\nproperty float x\r\n"
                               "property list uchar float extra\r\n"
                               "property double y\r\nproperty int z\r\n"
                               "element face 2\r\nproperty int label\r\n"
                               "property list uint8 uint32 vertex_index\r\n"
                               "element edge 1\r\nproperty list uchar int ends\r\nend_header\r\n"
                               "255 0 2 7 8 0 0\r\n0 1.5 0 0 -1\r\n1 0 1 9 0.25 3\r\n4 1 0 0 2\r\n"
                               "7 3 0 1 2\r\n8 3 0 2 3\r\n2 0 1\r\n");
  auto result = readMesh(path);
  REQUIRE(result.soup.positions.size() == 4);
  CHECK(result.soup.positions[0] == Position{0, 0, 0});
  CHECK(result.soup.positions[1] == Position{1.5, 0, -1});
  CHECK(result.soup.positions[2] == Position{0, 0.25, 3});
  CHECK(result.soup.positions[3] == Position{1, 0, 2});
  CHECK(result.soup.faces == std::vector<Face>{{0, 1, 2}, {0, 2, 3}});
}

TEST_CASE("read_mesh: binary PLY in both byte orders and all scalar types", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_ply_binary");
  const std::vector<Position> points = {{0.1, -2, 3}, {1e-7, 1e10, -4}, {-0.5, 7, 0}};
  for (bool big : {false, true}) {
    std::string bytes = std::string("ply\nformat ") +
                        (big ? "binary_big_endian" : "binary_little_endian") +
                        " 1.0\nelement vertex 3\nproperty int8 flag\nproperty double x\n"
                        "property float y\nproperty list ushort char junk\nproperty short z\n"
                        "element face 2\nproperty list uchar int vertex_indices\n"
                        "property float64 quality\n"
                        "element edge 1\nproperty list int uint16 ends\nproperty uint id\n"
                        "end_header\n";
    for (const Position& p : points) {
      put(bytes, std::int8_t{-1}, big);
      put(bytes, p[0], big);
      put(bytes, static_cast<float>(p[1]), big);
      put(bytes, std::uint16_t{2}, big);
      put(bytes, std::int8_t{5}, big);
      put(bytes, std::int8_t{-5}, big);
      put(bytes, static_cast<std::int16_t>(p[2]), big);
    }
    for (const Face& face : {Face{0, 1, 2}, Face{2, 1, 0, 5}}) {
      put(bytes, static_cast<std::uint8_t>(face.size()), big);
      for (std::int64_t index : face) put(bytes, static_cast<std::int32_t>(index), big);
      put(bytes, 0.75, big);
    }
    put(bytes, std::int32_t{2}, big);
    put(bytes, std::uint16_t{0}, big);
    put(bytes, std::uint16_t{1}, big);
    put(bytes, std::uint32_t{99}, big);

    auto result = readMesh(writeFile(dir, big ? "big.ply" : "little.ply", bytes));
    REQUIRE(result.soup.positions.size() == 3);
    for (std::size_t v = 0; v < 3; ++v) {
      CHECK(result.soup.positions[v][0] == points[v][0]);
      CHECK(result.soup.positions[v][1] == static_cast<float>(points[v][1]));
      CHECK(result.soup.positions[v][2] == points[v][2]);
    }
    CHECK(result.soup.faces == std::vector<Face>{{0, 1, 2}, {2, 1, 0}, {2, 0, 5}});
    CHECK(result.warnings == std::vector<std::string>{"1 polygon was triangulated"});
  }
}

TEST_CASE("read_mesh: STL ASCII and binary, shared corners merged", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_stl");
  SECTION("ASCII") {
    std::string text = "solid tetra\n";
    for (const auto& t : kTetrahedron) {
      text += "  facet normal 0 0 0\n    outer loop\n";
      for (int k = 0; k < 3; ++k)
        text += "      vertex " + std::to_string(t[3 * k]) + " " + std::to_string(t[3 * k + 1]) +
                " " + std::to_string(t[3 * k + 2]) + "\n";
      text += "    endloop\n  endfacet\n";
    }
    text += "endsolid tetra\n";
    checkTetrahedron(readMesh(writeFile(dir, "ascii.stl", text)).soup);
  }
  SECTION("binary") {
    auto bytes = binaryStl("exported by a tool", kTetrahedron, 4);
    checkTetrahedron(readMesh(writeFile(dir, "binary.STL", bytes)).soup);
  }
  SECTION("binary whose header starts with 'solid'") {
    auto bytes = binaryStl("solid but binary", kTetrahedron, 4);
    checkTetrahedron(readMesh(writeFile(dir, "solid.stl", bytes)).soup);
  }
  SECTION("-0 and +0 are the same point") {
    auto tris = kTetrahedron;
    tris[3][1] = -0.0f;
    checkTetrahedron(readMesh(writeFile(dir, "zero.stl", binaryStl("", tris, 4))).soup);
  }
}

TEST_CASE("read_mesh: malformed files throw InputError naming the file and line", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_malformed");
  struct Case {
    std::string name;
    std::string content;
    std::string where;  // expected "name:line" prefix, or the bare name for binary formats
    std::string says;   // a phrase the message must contain
  };
  std::string lyingPly =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
      "property float x\nproperty float y\nproperty float z\nend_header\n";
  // The face's list says 3 indices, but only one follows.
  std::string truncatedPly =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n" +
      std::string(12, '\0') + "\x03" + std::string(4, '\0');
  std::string shortStl = binaryStl("header", kTetrahedron, 5);
  const std::vector<Case> cases = {
      {"empty.off", "", "empty.off", "empty"},
      {"empty.ply", "", "empty.ply", "empty"},
      {"blank.off", "  \n# nothing\n", "blank.off:3", "no OFF header"},
      {"noheader.off", "3 1 0\n0 0 0\n", "noheader.off:1", "OFF header"},
      {"garbage.off", "OFF\n2 0 0\n0 0 0\n0 zero 0\n", "garbage.off:4", "'zero'"},
      {"trailing.off", "OFF\n1 0 0\n0 0 1.5x\n", "trailing.off:3", "'1.5x'"},
      {"short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "short.off:6", "end of the line"},
      {"fewverts.off", "OFF\n3 0 0\n0.0000001 0 0\n1.0000001 0 0\n", "fewverts.off",
       "2 of 3 vertices"},
      {"fewfaces.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "fewfaces.off",
       "1 of 2 faces"},
      {"lying.off", "OFF\n1000000000000 1 0\n0 0 0\n3 0 0 0\n", "lying.off:2", "header declares"},
      {"negative.off", "OFF\n-3 1 0\n", "negative.off:2", "negative vertex count"},
      {"dimension.off", "nOFF\n4\n1 0 0\n0 0 0 0\n", "dimension.off:2", "3-dimensional"},
      {"facesize.off", "OFF\n1 1 0\n0 0 0\n99999999999 0\n", "facesize.off:4", "face declares"},
      {"binary.off", "OFF BINARY\n", "binary.off:1", "binary OFF"},
      {"garbage.obj", "v 1 2 x\n", "garbage.obj:1", "'x'"},
      {"binary.obj", std::string("v 0 0 0\n\x01\x02\xff", 11), "binary.obj:2",
       "not an OBJ statement"},
      {"slash.obj", "v 0 0 0\nf 1/ 1/ 1/\n", "slash.obj:2", "texture coordinate index"},
      {"magic.ply", "plx\n", "magic.ply:1", "not a PLY file"},
      {"noend.ply", "ply\nformat ascii 1.0\nelement vertex 0\n", "noend.ply", "end_header"},
      {"format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", "format.ply:2",
       "unknown PLY format"},
      {"novertex.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n", "novertex.ply",
       "no vertex element"},
      {"noz.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "end_header\n0 0\n",
       "noz.ply", "no property z"},
      {"lying.ply", lyingPly, "lying.ply", "header declares 1000000000000 vertex"},
      {"truncated.ply", truncatedPly, "truncated.ply", "face 0 of 1"},
      {"asciishort.ply",
       "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
       "property float y\nproperty float z\nend_header\n0.0 0.0 0.0\n1.0 1.0\n",
       "asciishort.ply:10", "vertex 1 of 2"},
      {"truncated.stl", shortStl, "truncated.stl", "declares 5 triangles"},
      {"tiny.stl", "abc", "tiny.stl", "too short"},
      {"cut.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0", "cut.stl:5",
       "truncated"},
      {"word.stl",
       "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
       "vortex 0 1 0\nendloop\nendfacet\nendsolid\n",
       "word.stl:6", "'vortex'"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    std::string path = writeFile(dir, c.name, c.content);
    try {
      readMesh(path);
      FAIL("no exception");
    } catch (const InputError& error) {
      std::string message = error.what();
      CHECK_THAT(message, Catch::Contains(dir + "/" + c.where));
      CHECK_THAT(message, Catch::Contains(c.says));
    }
  }
}

TEST_CASE("read_mesh: every truncation or corruption reads or throws InputError", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_damage");
  mspline::structure::PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1.5, -0.25, 1e-3}, {0, 1, 0}, {0.125, 0.5, 2}};
  soup.faces = {{0, 1, 2}, {0, 2, 3}, {1, 3, 2}};
  soup.cornerUVs = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}, {{1, 0}, {0, 1}, {1, 1}}};
  mspline::io::MeshWriteOptions ascii;
  ascii.binary = false;
  std::vector<std::string> samples;
  for (const char* name : {"s.obj", "s.off", "s.ply", "a.ply", "s.stl"}) {
    std::string path = dir + "/" + name;
    mspline::io::writeMesh(path, soup,
                           std::string(name) == "a.ply" ? ascii : mspline::io::MeshWriteOptions{});
    samples.push_back(path);
  }
  samples.push_back(writeFile(dir, "a.stl",
                              "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                              "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n"));
  std::mt19937 random(12345);
  const std::string replacements = std::string("\0 \n#/-.9x\xff", 10);
  std::size_t reads = 0;
  std::size_t rejected = 0;
  auto attempt = [&](const std::string& path, const std::string& bytes) {
    writeFile(dir, "damaged" + fs::path(path).extension().string(), bytes);
    ++reads;
    try {
      readMesh(dir + "/damaged" + fs::path(path).extension().string());
    } catch (const InputError&) {
      ++rejected;
    }
  };
  for (const std::string& path : samples) {
    CAPTURE(path);
    std::ifstream in(path, std::ios::binary);
    std::ostringstream content;
    content << in.rdbuf();
    const std::string full = content.str();
    REQUIRE(readMesh(path).soup.faces.size() >= 1);
    for (std::size_t length = 0; length < full.size(); ++length)
      attempt(path, full.substr(0, length));
    for (int trial = 0; trial < 300; ++trial) {
      std::string bytes = full;
      bytes[random() % bytes.size()] = replacements[random() % replacements.size()];
      attempt(path, bytes);
    }
  }
  // Most damage is detected; some (a cut after a complete face, a changed digit) is not.
  CHECK(rejected > reads / 2);
  CHECK(rejected < reads);
}

TEST_CASE("read_mesh: unknown extension, missing file and directory", "[io]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_system");
  std::string unknown = writeFile(dir, "mesh.xyz", "OFF\n0 0 0\n");
  CHECK_THROWS_AS(readMesh(unknown), InputError);
  CHECK_THROWS_WITH(readMesh(unknown), Catch::Contains("mesh.xyz") && Catch::Contains(".xyz"));
  CHECK_THROWS_AS(readMesh(dir + "/noext"), InputError);
  CHECK(mspline::io::meshFormatFromPath("a/b.Ply") == mspline::io::MeshFormat::Ply);

  std::string missing = dir + "/missing.off";
  CHECK_THROWS_AS(readMesh(missing), IoError);
  CHECK_THROWS_WITH(readMesh(missing),
                    Catch::Contains(missing) && Catch::Contains(std::strerror(ENOENT)));
  std::filesystem::create_directory(dir + "/folder.obj");
  CHECK_THROWS_AS(readMesh(dir + "/folder.obj"), IoError);
  CHECK_THROWS_WITH(readMesh(dir + "/folder.obj"), Catch::Contains(std::strerror(EISDIR)));
}

TEST_CASE("read_mesh: real CGAL meshes give the header's counts", "[io]") {
  struct Expected {
    const char* name;
    std::size_t vertices;
    std::size_t faces;
  };
  for (Expected e : {Expected{"knot1.off", 3200, 6400}, Expected{"eight.off", 315, 634},
                     Expected{"bunny00.off", 37706, 75408}}) {
    CAPTURE(e.name);
    auto result = readMesh(mspline::test::realMeshPath(e.name));
    CHECK(result.soup.positions.size() == e.vertices);
    CHECK(result.soup.faces.size() == e.faces);
    CHECK(result.warnings.empty());
  }
}

TEST_CASE("read_mesh: every real mesh in the data directory reads", "[io]") {
  auto dir = std::filesystem::path(mspline::test::realMeshPath("knot1.off")).parent_path();
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::string path = entry.path().string();
    CAPTURE(path);
    auto result = readMesh(path);
    CHECK(!result.soup.positions.empty());
    std::size_t largest = 0;
    for (const Face& face : result.soup.faces) largest = std::max(largest, face.size());
    CHECK(largest <= 3);
    ++files;
  }
  CHECK(files > 100);
}

TEST_CASE("read_mesh: a 1M-face OFF reads quickly", "[io][slow]") {
  std::string dir = mspline::test::scratchDirectory("read_mesh_large");
  // A 708 x 707 grid of quads split in two: 1,000,000-ish triangles, about 500k vertices.
  const int nx = 708, ny = 707;
  mspline::structure::PolygonSoup soup;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      soup.positions.push_back({i * 0.0123456789, j * 0.0987654321, std::sin(i * 0.1) * 0.37});
  auto at = [&](int i, int j) { return static_cast<std::int64_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      soup.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      soup.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  std::string path = dir + "/large.off";
  auto start = std::chrono::steady_clock::now();
  mspline::io::writeMesh(path, soup);
  auto written = std::chrono::steady_clock::now();
  auto result = readMesh(path);
  auto read = std::chrono::steady_clock::now();
  using ms = std::chrono::duration<double, std::milli>;
  WARN("1M-face OFF (" << std::filesystem::file_size(path) / 1e6 << " MB): write "
                       << ms(written - start).count() << " ms, read " << ms(read - written).count()
                       << " ms");
  CHECK(result.soup.faces.size() == soup.faces.size());
  CHECK(result.soup.positions == soup.positions);
  CHECK(result.soup.faces == soup.faces);
}
