#include "mspline/io/spline_model_file.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "mspline/io/detail/byte_order.h"
#include "mspline/spline/subd/subd_fit_space.h"
#include "mspline/spline/tribspline/dms_spline.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/structure/core/errors.h"
#include "support/test_data.h"
#include "support/test_meshes.h"
#include "support/test_tmeshes.h"

using namespace mspline;

namespace {

namespace fs = std::filesystem;
using spline::SplineModel;

constexpr double kDenormMin = std::numeric_limits<double>::denorm_min();
constexpr int kCells = 4;  // flatTorusDomain(4): 16 vertices, 32 faces
constexpr int kDegree = 2;

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof(double)) == 0;
}

bool sameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index r = 0; r < a.rows(); ++r)
    for (Eigen::Index c = 0; c < a.cols(); ++c)
      if (!sameBits(a(r, c), b(r, c))) return false;
  return true;
}

std::vector<Eigen::Vector2d> cornersOf(const spline::SplineDomain& domain, int face) {
  const auto corners = spline::canonicalCorners(domain, face);
  return {corners.begin(), corners.end()};
}

// A torus sampled at the vertices of flatTorusDomain(4, 0.2), with the domain's triangles, DMS
// knot clouds in every face's frame, random control points, and doubles that only survive a
// bit-exact format (negative zero, subnormals, 0.1, 1e300) scattered through every section.
SplineModel awkwardModel() {
  SplineModel model;
  model.domain = test::flatTorusDomain(kCells, 0.2);
  const int vertices = kCells * kCells;
  model.surfaceVertices.resize(vertices, 3);
  for (int v = 0; v < vertices; ++v) {
    const double turn = 2 * std::acos(-1.0) / kCells;
    const double a = turn * (v % kCells), b = turn * (v / kCells);
    model.surfaceVertices.row(v) << (1 + 0.4 * std::cos(b)) * std::cos(a),
        (1 + 0.4 * std::cos(b)) * std::sin(a), 0.4 * std::sin(b);
  }
  model.surfaceVertices(0, 0) = -0.0;
  model.surfaceVertices(1, 1) = kDenormMin;
  model.surfaceVertices(2, 2) = 0.1;
  model.surfaceVertices(3, 0) = 1e300;
  model.surfaceFaces = model.domain.faces;
  // Vertex v is corner 0 of face 2 v (the lower triangle of its cell).
  for (int v = 0; v < vertices; ++v)
    model.surfaceVertexLocations.push_back({2 * v, Eigen::Vector3d(1.0, 0.0, 0.0)});
  model.surfaceVertexLocations[1].barycentric << 1.0, -0.0, -kDenormMin;
  for (int d = 0; d < vertices; ++d) model.domainVertexSource.push_back(vertices - 1 - d);
  model.domain.cone[5] = 1;

  model.degree = kDegree;
  for (int f = 0; f < model.domain.faceCount(); ++f) {
    spline::KnotCloudOptions options;
    options.seed = std::uint64_t(f) + 1;
    const auto clouds =
        spline::generateKnotClouds(cornersOf(model.domain, f), {{0, 1, 2}}, kDegree, options);
    model.knots.push_back({clouds[0], clouds[1], clouds[2]});
  }
  model.knots[31][1][2] << -0.0, kDenormMin;
  model.knots[31][2][1] << 0.1, 1e300;

  const int rows = model.domain.faceCount() * (kDegree + 1) * (kDegree + 2) / 2;
  model.controlPoints.resize(rows, 3);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  for (Eigen::Index r = 0; r < rows; ++r)
    for (Eigen::Index c = 0; c < 3; ++c) model.controlPoints(r, c) = coordinate(random);
  model.controlPoints(0, 0) = -0.0;
  model.controlPoints(1, 1) = kDenormMin;
  model.controlPoints(2, 2) = 0.1;
  model.controlPoints(3, 0) = 1e300;
  model.controlPoints(4, 1) = -1e-310;
  model.controlPoints(5, 2) = std::numeric_limits<double>::max();
  return model;
}

// Byte offsets of the sections of awkwardModel()'s file, from the layout documented in
// io/spline_model_file.h.
struct Layout {
  static constexpr std::size_t vertices = kCells * kCells, faces = 2 * vertices;
  static constexpr std::size_t surfaceVertices = 16;
  static constexpr std::size_t surfaceFaces = surfaceVertices + 4 + 24 * vertices;
  // Version 3: the filled-face count (0) follows the faces.
  static constexpr std::size_t filled = surfaceFaces + 4 + 12 * faces;
  static constexpr std::size_t locations = filled + 4;
  static constexpr std::size_t domainVertices = locations + 28 * vertices;
  static constexpr std::size_t domainFaces = domainVertices + 4 + 5 * vertices;
  static constexpr std::size_t degree = domainFaces + 4 + 51 * faces;
  static constexpr std::size_t knots = degree + 4;
  static constexpr std::size_t controlPoints = knots + faces * 3 * (kDegree + 1) * 16;
  static constexpr std::size_t rows = faces * (kDegree + 1) * (kDegree + 2) / 2;
  static constexpr std::size_t size = controlPoints + 8 + rows * 3 * 8;
};

// The periodic grid gridTMesh(0..6, 0..5): a torus of 6 x 5 unit cells, 30 vertices and faces.
constexpr int kColumns = 6, kRows = 5;

// A torus sampled at the grid's vertices (two triangles per cell) on the T-spline of
// gridTMesh(0..6, 0..5, periodic both ways) with random control points and weights, and doubles
// that only survive a bit-exact format in every section.
SplineModel tsplineModel() {
  SplineModel model;
  model.kind = spline::SplineKind::TSpline;
  model.tmesh = spline::gridTMesh(test::unitKnots(kColumns), test::unitKnots(kRows), true, true);
  const int vertices = kColumns * kRows;
  const auto id = [](int i, int j) { return (j % kRows) * kColumns + i % kColumns; };
  model.surfaceVertices.resize(vertices, 3);
  for (int j = 0; j < kRows; ++j)
    for (int i = 0; i < kColumns; ++i) {
      const double a = 2 * std::acos(-1.0) * i / kColumns, b = 2 * std::acos(-1.0) * j / kRows;
      model.surfaceVertices.row(id(i, j)) << (1 + 0.4 * std::cos(b)) * std::cos(a),
          (1 + 0.4 * std::cos(b)) * std::sin(a), 0.4 * std::sin(b);
      model.surfaceFaces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      model.surfaceFaces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      // Even vertices as the corner (0, 0) of the cell above and right of them, odd ones as the
      // corner (1, 1) of the cell below and left (face ids are vertex ids of corner (0, 0)).
      if (id(i, j) % 2 == 0)
        model.surfaceVertexTMeshPoints.push_back({id(i, j), Eigen::Vector2d(0.0, 0.0)});
      else
        model.surfaceVertexTMeshPoints.push_back(
            {id(i + kColumns - 1, j + kRows - 1), Eigen::Vector2d(1.0, 1.0)});
    }
  model.surfaceVertices(0, 0) = -0.0;
  model.surfaceVertices(1, 1) = kDenormMin;
  model.surfaceVertices(3, 0) = 1e300;
  model.surfaceVertexTMeshPoints[0].position << -0.0, kDenormMin;

  const int basis = spline::TSplineSpace(model.tmesh).numBasis();
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0), weight(0.5, 2.0);
  model.weights.resize(basis);
  for (int i = 0; i < basis; ++i) model.weights(i) = weight(random);
  model.weights(3) = 0.1;
  model.weights(4) = kDenormMin;
  model.controlPoints.resize(basis, 3);
  for (int r = 0; r < basis; ++r)
    for (int c = 0; c < 3; ++c) model.controlPoints(r, c) = coordinate(random);
  model.controlPoints(0, 0) = -0.0;
  model.controlPoints(1, 1) = kDenormMin;
  model.controlPoints(2, 2) = 0.1;
  return model;
}

// Byte offsets of the sections of tsplineModel()'s file.
struct TLayout {
  static constexpr std::size_t vertices = kColumns * kRows, faces = 2 * vertices;
  static constexpr std::size_t surfaceFaces = 16 + 4 + 24 * vertices;
  static constexpr std::size_t filled = surfaceFaces + 4 + 12 * faces;
  static constexpr std::size_t tmesh = filled + 4;
  static constexpr std::size_t tmeshFaces = tmesh + 8;  // face f at tmeshFaces + faceBytes * f
  static constexpr std::size_t faceBytes = 4 + 4 * 20;
  static constexpr std::size_t points = tmeshFaces + vertices * faceBytes;
  static constexpr std::size_t weights = points + 20 * vertices;
  static constexpr std::size_t controlPoints = weights + 4 + 8 * vertices;
  static constexpr std::size_t size = controlPoints + 8 + 24 * vertices;
};

template <typename T>
std::string patched(std::string bytes, std::size_t offset, T value) {
  std::string encoded;
  io::detail::appendLittleEndian(encoded, value);
  return bytes.replace(offset, encoded.size(), encoded);
}

// A fresh file each time: rewriting a file truncated to zero makes ext4 flush it on close
// (auto_da_alloc), which costs milliseconds per file.
void writeBytes(const std::string& path, const std::string& bytes) {
  fs::remove(path);
  std::ofstream(path, std::ios::binary) << bytes;
}

// The message of the InputError that reading `path` throws ("" when it throws none).
std::string inputError(const std::string& path) {
  try {
    io::readSplineModel(path);
  } catch (const structure::InputError& error) {
    return error.what();
  }
  return "";
}

// Every cut of `bytes` short of its end, written to `path`, is an input error naming the file
// and saying it is empty or truncated.
void checkEveryTruncation(const std::string& path, const std::string& bytes) {
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    writeBytes(path, bytes.substr(0, length));
    const std::string message = inputError(path);
    INFO("cut at " << length << ": " << message);
    CHECK(message.find(path) != std::string::npos);
    CHECK(message.find(length == 0 ? "empty" : "truncated") != std::string::npos);
  }
}

// expect(name, bytes, words): the bytes, written to dir/name, are an input error naming the file
// with `words` in its message.
auto corruptFileCheck(const std::string& dir) {
  return [dir](const std::string& name, const std::string& bytes, const std::string& words) {
    const std::string path = dir + "/" + name;
    writeBytes(path, bytes);
    const std::string message = inputError(path);
    INFO(name << ": " << message);
    CHECK(message.find(path) != std::string::npos);
    CHECK(message.find(words) != std::string::npos);
  };
}

}  // namespace

TEST_CASE("spline_model_file: save, load and save again is lossless", "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file");
  const SplineModel model = awkwardModel();
  io::writeSplineModel(dir + "/a.msp", model);
  const std::string bytes = test::fileText(dir + "/a.msp");
  CHECK(bytes.size() == Layout::size);
  CHECK(bytes.compare(0, 8, "MSPLINE\x1A") == 0);

  const SplineModel back = io::readSplineModel(dir + "/a.msp");
  CHECK(back.kind == model.kind);
  CHECK(back.surfaceVertices == model.surfaceVertices);
  CHECK(sameBits(back.surfaceVertices, model.surfaceVertices));
  CHECK(std::signbit(back.surfaceVertices(0, 0)));
  CHECK(back.surfaceFaces == model.surfaceFaces);
  REQUIRE(back.surfaceVertexLocations.size() == model.surfaceVertexLocations.size());
  for (std::size_t v = 0; v < model.surfaceVertexLocations.size(); ++v) {
    CHECK(back.surfaceVertexLocations[v].face == model.surfaceVertexLocations[v].face);
    CHECK(sameBits(back.surfaceVertexLocations[v].barycentric,
                   model.surfaceVertexLocations[v].barycentric));
  }
  CHECK(back.domain.faces == model.domain.faces);
  CHECK(back.domain.sideLengths == model.domain.sideLengths);
  CHECK(back.domain.neighbour == model.domain.neighbour);
  CHECK(back.domain.neighbourSide == model.domain.neighbourSide);
  CHECK(back.domain.cone == model.domain.cone);
  CHECK(back.domainVertexSource == model.domainVertexSource);
  CHECK(back.degree == model.degree);
  REQUIRE(back.knots.size() == model.knots.size());
  for (std::size_t f = 0; f < model.knots.size(); ++f)
    for (std::size_t c = 0; c < 3; ++c) {
      REQUIRE(back.knots[f][c].size() == model.knots[f][c].size());
      for (std::size_t b = 0; b < model.knots[f][c].size(); ++b)
        CHECK(sameBits(back.knots[f][c][b], model.knots[f][c][b]));
    }
  CHECK(std::signbit(back.knots[31][1][2].x()));
  CHECK(back.knots[31][1][2].y() == kDenormMin);
  CHECK(back.controlPoints == model.controlPoints);
  CHECK(sameBits(back.controlPoints, model.controlPoints));
  CHECK(std::signbit(back.controlPoints(0, 0)));

  io::writeSplineModel(dir + "/b.msp", back);
  CHECK(test::fileText(dir + "/b.msp") == bytes);

  // The spline of face 1 in its frame evaluates to the same bits from the loaded model.
  const auto space = [](const SplineModel& m) {
    return spline::DmsSpace(cornersOf(m.domain, 1), {{0, 1, 2}},
                            spline::KnotClouds(m.knots[1].begin(), m.knots[1].end()));
  };
  const int perFace = (kDegree + 1) * (kDegree + 2) / 2;
  const auto corners = cornersOf(model.domain, 1);
  for (const Eigen::Vector3d& b :
       {Eigen::Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3), Eigen::Vector3d(0.7, 0.2, 0.1),
        Eigen::Vector3d(0.05, 0.15, 0.8)}) {
    const Eigen::Vector2d x = b(0) * corners[0] + b(1) * corners[1] + b(2) * corners[2];
    const auto before =
        space(model).evaluate(model.controlPoints.middleRows(perFace, perFace), 0, x, 2);
    const auto after =
        space(back).evaluate(back.controlPoints.middleRows(perFace, perFace), 0, x, 2);
    CHECK(sameBits(after.position, before.position));
    CHECK(sameBits(after.du, before.du));
    CHECK(sameBits(after.dv, before.dv));
    CHECK(sameBits(after.duu, before.duu));
    CHECK(sameBits(after.duv, before.duv));
    CHECK(sameBits(after.dvv, before.dvv));
  }
}

TEST_CASE("spline_model_file: every truncation is an input error naming the file", "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_cut");
  io::writeSplineModel(dir + "/good.msp", awkwardModel());
  const std::string bytes = test::fileText(dir + "/good.msp");
  REQUIRE(bytes.size() == Layout::size);
  const std::string path = dir + "/cut.msp";
  checkEveryTruncation(path, bytes);
  // Cuts name the section they fall in.
  writeBytes(path, bytes.substr(0, Layout::domainFaces + 100));
  CHECK(inputError(path).find("domain faces section") != std::string::npos);
  writeBytes(path, bytes.substr(0, Layout::size - 1));
  CHECK(inputError(path).find("control points section") != std::string::npos);
}

TEST_CASE("spline_model_file: corrupt files are input errors naming the file and the problem",
          "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_bad");
  io::writeSplineModel(dir + "/good.msp", awkwardModel());
  const std::string good = test::fileText(dir + "/good.msp");
  REQUIRE(good.size() == Layout::size);
  const auto expect = corruptFileCheck(dir);
  const auto nan = std::numeric_limits<double>::quiet_NaN();
  const auto huge = std::uint32_t(std::numeric_limits<std::int32_t>::max());

  expect("empty.msp", "", "the file is empty");
  expect("text.msp", "# not a model\n", "not an .msp spline model");
  expect("magic.msp", patched(good, 7, std::uint8_t('\n')), "not an .msp spline model");
  expect("version.msp", patched(good, 8, std::uint32_t(5)),
         "unsupported format version 5 (this mspline reads versions 1 to 4)");
  expect("version0.msp", patched(good, 8, std::uint32_t(0)), "unsupported format version 0");
  expect("kind.msp", patched(good, 12, std::uint32_t(4)), "unsupported spline kind 4");
  expect("kind0.msp", patched(good, 12, std::uint32_t(0)), "unsupported spline kind 0");
  // Read as a T-spline, the triangular B-spline's bytes do not make one.
  expect("kind2.msp", patched(good, 12, std::uint32_t(2)), "");
  // Counts that do not fit in the file are refused before anything is allocated for them.
  expect("vertices.msp", patched(good, Layout::surfaceVertices, huge),
         "needs 2147483647 surface vertices");
  expect("toomany.msp", patched(good, Layout::domainFaces, std::uint32_t(0xffffffff)),
         "more than the format holds");
  expect("degree.msp", patched(good, Layout::degree, std::int32_t(1 << 30)),
         "truncated or corrupt: the knots section needs 96 corners");
  expect("rows.msp",
         patched(patched(good, Layout::controlPoints, huge), Layout::controlPoints + 4, huge),
         "truncated or corrupt: the control points section");
  expect("negative.msp", patched(good, Layout::degree, std::int32_t(-1)), "degree -1 is below 1");
  // Counts that fit but do not match: a face's control points missing.
  const std::size_t perFace = (kDegree + 1) * (kDegree + 2) / 2;
  expect("short.msp",
         patched(good, Layout::controlPoints, std::uint32_t(Layout::rows - perFace))
             .substr(0, Layout::size - perFace * 3 * 8),
         std::to_string(Layout::rows - perFace) + " control points, but 32 domain faces");
  expect("trailing.msp", good + "x", "1 bytes after the last section");
  expect("index.msp", patched(good, Layout::surfaceFaces + 4 + 4, std::int32_t(99)),
         "surface face 0 has vertex 99, out of range (16 surface vertices)");
  expect("location.msp", patched(good, Layout::locations, std::int32_t(-1)),
         "surface vertex 0 lies in face -1, out of range");
  expect("source.msp", patched(good, Layout::domainVertices + 4 + 1, std::int32_t(16)),
         "domain vertex 0 is surface vertex 16, out of range");
  expect("cone.msp", patched(good, Layout::domainVertices + 4, std::uint8_t(2)), "cone flag 2");
  expect("nan.msp", patched(good, Layout::surfaceVertices + 4 + 8, nan),
         "coordinate 1 of surface vertex 0 is not finite");
  expect("knot.msp", patched(good, Layout::knots, std::numeric_limits<double>::infinity()),
         "coordinate 0 of knot 0 of corner 0 of domain face 0 is not finite");
  expect("control.msp", patched(good, Layout::size - 8, -nan),
         "coordinate 2 of control point " + std::to_string(Layout::rows - 1) + " is not finite");
  // The domain is checked by spline::validateDomain: a neighbour out of range, a side whose two
  // faces disagree on its length.
  const std::size_t neighbourOfFace0 = Layout::domainFaces + 4 + 12 + 24;
  expect("neighbour.msp", patched(good, neighbourOfFace0, std::int32_t(1000)),
         "the neighbour across side 0 of domain face 0 does not point back");
  expect("length.msp", patched(good, Layout::domainFaces + 4 + 12, 1.5),
         "side 0 of domain face 0 has two lengths");
  expect("side.msp", patched(good, neighbourOfFace0 + 12, std::uint8_t(3)), "does not point back");
}

// The files of issue 17 that the reader accepted and check or export then crashed on (or wrote an
// empty mesh from).
TEST_CASE(
    "spline_model_file: empty models and control points of other than 3 coordinates are "
    "refused",
    "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_empty");
  io::writeSplineModel(dir + "/good.msp", awkwardModel());
  const std::string good = test::fileText(dir + "/good.msp");
  REQUIRE(good.size() == Layout::size);
  const auto expect = corruptFileCheck(dir);
  const auto u32 = [](std::uint32_t value) { return patched(std::string(4, '\0'), 0, value); };

  // 48 bytes: the header, then every count 0 (degree 1, control points 0 x 3).
  const std::string empty =
      good.substr(0, 16) + u32(0) + u32(0) + u32(0) + u32(0) + u32(0) + u32(1) + u32(0) + u32(3);
  REQUIRE(empty.size() == 48);
  expect("empty-model.msp", empty, "the model has no surface faces");
  // The surface kept, the domain emptied.
  expect("no-domain.msp",
         good.substr(0, Layout::domainFaces) + u32(0) + u32(kDegree) + u32(0) + u32(3),
         "the domain has no faces");
  // The control points' columns 0, 1, 2 and 4 (their values as many as the columns ask for).
  const std::string values = good.substr(Layout::controlPoints + 8);
  for (std::uint32_t columns : {0u, 1u, 2u, 4u}) {
    std::string bytes =
        patched(good.substr(0, Layout::controlPoints + 8), Layout::controlPoints + 4, columns);
    bytes += std::string(Layout::rows * columns * 8, '\0');
    expect("columns" + std::to_string(columns) + ".msp", bytes,
           "control points have " + std::to_string(columns) +
               " coordinates, triangular B-splines need 3");
  }
}

TEST_CASE("spline_model_file: unreadable and unwritable paths, models the format refuses", "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_paths");
  CHECK_THROWS_AS(io::readSplineModel(dir + "/missing.msp"), structure::IoError);
  CHECK_THROWS_AS(io::readSplineModel(dir), structure::IoError);
  CHECK_THROWS_WITH(io::readSplineModel(dir + "/missing.msp"),
                    Catch::Contains(dir + "/missing.msp"));

  const SplineModel model = awkwardModel();
  CHECK_THROWS_AS(io::writeSplineModel(dir + "/no/such/dir/a.msp", model), structure::IoError);
  CHECK_FALSE(fs::exists(dir + "/no"));

  // A model the reader would refuse is not written, and an existing file stays as it was.
  const std::string path = dir + "/a.msp";
  io::writeSplineModel(path, model);
  const std::string before = test::fileText(path);
  SplineModel broken = model;
  broken.controlPoints(7, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(io::writeSplineModel(path, broken),
                    Catch::Contains("cannot write '" + path + "'") &&
                        Catch::Contains("coordinate 1 of control point 7 is not finite"));
  broken = model;
  broken.knots.pop_back();
  CHECK_THROWS_WITH(io::writeSplineModel(dir + "/b.msp", broken),
                    Catch::Contains("knots for 31 faces, but the domain has 32"));
  broken = model;
  broken.surfaceVertexLocations.pop_back();
  CHECK_THROWS_AS(io::writeSplineModel(dir + "/b.msp", broken), structure::InputError);
  CHECK(test::fileText(path) == before);
  CHECK_FALSE(fs::exists(dir + "/b.msp"));
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);
}

TEST_CASE("spline_model_file: version 1 and 2 files read as the same model", "[io]") {
  // Version 2 moved the triangular B-spline's sections out of the common part without changing
  // a byte, version 3 added the filled-face flags after the surface faces (version 4 changed only
  // T-splines): a version 1 or 2 file is the version 4 file without them and with another version
  // number.
  const std::string dir = test::scratchDirectory("io_spline_model_file_v1");
  const SplineModel model = awkwardModel();
  io::writeSplineModel(dir + "/v3.msp", model);
  const std::string bytes = test::fileText(dir + "/v3.msp");
  REQUIRE(bytes.size() == Layout::size);
  CHECK(io::detail::decode<std::uint32_t>(bytes.data() + 8, false) == 4);
  const std::string older = bytes.substr(0, Layout::filled) + bytes.substr(Layout::filled + 4);
  writeBytes(dir + "/v2.msp", patched(older, 8, std::uint32_t(2)));
  CHECK(io::readSplineModel(dir + "/v2.msp").controlPoints == model.controlPoints);
  writeBytes(dir + "/v1.msp", patched(older, 8, std::uint32_t(1)));

  const SplineModel back = io::readSplineModel(dir + "/v1.msp");
  CHECK(back.kind == spline::SplineKind::TriangularBSpline);
  CHECK(sameBits(back.surfaceVertices, model.surfaceVertices));
  CHECK(back.surfaceFaces == model.surfaceFaces);
  CHECK(back.domain.faces == model.domain.faces);
  CHECK(back.domainVertexSource == model.domainVertexSource);
  CHECK(back.degree == kDegree);
  CHECK(sameBits(back.knots[31][2][1], model.knots[31][2][1]));
  CHECK(sameBits(back.controlPoints, model.controlPoints));
  CHECK(back.tmesh.faces.empty());
  CHECK(back.weights.size() == 0);
  // Every field: the writer puts all of them in the file, which is the version 4 one.
  io::writeSplineModel(dir + "/again.msp", back);
  CHECK(test::fileText(dir + "/again.msp") == bytes);
}

TEST_CASE("spline_model_file: a T-spline's save, load and save again is lossless", "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_tspline");
  const SplineModel model = tsplineModel();
  // A periodic grid has no boundary and no extraordinary vertex: a function at every vertex.
  REQUIRE(model.controlPoints.rows() == kColumns * kRows);
  io::writeSplineModel(dir + "/a.msp", model);
  const std::string bytes = test::fileText(dir + "/a.msp");
  CHECK(bytes.size() == TLayout::size);
  CHECK(bytes.compare(0, 8, "MSPLINE\x1A") == 0);
  CHECK(io::detail::decode<std::uint32_t>(bytes.data() + 12, false) == 2);

  const SplineModel back = io::readSplineModel(dir + "/a.msp");
  CHECK(back.kind == spline::SplineKind::TSpline);
  CHECK(back.degree == 3);
  CHECK(sameBits(back.surfaceVertices, model.surfaceVertices));
  CHECK(back.surfaceFaces == model.surfaceFaces);
  CHECK(back.surfaceVertexLocations.empty());
  CHECK(back.knots.empty());
  CHECK(back.domain.faces.empty());
  // The T-mesh comes back completed as buildTMesh completes it.
  CHECK(back.tmesh.numVertices == model.tmesh.numVertices);
  CHECK(back.tmesh.quarterTurnsAround == model.tmesh.quarterTurnsAround);
  CHECK(back.tmesh.onBoundary == model.tmesh.onBoundary);
  REQUIRE(back.tmesh.numFaces() == model.tmesh.numFaces());
  for (int f = 0; f < model.tmesh.numFaces(); ++f) {
    const spline::TMeshFace &a = model.tmesh.faces[f], &b = back.tmesh.faces[f];
    CHECK(b.vertices == a.vertices);
    CHECK(b.positions == a.positions);
    CHECK(b.width == a.width);
    CHECK(b.height == a.height);
    CHECK(b.twinFace == a.twinFace);
    CHECK(b.twinEdge == a.twinEdge);
  }
  REQUIRE(back.surfaceVertexTMeshPoints.size() == model.surfaceVertexTMeshPoints.size());
  for (std::size_t v = 0; v < model.surfaceVertexTMeshPoints.size(); ++v) {
    CHECK(back.surfaceVertexTMeshPoints[v].face == model.surfaceVertexTMeshPoints[v].face);
    CHECK(sameBits(back.surfaceVertexTMeshPoints[v].position,
                   model.surfaceVertexTMeshPoints[v].position));
  }
  CHECK(std::signbit(back.surfaceVertexTMeshPoints[0].position.x()));
  CHECK(sameBits(back.weights, model.weights));
  CHECK(back.weights(4) == kDenormMin);
  CHECK(sameBits(back.controlPoints, model.controlPoints));
  CHECK(std::signbit(back.controlPoints(0, 0)));

  io::writeSplineModel(dir + "/b.msp", back);
  CHECK(test::fileText(dir + "/b.msp") == bytes);

  // The loaded spline evaluates to the same bits at every surface vertex and inside faces.
  const spline::TSplineSpace before(model.tmesh), after(back.tmesh);
  std::vector<spline::FacePoint> points = model.surfaceVertexTMeshPoints;
  points.push_back({0, Eigen::Vector2d(0.5, 0.5)});
  points.push_back({17, Eigen::Vector2d(0.25, 0.75)});
  points.push_back({29, Eigen::Vector2d(0.9, 0.1)});
  for (const spline::FacePoint& p : points) {
    INFO("face " << p.face << " at " << p.position.transpose());
    const auto x = before.evaluate(model.controlPoints, model.weights, p.face, p.position, 2);
    const auto y = after.evaluate(back.controlPoints, back.weights, p.face, p.position, 2);
    REQUIRE(x.denominator > 0.0);
    REQUIRE(x.position.allFinite());
    CHECK(sameBits(y.denominator, x.denominator));
    CHECK(sameBits(y.position, x.position));
    CHECK(sameBits(y.ds, x.ds));
    CHECK(sameBits(y.dt, x.dt));
    CHECK(sameBits(y.dss, x.dss));
    CHECK(sameBits(y.dst, x.dst));
    CHECK(sameBits(y.dtt, x.dtt));
  }
}

TEST_CASE("spline_model_file: every truncation of a T-spline file is an input error", "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_tspline_cut");
  io::writeSplineModel(dir + "/good.msp", tsplineModel());
  const std::string bytes = test::fileText(dir + "/good.msp");
  REQUIRE(bytes.size() == TLayout::size);
  const std::string path = dir + "/cut.msp";
  checkEveryTruncation(path, bytes);
  const auto cutAt = [&](std::size_t length) {
    writeBytes(path, bytes.substr(0, length));
    return inputError(path);
  };
  CHECK_THAT(cutAt(TLayout::tmesh + 2), Catch::Contains("T-mesh section"));
  CHECK_THAT(cutAt(TLayout::tmeshFaces + 100), Catch::Contains("T-mesh section"));
  CHECK_THAT(cutAt(TLayout::points + 30), Catch::Contains("surface vertex T-mesh points section"));
  CHECK_THAT(cutAt(TLayout::weights + 2), Catch::Contains("weights section"));
  CHECK_THAT(cutAt(TLayout::weights + 20), Catch::Contains("weights section"));
  CHECK_THAT(cutAt(TLayout::controlPoints + 6), Catch::Contains("control points section"));
  CHECK_THAT(cutAt(TLayout::size - 1), Catch::Contains("control points section"));
}

TEST_CASE("spline_model_file: corrupt T-spline files are input errors naming the problem", "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_tspline_bad");
  io::writeSplineModel(dir + "/good.msp", tsplineModel());
  const std::string good = test::fileText(dir + "/good.msp");
  REQUIRE(good.size() == TLayout::size);
  const auto expect = corruptFileCheck(dir);
  const auto nan = std::numeric_limits<double>::quiet_NaN();
  const auto huge = std::uint32_t(std::numeric_limits<std::int32_t>::max());
  const std::size_t n = TLayout::vertices;
  const std::size_t face0 = TLayout::tmeshFaces, point0 = TLayout::points;

  expect("version1.msp", patched(good, 8, std::uint32_t(1)),
         "unsupported spline kind 2 (format version 1 knows kind 1, triangular B-spline)");
  expect("kind.msp", patched(good, 12, std::uint32_t(4)),
         "unsupported spline kind 4 (format version 4 knows kinds 1, triangular B-spline, 2, "
         "T-spline, and 3, subdivision surface)");
  expect("trailing.msp", good + std::string(8, '\0'), "8 bytes after the last section");
  // The T-mesh: counts that cannot be, then what spline::buildTMesh refuses.
  expect("vertices.msp", patched(good, TLayout::tmesh, huge),
         "the T-mesh declares 2147483647 vertices, but its faces have only 120 boundary vertices");
  expect("faces.msp", patched(good, TLayout::tmesh + 4, huge),
         "truncated or corrupt: the T-mesh section needs 2147483647 faces");
  expect("corners.msp", patched(good, face0, huge),
         "truncated or corrupt: the T-mesh section needs 2147483647 boundary vertices");
  expect("nofaces.msp", patched(good, TLayout::tmesh + 4, std::uint32_t(0)),
         "the T-mesh declares 30 vertices, but its faces have only 0 boundary vertices");
  expect("id.msp", patched(good, face0 + 4 + 20, std::int32_t(999)),
         "invalid T-mesh: T-mesh face 0 has vertex id 999 out of range");
  expect("repeat.msp", patched(good, face0 + 4 + 20, std::int32_t(0)),
         "invalid T-mesh: T-mesh face 0 repeats a vertex");
  expect("corner.msp", patched(good, face0 + 4 + 20 + 4, 1.5),
         "invalid T-mesh: T-mesh face 0 is not a rectangle");
  expect("triangle.msp", patched(good, face0, std::uint32_t(3)).erase(face0 + 4 + 3 * 20, 20),
         "invalid T-mesh: T-mesh face 0 needs at least 4 vertices");
  expect("infinite.msp", patched(good, face0 + 4 + 4, std::numeric_limits<double>::infinity()),
         "invalid T-mesh: T-mesh face 0 has a non-finite position");
  // Surface vertex points: the face out of range, the position outside its rectangle.
  expect("face.msp", patched(good, point0, std::int32_t(n)),
         "surface vertex 0 lies in T-mesh face 30, out of range (30 T-mesh faces)");
  expect("face-1.msp", patched(good, point0 + 20, std::int32_t(-1)),
         "surface vertex 1 lies in T-mesh face -1, out of range");
  expect("outside.msp", patched(good, point0 + 4, 1.5),
         "surface vertex 0 lies at (1.500000, 0.000000), outside T-mesh face 0 ([0, 1.000000] x "
         "[0, 1.000000])");
  expect("below.msp", patched(good, point0 + 20 + 12, -1e-8), "surface vertex 1 lies at");
  expect("point-nan.msp", patched(good, point0 + 12, nan),
         "coordinate 1 of the T-mesh point of surface vertex 0 is not finite");
  // Within 1e-9 of the face's size a point is inside.
  writeBytes(dir + "/edge.msp", patched(patched(good, point0 + 4, 1 + 1e-10), point0 + 12, -1e-10));
  CHECK(io::readSplineModel(dir + "/edge.msp").surfaceVertexTMeshPoints[0].position.x() ==
        1 + 1e-10);
  // Weights must be positive and finite.
  for (double w : {0.0, -0.0, -1.0, nan, std::numeric_limits<double>::infinity()})
    expect("weight.msp", patched(good, TLayout::weights + 4 + 8 * 7, w),
           "weight 7 is " + std::to_string(w) + ", not a positive finite number");
  // Counts that fit but do not match: a weight missing, a weight and a control point missing,
  // two coordinates per control point.
  const std::string noLastWeight =
      patched(good, TLayout::weights, std::uint32_t(n - 1)).erase(TLayout::controlPoints - 8, 8);
  expect("weights.msp", noLastWeight, "29 weights for 30 control points");
  expect("rows.msp",
         patched(noLastWeight, TLayout::controlPoints - 8, std::uint32_t(n - 1))
             .substr(0, TLayout::size - 8 - 24),
         "29 control points, but the T-mesh has 30 blending functions");
  expect(
      "columns.msp",
      patched(good, TLayout::controlPoints + 4, std::uint32_t(2)).substr(0, TLayout::size - 8 * n),
      "control points have 2 coordinates, T-splines need 3");
  expect("control.msp", patched(good, TLayout::size - 8, nan),
         "coordinate 2 of control point 29 is not finite");
  expect("surface.msp", patched(good, TLayout::surfaceFaces + 4, std::int32_t(30)),
         "surface face 0 has vertex 30, out of range (30 surface vertices)");
}

TEST_CASE("spline_model_file: T-spline models the format refuses are not written", "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_tspline_refused");
  const SplineModel model = tsplineModel();
  const std::string path = dir + "/a.msp";
  const auto refused = [&](const SplineModel& broken, const std::string& words) {
    CHECK_THROWS_WITH(io::writeSplineModel(path, broken),
                      Catch::Contains("cannot write '" + path + "'") && Catch::Contains(words));
    CHECK_FALSE(fs::exists(path));
  };
  SplineModel broken = model;
  broken.weights(3) = 0.0;
  refused(broken, "weight 3 is 0.000000, not a positive finite number");
  broken = model;
  broken.weights(5) = -std::numeric_limits<double>::infinity();
  refused(broken, "weight 5 is -inf");
  broken = model;
  broken.degree = 2;
  refused(broken, "degree 2, but T-splines are cubic (degree 3)");
  broken = model;
  broken.tmesh.faces[4].vertices.pop_back();
  broken.tmesh.faces[4].positions.pop_back();
  refused(broken, "invalid T-mesh: T-mesh face 4 needs at least 4 vertices");
  broken = model;
  broken.tmesh.numVertices = 31;
  refused(broken, "invalid T-mesh: T-mesh vertex 30 is in no face");
  broken = model;
  broken.surfaceVertexTMeshPoints[2].position.y() = 1.01;
  refused(broken, "surface vertex 2 lies at (0.000000, 1.010000), outside T-mesh face 2");
  broken = model;
  broken.surfaceVertexTMeshPoints.pop_back();
  refused(broken, "29 surface vertex T-mesh points for 30 surface vertices");
  broken = model;
  broken.weights.conservativeResize(29);
  broken.controlPoints.conservativeResize(29, 3);
  refused(broken, "29 control points, but the T-mesh has 30 blending functions");
  broken = model;
  broken.controlPoints.conservativeResize(30, 4);
  broken.controlPoints.col(3).setZero();
  refused(broken, "control points have 4 coordinates, T-splines need 3");
  // A model holds its own kind's data only: the file would lose the other kind's.
  broken = model;
  broken.knots.resize(2);
  refused(broken, "a T-spline model has 2 faces of knots");
  broken = model;
  broken.surfaceVertexLocations.resize(30);
  refused(broken, "a T-spline model has 30 surface vertex locations");
  SplineModel triangular = awkwardModel();
  triangular.weights = model.weights;
  refused(triangular, "a triangular B-spline model has 30 weights");
  triangular = awkwardModel();
  triangular.tmesh = model.tmesh;
  refused(triangular, "a triangular B-spline model has 30 T-mesh vertices");
  CHECK(fs::is_empty(dir));
}

TEST_CASE("spline_model_file: a subdivision surface's save, load and save again is lossless",
          "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_subd");
  // The T-spline model's T-mesh and surface points, one net point per T-mesh vertex, no weights.
  SplineModel model = tsplineModel();
  model.kind = spline::SplineKind::Subdivision;
  model.weights.resize(0);
  REQUIRE(model.controlPoints.rows() == model.tmesh.numVertices);
  io::writeSplineModel(dir + "/a.msp", model);
  const std::string bytes = test::fileText(dir + "/a.msp");
  // The T-spline's file without the weights section (u32 count and 30 f64).
  CHECK(bytes.size() == TLayout::size - 4 - 8 * std::size_t(kColumns * kRows));
  CHECK(io::detail::decode<std::uint32_t>(bytes.data() + 8, false) == 4);
  CHECK(io::detail::decode<std::uint32_t>(bytes.data() + 12, false) == 3);

  const SplineModel back = io::readSplineModel(dir + "/a.msp");
  CHECK(back.kind == spline::SplineKind::Subdivision);
  CHECK(sameBits(back.surfaceVertices, model.surfaceVertices));
  CHECK(back.surfaceFaces == model.surfaceFaces);
  CHECK(back.weights.size() == 0);
  CHECK(sameBits(back.controlPoints, model.controlPoints));
  REQUIRE(back.tmesh.numFaces() == model.tmesh.numFaces());
  for (int f = 0; f < model.tmesh.numFaces(); ++f) {
    CHECK(back.tmesh.faces[f].positions == model.tmesh.faces[f].positions);
    CHECK(back.tmesh.faces[f].twinFace == model.tmesh.faces[f].twinFace);
  }
  REQUIRE(back.surfaceVertexTMeshPoints.size() == model.surfaceVertexTMeshPoints.size());
  for (std::size_t v = 0; v < model.surfaceVertexTMeshPoints.size(); ++v) {
    CHECK(back.surfaceVertexTMeshPoints[v].face == model.surfaceVertexTMeshPoints[v].face);
    CHECK(sameBits(back.surfaceVertexTMeshPoints[v].position,
                   model.surfaceVertexTMeshPoints[v].position));
  }
  io::writeSplineModel(dir + "/b.msp", back);
  CHECK(test::fileText(dir + "/b.msp") == bytes);
  // The loaded surface evaluates to the same bits.
  const spline::SubdSpace before(model.tmesh), after(back.tmesh);
  for (const spline::FacePoint& p :
       {spline::FacePoint{0, {0.5, 0.5}}, spline::FacePoint{17, {0.25, 0.75}}}) {
    Eigen::Vector3d x, y, xs, ys;
    REQUIRE(before.evaluate(model.controlPoints, p.face, p.position, x, &xs));
    REQUIRE(after.evaluate(back.controlPoints, p.face, p.position, y, &ys));
    CHECK(sameBits(Eigen::VectorXd(x), Eigen::VectorXd(y)));
    CHECK(sameBits(Eigen::VectorXd(xs), Eigen::VectorXd(ys)));
  }

  // What the format refuses.
  const std::string path = dir + "/c.msp";
  const auto refused = [&](const SplineModel& broken, const std::string& words) {
    CHECK_THROWS_WITH(io::writeSplineModel(path, broken),
                      Catch::Contains("cannot write '" + path + "'") && Catch::Contains(words));
    CHECK_FALSE(fs::exists(path));
  };
  SplineModel broken = model;
  broken.weights = Eigen::VectorXd::Ones(30);
  refused(broken, "a subdivision surface model has 30 weights");
  broken = model;
  broken.controlPoints.conservativeResize(29, 3);
  refused(broken, "29 control points, but the T-mesh has 30 vertices");
  broken = model;
  broken.tmesh = test::stoppedLine();
  broken.surfaceVertexTMeshPoints.assign(30, {0, Eigen::Vector2d(0.5, 0.5)});
  broken.controlPoints = Eigen::MatrixXd::Zero(broken.tmesh.numVertices, 3);
  refused(broken, "boundary vertices, a subdivision surface's net needs quads");
  // A file whose control points do not match its T-mesh names the file.
  std::string cut = bytes;
  const std::size_t rowsAt = bytes.size() - 8 - 8 * 3 * std::size_t(kColumns * kRows);
  const std::uint32_t rows = 29;
  std::memcpy(&cut[rowsAt], &rows, 4);
  cut.resize(cut.size() - 24);
  writeBytes(path, cut);
  CHECK_THROWS_WITH(io::readSplineModel(path),
                    Catch::Contains(path) &&
                        Catch::Contains("29 control points, but the T-mesh has 30 vertices"));
}

TEST_CASE("spline_model_file: filled faces round-trip and are checked", "[io]") {
  const std::string dir = test::scratchDirectory("io_spline_model_file_filled");
  SplineModel model = tsplineModel();
  model.surfaceFaceFilled.assign(model.surfaceFaces.size(), 0);
  model.surfaceFaceFilled[3] = 1;
  io::writeSplineModel(dir + "/a.msp", model);
  const std::string bytes = test::fileText(dir + "/a.msp");
  CHECK(bytes.size() == TLayout::size + model.surfaceFaces.size());
  const SplineModel back = io::readSplineModel(dir + "/a.msp");
  CHECK(back.surfaceFaceFilled == model.surfaceFaceFilled);
  writeBytes(dir + "/flag.msp", patched(bytes, TLayout::filled + 4 + 3, std::uint8_t(7)));
  CHECK_THROWS_WITH(io::readSplineModel(dir + "/flag.msp"),
                    Catch::Contains("a filled-face flag is 7"));
  model.surfaceFaceFilled.pop_back();
  CHECK_THROWS_WITH(io::writeSplineModel(dir + "/b.msp", model),
                    Catch::Contains("filled-face flags for"));
  CHECK_FALSE(fs::exists(dir + "/b.msp"));
}

TEST_CASE("spline_model_file: a T-spline written before caps reads with its cones capped", "[io]") {
  // The cube of 5 x 5 cells a side: 8 cones of valence 3. A version 3 file had rows only for the
  // anchors off the cones and their one-rings, in vertex order.
  const std::string dir = test::scratchDirectory("io_spline_model_file_caps");
  const test::CubeTMesh cube = test::cubeTMesh(5);
  SplineModel model;
  model.kind = spline::SplineKind::TSpline;
  model.tmesh = cube.mesh;
  model.surfaceVertices = cube.latticePoints.topRows(3);
  model.surfaceFaces = {{0, 1, 2}};
  for (int v = 0; v < 3; ++v)
    model.surfaceVertexTMeshPoints.push_back({0, Eigen::Vector2d::Zero()});
  const spline::TSplineSpace space(cube.mesh);
  model.controlPoints = test::anchorControl(space, cube.vertexPoints);
  model.weights = Eigen::VectorXd::Constant(space.numBasis(), 2.0);
  io::writeSplineModel(dir + "/v4.msp", model);
  const std::string bytes = test::fileText(dir + "/v4.msp");
  CHECK(io::detail::decode<std::uint32_t>(bytes.data() + 8, false) == 4);
  // The old rows: the anchors off the caps.
  std::vector<char> cap(std::size_t(cube.mesh.numVertices), 0);
  for (const auto& face : space.capFaces())
    for (int v : cube.mesh.faces[std::size_t(face.face)].vertices) cap[std::size_t(v)] = 1;
  std::vector<int> oldRows;
  for (int a = 0; a < space.numBasis(); ++a)
    if (!cap[std::size_t(space.anchors()[std::size_t(a)].vertex)]) oldRows.push_back(a);
  REQUIRE(int(oldRows.size()) == space.numBasis() - 8 * 7);
  const std::size_t weights = bytes.size() - (8 + 24 * std::size_t(space.numBasis())) -
                              (4 + 8 * std::size_t(space.numBasis()));
  std::string old = patched(bytes.substr(0, weights), 8, std::uint32_t(3));
  io::detail::appendLittleEndian(old, std::uint32_t(oldRows.size()));
  for (std::size_t r = 0; r < oldRows.size(); ++r) io::detail::appendLittleEndian(old, 2.0);
  io::detail::appendLittleEndian(old, std::uint32_t(oldRows.size()));
  io::detail::appendLittleEndian(old, std::uint32_t(3));
  for (int a : oldRows)
    for (int c = 0; c < 3; ++c) io::detail::appendLittleEndian(old, model.controlPoints(a, c));
  writeBytes(dir + "/v3.msp", old);
  const SplineModel back = io::readSplineModel(dir + "/v3.msp");
  REQUIRE(back.controlPoints.rows() == space.numBasis());
  CHECK(back.weights == model.weights);
  for (int a : oldRows) CHECK(back.controlPoints.row(a) == model.controlPoints.row(a));
  // A cone and its ring get the ring averages of the anchored points: near the net, not equal.
  for (int v = 0; v < cube.mesh.numVertices; ++v) {
    if (!cube.mesh.isExtraordinary(v)) continue;
    const int a = space.anchorOfVertex()[std::size_t(v)];
    const double gap = (back.controlPoints.row(a) - model.controlPoints.row(a)).norm();
    CHECK(gap > 0.0);
    CHECK(gap < 0.5);
  }
  // Too many rows for the T-mesh before caps: named.
  writeBytes(dir + "/v3wrong.msp", patched(bytes, 8, std::uint32_t(3)));
  CHECK_THAT(inputError(dir + "/v3wrong.msp"),
             Catch::Contains("v3wrong.msp") && Catch::Contains("blending functions before caps"));
}
