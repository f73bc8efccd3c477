#include "mspline/io/spline_model_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string_view>
#include <utility>

#include "mspline/io/atomic_file.h"
#include "mspline/io/detail/byte_order.h"
#include "mspline/io/detail/output_buffer.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_cap.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/whole_file.h"

namespace mspline::io {

namespace {

using spline::SplineKind;
using spline::SplineModel;
using structure::InputError;

constexpr std::string_view kMagic("MSPLINE\x1A", 8);
constexpr std::uint32_t kVersion = 4;
// The first version whose T-splines anchor functions at cones and their one-rings (caps).
constexpr std::uint32_t kCapsVersion = 4;
// The model indexes with int.
constexpr std::uint64_t kMaxCount = std::numeric_limits<std::int32_t>::max();

// Bytes per item of the sections, as documented in the header.
constexpr std::uint64_t kVertexBytes = 3 * 8;
constexpr std::uint64_t kFaceBytes = 3 * 4;
constexpr std::uint64_t kLocationBytes = 4 + 3 * 8;
constexpr std::uint64_t kDomainVertexBytes = 1 + 4;
constexpr std::uint64_t kDomainFaceBytes = 3 * 4 + 3 * 8 + 3 * 4 + 3;
constexpr std::uint64_t kPointBytes = 2 * 8;
constexpr std::uint64_t kTMeshFaceBytes = 4;  // the count; its boundary vertices are checked apart
constexpr std::uint64_t kTMeshCornerBytes = 4 + 2 * 8;
constexpr std::uint64_t kTMeshPointBytes = 4 + 2 * 8;

[[noreturn]] void fail(const std::string& problem) {
  throw InputError(problem);
}

std::string str(std::uint64_t n) {
  return std::to_string(n);
}

template <class Name>
void requireFinite(double value, const Name& name) {
  if (!std::isfinite(value)) fail(name() + " is not finite (" + std::to_string(value) + ")");
}

template <class Name>
void requireIndex(int index, std::size_t count, const Name& name, const char* range) {
  if (index < 0 || std::size_t(index) >= count)
    fail(name() + " " + std::to_string(index) + ", out of range (" + str(count) + " " + range +
         ")");
}

void requireCount(std::size_t count, const char* what) {
  if (count > kMaxCount)
    fail(str(count) + " " + what + " are more than the format holds (2^31 - 1)");
}

// Data of the other kind would not be written, so a loaded model would differ from the saved one.
void requireNone(std::size_t count, const char* what, const char* kind) {
  if (count != 0)
    fail("a " + std::string(kind) + " model has " + str(count) + " " + what +
         ", which its part of the format does not hold");
}

void checkControlPoints(const Eigen::MatrixXd& control) {
  requireCount(std::size_t(control.rows()), "control points");
  requireCount(std::size_t(control.cols()), "control point coordinates");
  for (Eigen::Index r = 0; r < control.rows(); ++r)
    for (Eigen::Index k = 0; k < control.cols(); ++k)
      requireFinite(control(r, k),
                    [&] { return "coordinate " + str(k) + " of control point " + str(r); });
}

void checkCommon(const SplineModel& model) {
  const std::size_t vertices = std::size_t(model.surfaceVertices.rows());
  requireCount(vertices, "surface vertices");
  requireCount(model.surfaceFaces.size(), "surface faces");
  // A spline is built on a surface: without one, check has nowhere to sample and export nothing
  // to write.
  if (model.surfaceFaces.empty()) fail("the model has no surface faces");
  for (std::size_t v = 0; v < vertices; ++v)
    for (int k = 0; k < 3; ++k)
      requireFinite(model.surfaceVertices(Eigen::Index(v), k),
                    [&] { return "coordinate " + str(k) + " of surface vertex " + str(v); });
  for (std::size_t f = 0; f < model.surfaceFaces.size(); ++f)
    for (int v : model.surfaceFaces[f])
      requireIndex(
          v, vertices, [&] { return "surface face " + str(f) + " has vertex"; },
          "surface vertices");
  if (!model.surfaceFaceFilled.empty() &&
      model.surfaceFaceFilled.size() != model.surfaceFaces.size())
    throw InputError(str(model.surfaceFaceFilled.size()) + " filled-face flags for " +
                     str(model.surfaceFaces.size()) + " surface faces");
}

void checkTriangularBSpline(const SplineModel& model) {
  const char* kind = "triangular B-spline";
  requireNone(std::size_t(model.tmesh.numVertices), "T-mesh vertices", kind);
  requireNone(model.tmesh.faces.size(), "T-mesh faces", kind);
  requireNone(model.surfaceVertexTMeshPoints.size(), "surface vertex T-mesh points", kind);
  requireNone(std::size_t(model.weights.size()), "weights", kind);
  const spline::SplineDomain& domain = model.domain;
  const std::size_t vertices = std::size_t(model.surfaceVertices.rows());
  const std::size_t faces = domain.faces.size();
  requireCount(domain.cone.size(), "domain vertices");
  requireCount(faces, "domain faces");
  if (model.surfaceVertexLocations.size() != vertices)
    fail(str(model.surfaceVertexLocations.size()) + " surface vertex locations for " +
         str(vertices) + " surface vertices");
  if (model.domainVertexSource.size() != domain.cone.size())
    fail(str(model.domainVertexSource.size()) + " source surface vertices for " +
         str(domain.cone.size()) + " domain vertices");
  if (domain.sideLengths.size() != faces || domain.neighbour.size() != faces ||
      domain.neighbourSide.size() != faces)
    fail("the domain's per-face arrays have different sizes");
  if (faces == 0) fail("the domain has no faces");
  if (model.controlPoints.cols() != 3)
    fail("control points have " + str(std::size_t(model.controlPoints.cols())) +
         " coordinates, triangular B-splines need 3");
  if (model.degree < 1) fail("degree " + std::to_string(model.degree) + " is below 1");
  const std::size_t knotsPerCorner = std::size_t(model.degree) + 1;
  if (model.knots.size() != faces)
    fail("knots for " + str(model.knots.size()) + " faces, but the domain has " + str(faces));
  for (std::size_t f = 0; f < faces; ++f)
    for (std::size_t c = 0; c < 3; ++c)
      if (model.knots[f][c].size() != knotsPerCorner)
        fail("corner " + str(c) + " of domain face " + str(f) + " has " +
             str(model.knots[f][c].size()) + " knots, degree " + std::to_string(model.degree) +
             " needs " + str(knotsPerCorner));
  const std::size_t perFace = knotsPerCorner * (knotsPerCorner + 1) / 2;
  const std::size_t rows = std::size_t(model.controlPoints.rows());
  if (rows % perFace != 0 || rows / perFace != faces)
    fail(str(rows) + " control points, but " + str(faces) + " domain faces of degree " +
         std::to_string(model.degree) + " have " + str(perFace) + " basis functions each");

  for (std::size_t v = 0; v < vertices; ++v) {
    const spline::SurfacePoint& location = model.surfaceVertexLocations[v];
    requireIndex(
        location.face, faces, [&] { return "surface vertex " + str(v) + " lies in face"; },
        "domain faces");
    for (int k = 0; k < 3; ++k)
      requireFinite(location.barycentric(k), [&] {
        return "barycentric coordinate " + str(k) + " of surface vertex " + str(v);
      });
  }
  for (std::size_t d = 0; d < domain.cone.size(); ++d) {
    const auto flag = static_cast<unsigned char>(domain.cone[d]);
    if (flag > 1)
      fail("domain vertex " + str(d) + " has cone flag " + str(flag) + " (0 or 1 expected)");
    requireIndex(
        model.domainVertexSource[d], vertices,
        [&] { return "domain vertex " + str(d) + " is surface vertex"; }, "surface vertices");
  }
  for (std::size_t f = 0; f < faces; ++f)
    for (std::size_t k = 0; k < 3; ++k)
      requireFinite(domain.sideLengths[f][k],
                    [&] { return "side length " + str(k) + " of domain face " + str(f); });
  for (std::size_t f = 0; f < faces; ++f)
    for (std::size_t c = 0; c < 3; ++c)
      for (std::size_t b = 0; b < knotsPerCorner; ++b)
        for (int k = 0; k < 2; ++k)
          requireFinite(model.knots[f][c][b](k), [&] {
            return "coordinate " + str(k) + " of knot " + str(b) + " of corner " + str(c) +
                   " of domain face " + str(f);
          });
  checkControlPoints(model.controlPoints);
  spline::validateDomain(domain);
}

// Returns the T-mesh as spline::buildTMesh completes it (widths, heights, twins).
// The fields of T-mesh kinds (T-splines, subdivision surfaces) but for weights and control
// points; `kind` names the kind in messages.
spline::TMesh checkTMeshModel(const SplineModel& model, const char* kind) {
  requireNone(model.surfaceVertexLocations.size(), "surface vertex locations", kind);
  requireNone(model.domain.cone.size(), "domain vertices", kind);
  requireNone(model.domain.faces.size(), "domain faces", kind);
  requireNone(model.domainVertexSource.size(), "source surface vertices", kind);
  requireNone(model.knots.size(), "faces of knots", kind);
  if (model.degree != 3)
    fail("degree " + std::to_string(model.degree) + ", but " + kind + "s are cubic (degree 3)");
  const std::size_t vertices = std::size_t(model.surfaceVertices.rows());
  if (model.surfaceVertexTMeshPoints.size() != vertices)
    fail(str(model.surfaceVertexTMeshPoints.size()) + " surface vertex T-mesh points for " +
         str(vertices) + " surface vertices");
  requireCount(model.tmesh.faces.size(), "T-mesh faces");
  if (model.tmesh.faces.empty()) fail("the T-mesh has no faces");
  for (const spline::TMeshFace& face : model.tmesh.faces)
    requireCount(face.vertices.size(), "T-mesh face vertices");
  spline::TMesh mesh;
  try {
    mesh = spline::buildTMesh(model.tmesh.numVertices, model.tmesh.faces);
  } catch (const InputError& error) {
    fail(std::string("invalid T-mesh: ") + error.what());
  }

  for (std::size_t v = 0; v < vertices; ++v) {
    const spline::FacePoint& point = model.surfaceVertexTMeshPoints[v];
    requireIndex(
        point.face, mesh.faces.size(),
        [&] { return "surface vertex " + str(v) + " lies in T-mesh face"; }, "T-mesh faces");
    for (int k = 0; k < 2; ++k)
      requireFinite(point.position(k), [&] {
        return "coordinate " + str(k) + " of the T-mesh point of surface vertex " + str(v);
      });
    const spline::TMeshFace& face = mesh.faces[std::size_t(point.face)];
    const double tolerance = 1e-9 * std::max(face.width, face.height);
    const Eigen::Vector2d& p = point.position;
    if (!(p.x() >= -tolerance && p.x() <= face.width + tolerance && p.y() >= -tolerance &&
          p.y() <= face.height + tolerance))
      fail("surface vertex " + str(v) + " lies at (" + std::to_string(p.x()) + ", " +
           std::to_string(p.y()) + "), outside T-mesh face " + str(std::size_t(point.face)) +
           " ([0, " + std::to_string(face.width) + "] x [0, " + std::to_string(face.height) + "])");
  }
  return mesh;
}

spline::TMesh checkTSpline(const SplineModel& model) {
  spline::TMesh mesh = checkTMeshModel(model, "T-spline");
  const auto weights = std::size_t(model.weights.size());
  const auto rows = std::size_t(model.controlPoints.rows());
  requireCount(weights, "weights");
  if (weights != rows) fail(str(weights) + " weights for " + str(rows) + " control points");
  if (model.controlPoints.cols() != 3)
    fail("control points have " + str(std::size_t(model.controlPoints.cols())) +
         " coordinates, T-splines need 3");
  for (std::size_t i = 0; i < weights; ++i) {
    const double weight = model.weights(Eigen::Index(i));
    if (!(weight > 0.0 && std::isfinite(weight)))
      fail("weight " + str(i) + " is " + std::to_string(weight) + ", not a positive finite number");
  }
  checkControlPoints(model.controlPoints);
  std::size_t basis = 0;
  try {
    basis = std::size_t(spline::TSplineSpace(mesh).numBasis());
  } catch (const InputError& error) {
    fail(std::string("invalid T-mesh: ") + error.what());
  } catch (const structure::SolverError& error) {
    fail(error.what());
  }
  if (rows != basis)
    fail(str(rows) + " control points, but the T-mesh has " + str(basis) + " blending functions");
  return mesh;
}

// Before format version 4 no function was anchored at a cone nor at its one-ring (the surface had
// a hole there): the rows, in vertex order, are the other anchors'. The cap anchors get the ring
// averages of tsplineControlNet's rule (spline::fillByRingAverages), of (w c, w) alike.
void addCapAnchors(SplineModel& model) {
  const spline::TMesh mesh = checkTMeshModel(model, "T-spline");
  const Eigen::Index rows = model.controlPoints.rows();
  if (model.controlPoints.cols() != 3 || model.weights.size() != rows) return;  // checkTSpline
  std::unique_ptr<spline::TSplineSpace> space;
  try {
    space = std::make_unique<spline::TSplineSpace>(mesh);
  } catch (const structure::Error& error) {
    fail(std::string("a T-spline written before caps (format version 3 or older) whose T-mesh "
                     "cannot have them; fit it again: ") +
         error.what());
  }
  // The cones and their one-rings: the corners of the faces around the cones.
  std::vector<char> capAnchor(std::size_t(mesh.numVertices), 0);
  for (const spline::TSplineCapFace& cap : space->capFaces())
    for (int v : mesh.faces[std::size_t(cap.face)].vertices) capAnchor[std::size_t(v)] = 1;
  Eigen::MatrixXd homogeneous = Eigen::MatrixXd::Zero(mesh.numVertices, 4);
  std::vector<char> placed(std::size_t(mesh.numVertices), 0);
  Eigen::Index row = 0;
  for (const spline::TSplineAnchor& anchor : space->anchors()) {
    if (capAnchor[std::size_t(anchor.vertex)]) continue;
    if (row == rows) fail(str(std::size_t(rows)) + " control points, too few for the T-mesh");
    const double w = model.weights[row];
    homogeneous.row(anchor.vertex) << w * model.controlPoints.row(row), w;
    placed[std::size_t(anchor.vertex)] = 1;
    ++row;
  }
  if (row != rows)
    fail(str(std::size_t(rows)) + " control points, but the T-mesh had " + str(std::size_t(row)) +
         " blending functions before caps");
  spline::fillByRingAverages(mesh, homogeneous, placed, "T-spline");
  model.controlPoints.resize(space->numBasis(), 3);
  model.weights.resize(space->numBasis());
  for (int a = 0; a < space->numBasis(); ++a) {
    const auto h = homogeneous.row(space->anchors()[std::size_t(a)].vertex);
    model.weights[a] = h[3];
    model.controlPoints.row(a) = h.head<3>() / h[3];
  }
}

// Returns the T-mesh as spline::buildTMesh completes it.
spline::TMesh checkSubdivision(const SplineModel& model) {
  const char* kind = "subdivision surface";
  requireNone(std::size_t(model.weights.size()), "weights", kind);
  if (model.controlPoints.cols() != 3)
    fail("control points have " + str(std::size_t(model.controlPoints.cols())) +
         " coordinates, subdivision surfaces need 3");
  spline::TMesh mesh = checkTMeshModel(model, kind);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    if (mesh.faces[f].vertices.size() != 4)
      fail("T-mesh face " + str(f) + " has " + str(mesh.faces[f].vertices.size()) +
           " boundary vertices, a subdivision surface's net needs quads (no T-junctions)");
  checkControlPoints(model.controlPoints);
  const auto rows = std::size_t(model.controlPoints.rows());
  if (rows != std::size_t(mesh.numVertices))
    fail(str(rows) + " control points, but the T-mesh has " + str(std::size_t(mesh.numVertices)) +
         " vertices");
  return mesh;
}

// Everything the reader checks, so that the writer never writes a file the reader rejects.
// Throws InputError naming the first problem. Returns the completed T-mesh of a T-spline (empty
// for other kinds), so that the reader builds it once.
spline::TMesh checkModel(const SplineModel& model) {
  checkCommon(model);
  switch (model.kind) {
    case SplineKind::TriangularBSpline:
      checkTriangularBSpline(model);
      return {};
    case SplineKind::TSpline:
      return checkTSpline(model);
    case SplineKind::Subdivision:
      return checkSubdivision(model);
  }
  fail("unknown spline kind " + std::to_string(int(model.kind)));
}

// A cursor over the file's bytes that knows which section it is in, for the messages.
class ModelReader {
 public:
  ModelReader(std::string_view data, const std::string& path) : data_(data), path_(path) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(path_ + ": " + problem);
  }
  void section(const char* name) { section_ = name; }
  std::uint64_t remaining() const { return data_.size() - offset_; }

  std::string_view bytes(std::size_t count) {
    if (remaining() < count)
      fail("truncated: the file ends inside the " + section_ + " section (after " +
           str(data_.size()) + " bytes)");
    const std::string_view out = data_.substr(offset_, count);
    offset_ += count;
    return out;
  }
  template <typename T>
  T value() {
    return detail::decode<T>(bytes(sizeof(T)).data(), false);
  }
  /// Checks, before anything is allocated for them, that `items` items of `itemBytes` bytes
  /// each fit in the rest of the file: a corrupt count must not allocate gigabytes.
  void requireFit(std::uint64_t items, std::uint64_t itemBytes, const std::string& what) const {
    if (itemBytes != 0 && items > remaining() / itemBytes)
      fail("truncated or corrupt: the " + section_ + " section needs " + what + " of " +
           str(itemBytes) + " bytes each, but only " + str(remaining()) + " bytes remain");
  }
  /// A u32 count of items of `itemBytes` bytes each, all of which must fit in the file.
  int count(std::uint64_t itemBytes, const char* noun) {
    const std::uint64_t n = value<std::uint32_t>();
    if (n > kMaxCount)
      fail("the " + section_ + " section declares " + str(n) + " " + noun +
           ", more than the format holds (2^31 - 1)");
    requireFit(n, itemBytes, str(n) + " " + noun);
    return int(n);
  }

 private:
  std::string_view data_;
  const std::string& path_;
  std::size_t offset_ = 0;
  std::string section_;
};

void readTriangularBSpline(ModelReader& in, SplineModel& model) {
  in.section("surface vertex locations");
  const auto vertices = std::size_t(model.surfaceVertices.rows());
  in.requireFit(vertices, kLocationBytes, str(vertices) + " locations");
  model.surfaceVertexLocations.resize(vertices);
  for (auto& location : model.surfaceVertexLocations) {
    location.face = in.value<std::int32_t>();
    for (int k = 0; k < 3; ++k) location.barycentric(k) = in.value<double>();
  }

  in.section("domain vertices");
  spline::SplineDomain& domain = model.domain;
  const auto domainVertices = std::size_t(in.count(kDomainVertexBytes, "domain vertices"));
  domain.cone.resize(domainVertices);
  model.domainVertexSource.resize(domainVertices);
  for (std::size_t d = 0; d < domainVertices; ++d) {
    domain.cone[d] = static_cast<char>(in.value<std::uint8_t>());
    model.domainVertexSource[d] = in.value<std::int32_t>();
  }

  in.section("domain faces");
  const auto faces = std::size_t(in.count(kDomainFaceBytes, "domain faces"));
  domain.faces.resize(faces);
  domain.sideLengths.resize(faces);
  domain.neighbour.resize(faces);
  domain.neighbourSide.resize(faces);
  for (std::size_t f = 0; f < faces; ++f) {
    for (int& corner : domain.faces[f]) corner = in.value<std::int32_t>();
    for (double& length : domain.sideLengths[f]) length = in.value<double>();
    for (int& neighbour : domain.neighbour[f]) neighbour = in.value<std::int32_t>();
    for (int& side : domain.neighbourSide[f]) side = in.value<std::uint8_t>();
  }

  in.section("degree");
  model.degree = in.value<std::int32_t>();
  if (model.degree < 1) in.fail("degree " + std::to_string(model.degree) + " is below 1");

  in.section("knots");
  const auto knotsPerCorner = std::size_t(model.degree) + 1;
  in.requireFit(3 * faces, knotsPerCorner * kPointBytes, str(3 * faces) + " corners");
  model.knots.resize(faces);
  for (auto& face : model.knots)
    for (auto& corner : face) {
      corner.resize(knotsPerCorner);
      for (auto& knot : corner) {
        knot.x() = in.value<double>();
        knot.y() = in.value<double>();
      }
    }
}

// The T-mesh and the surface vertex T-mesh points (T-splines and subdivision surfaces).
void readTMeshPart(ModelReader& in, SplineModel& model) {
  in.section("T-mesh");
  spline::TMesh& mesh = model.tmesh;
  mesh.numVertices = in.count(0, "vertices");
  mesh.faces.resize(std::size_t(in.count(kTMeshFaceBytes, "faces")));
  std::uint64_t corners = 0;
  for (spline::TMeshFace& face : mesh.faces) {
    const auto n = std::size_t(in.count(kTMeshCornerBytes, "boundary vertices of a face"));
    corners += n;
    face.vertices.resize(n);
    face.positions.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      face.vertices[k] = in.value<std::int32_t>();
      face.positions[k].x() = in.value<double>();
      face.positions[k].y() = in.value<double>();
    }
  }
  // Every vertex is on some face (buildTMesh checks it): a corrupt count must not allocate.
  if (std::uint64_t(mesh.numVertices) > corners)
    in.fail("the T-mesh declares " + str(std::size_t(mesh.numVertices)) +
            " vertices, but its faces have only " + str(corners) + " boundary vertices in all");

  in.section("surface vertex T-mesh points");
  const auto vertices = std::size_t(model.surfaceVertices.rows());
  in.requireFit(vertices, kTMeshPointBytes, str(vertices) + " points");
  model.surfaceVertexTMeshPoints.resize(vertices);
  for (spline::FacePoint& point : model.surfaceVertexTMeshPoints) {
    point.face = in.value<std::int32_t>();
    point.position.x() = in.value<double>();
    point.position.y() = in.value<double>();
  }
}

void readTSpline(ModelReader& in, SplineModel& model) {
  readTMeshPart(in, model);
  in.section("weights");
  model.weights.resize(in.count(8, "weights"));
  for (Eigen::Index i = 0; i < model.weights.size(); ++i) model.weights(i) = in.value<double>();
}

// Sequential little-endian output of the sections.
class ModelWriter {
 public:
  explicit ModelWriter(std::ostream& out) : buffer_(out) {}
  void text(std::string_view s) { buffer_.text(s); }
  void u8(int value) { buffer_.littleEndian(std::uint8_t(value)); }
  void u32(std::size_t value) { buffer_.littleEndian(std::uint32_t(value)); }
  void i32(int value) { buffer_.littleEndian(std::int32_t(value)); }
  void f64(double value) { buffer_.littleEndian(value); }
  void flush() { buffer_.flush(); }

 private:
  detail::OutputBuffer buffer_;
};

void writeTriangularBSpline(ModelWriter& out, const SplineModel& model) {
  for (const auto& location : model.surfaceVertexLocations) {
    out.i32(location.face);
    for (int k = 0; k < 3; ++k) out.f64(location.barycentric(k));
  }
  const auto& domain = model.domain;
  out.u32(domain.cone.size());
  for (std::size_t d = 0; d < domain.cone.size(); ++d) {
    out.u8(domain.cone[d]);
    out.i32(model.domainVertexSource[d]);
  }
  out.u32(domain.faces.size());
  for (std::size_t f = 0; f < domain.faces.size(); ++f) {
    for (int corner : domain.faces[f]) out.i32(corner);
    for (double length : domain.sideLengths[f]) out.f64(length);
    for (int neighbour : domain.neighbour[f]) out.i32(neighbour);
    for (int side : domain.neighbourSide[f]) out.u8(side);
  }
  out.i32(model.degree);
  for (const auto& face : model.knots)
    for (const auto& corner : face)
      for (const auto& knot : corner) {
        out.f64(knot.x());
        out.f64(knot.y());
      }
}

void writeTMeshPart(ModelWriter& out, const SplineModel& model) {
  out.u32(std::size_t(model.tmesh.numVertices));
  out.u32(model.tmesh.faces.size());
  for (const spline::TMeshFace& face : model.tmesh.faces) {
    out.u32(face.vertices.size());
    for (std::size_t k = 0; k < face.vertices.size(); ++k) {
      out.i32(face.vertices[k]);
      out.f64(face.positions[k].x());
      out.f64(face.positions[k].y());
    }
  }
  for (const spline::FacePoint& point : model.surfaceVertexTMeshPoints) {
    out.i32(point.face);
    out.f64(point.position.x());
    out.f64(point.position.y());
  }
}

void writeTSpline(ModelWriter& out, const SplineModel& model) {
  writeTMeshPart(out, model);
  out.u32(std::size_t(model.weights.size()));
  for (Eigen::Index i = 0; i < model.weights.size(); ++i) out.f64(model.weights(i));
}

}  // namespace

void writeSplineModel(const std::string& path, const SplineModel& model) {
  try {
    checkModel(model);
  } catch (const InputError& error) {
    throw InputError("cannot write '" + path + "': " + error.what());
  }
  writeFileAtomically(path, [&](std::ostream& stream) {
    ModelWriter out(stream);
    out.text(kMagic);
    out.u32(kVersion);
    out.u32(std::size_t(model.kind));

    const auto& vertices = model.surfaceVertices;
    out.u32(std::size_t(vertices.rows()));
    for (Eigen::Index v = 0; v < vertices.rows(); ++v)
      for (int k = 0; k < 3; ++k) out.f64(vertices(v, k));
    out.u32(model.surfaceFaces.size());
    for (const auto& face : model.surfaceFaces)
      for (int v : face) out.i32(v);
    out.u32(model.surfaceFaceFilled.size());
    for (const char filled : model.surfaceFaceFilled) out.u8(filled ? 1 : 0);

    if (model.kind == SplineKind::TriangularBSpline)
      writeTriangularBSpline(out, model);
    else if (model.kind == SplineKind::TSpline)
      writeTSpline(out, model);
    else
      writeTMeshPart(out, model);

    const auto& control = model.controlPoints;
    out.u32(std::size_t(control.rows()));
    out.u32(std::size_t(control.cols()));
    for (Eigen::Index r = 0; r < control.rows(); ++r)
      for (Eigen::Index k = 0; k < control.cols(); ++k) out.f64(control(r, k));
    out.flush();
  });
}

SplineModel readSplineModel(const std::string& path) {
  return parseSplineModel(structure::readWholeFile(path), path);
}

SplineModel parseSplineModel(std::string_view data, const std::string& sourceName) {
  ModelReader in(data, sourceName);
  SplineModel model;

  in.section("header");
  if (data.empty()) in.fail("the file is empty, not an .msp spline model");
  const std::string_view start = data.substr(0, kMagic.size());
  if (start != kMagic.substr(0, start.size()))
    in.fail("not an .msp spline model (it does not start with the MSPLINE magic)");
  in.bytes(kMagic.size());
  const std::uint32_t version = in.value<std::uint32_t>();
  if (version < 1 || version > kVersion)
    in.fail("unsupported format version " + str(version) + " (this mspline reads versions 1 to " +
            str(kVersion) + ")");
  const std::uint32_t kind = in.value<std::uint32_t>();
  // Version 1 knew kind 1 only; version 2 added kinds 2 and 3.
  const std::uint32_t lastKind = version == 1 ? 1 : 3;
  if (kind < 1 || kind > lastKind)
    in.fail("unsupported spline kind " + str(kind) + " (format version " + str(version) +
            (version == 1 ? " knows kind 1, triangular B-spline)"
                          : " knows kinds 1, triangular B-spline, 2, T-spline, and 3, "
                            "subdivision surface)"));
  model.kind = SplineKind(kind);

  in.section("surface vertices");
  const int vertices = in.count(kVertexBytes, "surface vertices");
  model.surfaceVertices.resize(vertices, 3);
  for (int v = 0; v < vertices; ++v)
    for (int k = 0; k < 3; ++k) model.surfaceVertices(v, k) = in.value<double>();

  in.section("surface faces");
  model.surfaceFaces.resize(std::size_t(in.count(kFaceBytes, "surface faces")));
  for (auto& face : model.surfaceFaces)
    for (int& v : face) v = in.value<std::int32_t>();

  if (version >= 3) {
    in.section("filled surface faces");
    const int filled = in.count(1, "filled surface face flags");
    if (filled != 0 && filled != int(model.surfaceFaces.size()))
      in.fail(str(filled) + " filled-face flags for " + str(model.surfaceFaces.size()) +
              " surface faces");
    model.surfaceFaceFilled.resize(std::size_t(filled));
    for (char& flag : model.surfaceFaceFilled) {
      const std::uint8_t value = in.value<std::uint8_t>();
      if (value > 1) in.fail("a filled-face flag is " + str(value) + ", not 0 or 1");
      flag = char(value);
    }
  }

  if (model.kind == SplineKind::TriangularBSpline)
    readTriangularBSpline(in, model);
  else if (model.kind == SplineKind::TSpline)
    readTSpline(in, model);
  else
    readTMeshPart(in, model);

  in.section("control points");
  const std::uint64_t rows = in.value<std::uint32_t>();
  const std::uint64_t columns = in.value<std::uint32_t>();
  if (rows > kMaxCount || columns > kMaxCount)
    in.fail("the control points section declares " + str(rows) + " x " + str(columns) +
            " coordinates, more than the format holds (2^31 - 1 each)");
  in.requireFit(rows, columns * 8, str(rows) + " control points");
  model.controlPoints.resize(Eigen::Index(rows), Eigen::Index(columns));
  for (Eigen::Index r = 0; r < model.controlPoints.rows(); ++r)
    for (Eigen::Index k = 0; k < model.controlPoints.cols(); ++k)
      model.controlPoints(r, k) = in.value<double>();

  if (in.remaining() != 0)
    in.fail("the file goes on for " + str(in.remaining()) + " bytes after the last section");
  try {
    if (model.kind == SplineKind::TSpline && version < kCapsVersion) addCapAnchors(model);
    spline::TMesh mesh = checkModel(model);
    if (model.kind != SplineKind::TriangularBSpline) model.tmesh = std::move(mesh);
  } catch (const InputError& error) {
    in.fail(error.what());
  }
  return model;
}

}  // namespace mspline::io
