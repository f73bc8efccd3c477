#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/model_surface.h"
#include "mspline/spline/tribspline/tri_bspline_fit_space.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "support/test_data.h"
#include "support/test_tmeshes.h"

using namespace mspline;
using Catch::Matchers::Contains;

namespace {

// A T-spline on the surface of a cube (8 extraordinary vertices: holes) with random weights.
spline::SplineModel cubeTSpline() {
  const test::CubeTMesh cube = test::cubeTMesh(5);
  const spline::TSplineSpace space(cube.mesh);
  spline::SplineModel model;
  model.kind = spline::SplineKind::TSpline;
  model.tmesh = cube.mesh;
  model.controlPoints = test::anchorControl(space, cube.vertexPoints);
  model.weights = test::randomWeights(space.numBasis(), 3u);
  return model;
}

// A planar T-spline with a T-junction (test::stoppedLine) and an open boundary, over a wavy
// height field, with random weights.
spline::SplineModel planarTSpline() {
  spline::SplineModel model;
  model.kind = spline::SplineKind::TSpline;
  model.tmesh = test::stoppedLine();
  const spline::TSplineSpace space(model.tmesh);
  const std::vector<Eigen::Vector2d> plane = test::planarVertices(model.tmesh);
  Eigen::MatrixXd points(model.tmesh.numVertices, 3);
  for (int v = 0; v < model.tmesh.numVertices; ++v) {
    const Eigen::Vector2d& p = plane[std::size_t(v)];
    points.row(v) << p.x(), p.y(), std::sin(p.x()) * std::cos(0.7 * p.y());
  }
  model.controlPoints = test::anchorControl(space, points);
  model.weights = test::randomWeights(space.numBasis(), 4u);
  return model;
}

// Per face: it has a corner at a cone (a cone of the domain) or, on a T-mesh, a vertex in common
// with a face at an extraordinary vertex (the T-spline's hole reaches that far: no function is
// anchored where its support holds the extraordinary vertex).
std::vector<char> facesNearCones(const spline::SplineModel& model) {
  if (model.kind == spline::SplineKind::TriangularBSpline) {
    std::vector<char> out;
    for (const auto& corners : model.domain.faces)
      out.push_back(std::any_of(corners.begin(), corners.end(),
                                [&](int v) { return model.domain.cone[std::size_t(v)] != 0; }));
    return out;
  }
  const spline::TMesh& mesh = model.tmesh;
  std::vector<char> ring(std::size_t(mesh.numVertices), 0);
  for (const spline::TMeshFace& face : mesh.faces)
    if (std::any_of(face.vertices.begin(), face.vertices.end(),
                    [&](int v) { return mesh.isExtraordinary(v); }))
      for (int v : face.vertices) ring[std::size_t(v)] = 1;
  std::vector<char> out;
  for (const spline::TMeshFace& face : mesh.faces)
    out.push_back(std::any_of(face.vertices.begin(), face.vertices.end(),
                              [&](int v) { return ring[std::size_t(v)] != 0; }));
  return out;
}

// The samples' rows reproduce the tessellation: positions, normals where the vertex is the
// surface at a point, a partition of unity; means exactly where the tessellation has them.
void checkSamples(const spline::SplineModel& model, int resolution) {
  const spline::ModelSurface surface(model, "model.msp");
  const spline::ModelTessellation t = surface.tessellate(model.controlPoints, resolution);
  const auto n = Eigen::Index(t.mesh.positions.size());
  REQUIRE(t.sampleOffsets.size() == std::size_t(n) + 1);
  const spline::SurfaceSamples s = surface.samples(t);
  REQUIRE(s.value.rows() == n);
  REQUIRE(s.value.cols() == surface.numControlPoints());
  REQUIRE(s.isMean.size() == std::size_t(n));
  const Eigen::MatrixXd& c = model.controlPoints;
  const Eigen::MatrixX3d x = structure::pointMatrix(t.mesh.positions);
  const double scale = structure::boundingBoxDiagonal(x);

  // (a) value * C is the tessellation.
  const Eigen::MatrixXd y = s.value * c;
  CHECK((y - x).cwiseAbs().maxCoeff() <= 1e-12 * scale);
  // (c) Partition of unity, and its derivatives vanish.
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(c.rows());
  CHECK((s.value * ones - Eigen::VectorXd::Ones(n)).cwiseAbs().maxCoeff() <= 1e-12);
  const Eigen::VectorXd dsSum = s.ds * ones, dtSum = s.dt * ones;
  const Eigen::VectorXd dsSize = s.ds.cwiseAbs() * ones, dtSize = s.dt.cwiseAbs() * ones;
  for (Eigen::Index v = 0; v < n; ++v) {
    CHECK(std::abs(dsSum[v]) <= 1e-9 * std::max(1.0, dsSize[v]));
    CHECK(std::abs(dtSum[v]) <= 1e-9 * std::max(1.0, dtSize[v]));
  }
  // Means: the tessellation's mean vertices, several points each only there; the others one.
  std::vector<char> mean(std::size_t(n), 0);
  for (std::int64_t v : t.meanVertices) mean[std::size_t(v)] = 1;
  int several = 0;
  for (Eigen::Index v = 0; v < n; ++v) {
    const auto points = t.sampleOffsets[std::size_t(v) + 1] - t.sampleOffsets[std::size_t(v)];
    CHECK(s.isMean[std::size_t(v)] == mean[std::size_t(v)]);
    CHECK(points >= 1);
    if (!mean[std::size_t(v)]) CHECK(points == 1);
    several += points > 1;
  }
  // (b) Normals from the derivative rows, at every vertex that is the surface at a point and
  // where they are well conditioned: only next to a cone may a derivative (nearly) vanish (edges
  // the normalization collapses, Catmull-Clark's extraordinary points), and the tessellation's
  // normal there is as much rounding as ours.
  const Eigen::MatrixXd ds = s.ds * c, dt = s.dt * c;
  double worst = 0.0;
  int compared = 0, illConditioned = 0;
  const std::vector<char> nearCone = facesNearCones(model);
  for (Eigen::Index v = 0; v < n; ++v) {
    if (s.isMean[std::size_t(v)]) {
      CHECK(s.ds.row(v).nonZeros() == 0);
      CHECK(s.dt.row(v).nonZeros() == 0);
      continue;
    }
    const Eigen::Vector3d cross = Eigen::Vector3d(ds.row(v)).cross(Eigen::Vector3d(dt.row(v)));
    const double largest = std::max(ds.row(v).norm(), dt.row(v).norm());
    if (!(cross.norm() > 1e-4 * largest * largest)) {
      ++illConditioned;
      const int face = t.samplePoints[std::size_t(t.sampleOffsets[std::size_t(v)])].face;
      CHECK(nearCone[std::size_t(face)]);
      continue;
    }
    const auto& expected = t.normals[std::size_t(v)];
    worst = std::max(
        worst,
        (cross.normalized() - Eigen::Vector3d(expected[0], expected[1], expected[2])).norm());
    ++compared;
  }
  INFO(n << " vertices, " << t.meanVertices.size() << " means (" << several
         << " of several points), " << compared << " normals compared, " << illConditioned
         << " ill-conditioned");
  CHECK(compared + illConditioned + int(t.meanVertices.size()) == n);
  CHECK(worst <= 1e-9);
}

// (d) Moving control point `row` moves every vertex by its entry in the row's column times the
// move: exactly the vertices with a non-zero there move.
void checkLocalEdit(const spline::SplineModel& model, int row, int resolution) {
  const spline::ModelSurface surface(model, "model.msp");
  const spline::ModelTessellation before = surface.tessellate(model.controlPoints, resolution);
  const Eigen::SparseMatrix<double> byColumn = surface.samples(before).value;
  const double scale =
      structure::boundingBoxDiagonal(structure::pointMatrix(before.mesh.positions));
  const Eigen::Vector3d move = 0.01 * scale * Eigen::Vector3d(1.0, -2.0, 2.0) / 3.0;
  Eigen::MatrixXd moved = model.controlPoints;
  moved.row(row) += move.transpose();
  const spline::ModelTessellation after = surface.tessellate(moved, resolution);
  // The same points evaluated, so that the difference is the basis function's share.
  REQUIRE(after.sampleOffsets == before.sampleOffsets);
  REQUIRE(after.samplePoints.size() == before.samplePoints.size());
  for (std::size_t k = 0; k < after.samplePoints.size(); ++k) {
    REQUIRE(after.samplePoints[k].face == before.samplePoints[k].face);
    REQUIRE(after.samplePoints[k].position == before.samplePoints[k].position);
  }
  const Eigen::MatrixX3d change =
      structure::pointMatrix(after.mesh.positions) - structure::pointMatrix(before.mesh.positions);
  Eigen::MatrixX3d predicted = Eigen::MatrixX3d::Zero(change.rows(), 3);
  int inColumn = 0, visible = 0, movedMeans = 0;
  for (Eigen::SparseMatrix<double>::InnerIterator it(byColumn, row); it; ++it) {
    predicted.row(it.row()) = it.value() * move.transpose();
    ++inColumn;
    visible += std::abs(it.value()) * move.norm() > 1e-12 * scale;
    movedMeans += std::binary_search(before.meanVertices.begin(), before.meanVertices.end(),
                                     std::int64_t(it.row()));
  }
  int changed = 0;
  for (Eigen::Index v = 0; v < change.rows(); ++v) changed += change.row(v).norm() > 1e-12 * scale;
  INFO("row " << row << ": " << inColumn << " vertices in its column, " << movedMeans << " means, "
              << changed << " changed");
  CHECK(inColumn > 0);
  CHECK(inColumn < change.rows() / 4);
  CHECK((change - predicted).cwiseAbs().maxCoeff() <= 1e-12 * scale);
  CHECK(changed == visible);
}

// A control point row acting on a cone's vertex (a mean around the cone but for subdivision
// surfaces).
int rowAtCone(const spline::SplineModel& model, int resolution) {
  const spline::ModelSurface surface(model, "model.msp");
  const spline::ModelTessellation t = surface.tessellate(model.controlPoints, resolution);
  REQUIRE(!t.coneVertices.empty());
  const spline::SurfaceSamples s = surface.samples(t);
  const Eigen::Index v = Eigen::Index(t.coneVertices.front());
  Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(s.value, v);
  return it ? int(it.col()) : -1;
}

// Per T-mesh vertex: the vertex lies inside a side of a face (a boundary vertex of the face whose
// angle there is a half turn), found from the angle sums: every face contributes one quarter turn
// at its corners and two inside its sides.
std::vector<char> tJunctionVertices(const spline::TMesh& mesh) {
  std::vector<int> faces(std::size_t(mesh.numVertices), 0);
  for (const spline::TMeshFace& face : mesh.faces)
    for (int v : face.vertices) ++faces[std::size_t(v)];
  std::vector<char> out(std::size_t(mesh.numVertices), 0);
  for (int v = 0; v < mesh.numVertices; ++v)
    out[std::size_t(v)] = faces[std::size_t(v)] < mesh.quarterTurnsAround[std::size_t(v)];
  return out;
}

// (e) Every line joins two distinct shown points; extraordinary and T-junction rows are those of
// the T-mesh's vertices.
void checkNet(const spline::SplineModel& model) {
  const spline::ModelSurface surface(model, "model.msp");
  const spline::ModelControlNet net = surface.controlNet();
  const int rows = surface.numControlPoints();
  std::vector<char> shown(std::size_t(rows), 0);
  for (int p : net.points) {
    REQUIRE(p >= 0);
    REQUIRE(p < rows);
    CHECK(!shown[std::size_t(p)]);
    shown[std::size_t(p)] = 1;
  }
  for (const auto& [a, b] : net.lines) {
    REQUIRE(std::min(a, b) >= 0);
    REQUIRE(std::max(a, b) < rows);
    CHECK(shown[std::size_t(a)]);
    CHECK(shown[std::size_t(b)]);
    CHECK(a != b);
  }
  for (int r : net.extraordinary) CHECK(shown[std::size_t(r)]);
  for (int r : net.tJunctions) CHECK(shown[std::size_t(r)]);
  CHECK(std::is_sorted(net.extraordinary.begin(), net.extraordinary.end()));
  CHECK(std::is_sorted(net.tJunctions.begin(), net.tJunctions.end()));
  if (model.kind == spline::SplineKind::TriangularBSpline) {
    // All rows; per face the edges of the triangular grid of degree n: 3 n (n + 1) / 2.
    const int n = model.degree;
    CHECK(net.points.size() == std::size_t(rows));
    CHECK(net.lines.size() == std::size_t(model.domain.faceCount() * 3 * n * (n + 1) / 2));
    CHECK(net.extraordinary.empty());
    CHECK(net.tJunctions.empty());
    return;
  }
  const spline::TMesh& mesh = model.tmesh;
  // The row of each T-mesh vertex: its anchor (anchors follow the vertex order), or the vertex.
  std::vector<int> rowOf(std::size_t(mesh.numVertices), -1);
  if (model.kind == spline::SplineKind::TSpline)
    rowOf = spline::TSplineSpace(mesh).anchorOfVertex();
  else
    for (int v = 0; v < mesh.numVertices; ++v) rowOf[std::size_t(v)] = v;
  std::vector<int> extraordinary, tJunctions;
  const std::vector<char> inSide = tJunctionVertices(mesh);
  int unanchoredCones = 0;
  for (int v = 0; v < mesh.numVertices; ++v) {
    const int row = rowOf[std::size_t(v)];
    unanchoredCones += mesh.isExtraordinary(v) && row < 0;
    if (row < 0) continue;
    if (mesh.isExtraordinary(v)) extraordinary.push_back(row);
    if (inSide[std::size_t(v)]) tJunctions.push_back(row);
  }
  CHECK(net.extraordinary == extraordinary);
  CHECK(net.tJunctions == tJunctions);
  CHECK(net.points.size() == std::size_t(rows));  // every function is anchored at a vertex
  if (model.kind == spline::SplineKind::TSpline) {
    // Extraordinary vertices anchor functions (caps).
    CHECK(int(net.extraordinary.size()) == mesh.numExtraordinary());
    CHECK(unanchoredCones == 0);
  } else {
    CHECK(int(net.extraordinary.size()) == mesh.numExtraordinary());
    // Every T-mesh edge once: V - E + F is the Euler characteristic of the closed (filled) head.
    CHECK(mesh.numVertices - int(net.lines.size()) + mesh.numFaces() == 2);
  }
}

}  // namespace

TEST_CASE("model_surface: the samples reproduce the tessellation of every kind", "[spline]") {
  for (const std::string kind : {"tspline", "tribspline", "subd"}) {
    INFO(kind);
    checkSamples(test::headModel(kind), 4);
  }
  INFO("cube T-spline");
  checkSamples(cubeTSpline(), 3);
  INFO("planar T-spline");
  checkSamples(planarTSpline(), 3);
}

TEST_CASE("model_surface: sample points, cones and means of the tessellations", "[spline]") {
  SECTION("triangular B-spline: a mean per cone, of the points around it") {
    const spline::SplineModel& model = test::headModel("tribspline");
    const spline::ModelSurface surface(model, "head.msp");
    const spline::ModelTessellation t = surface.tessellate(model.controlPoints, 3);
    const long cones = std::count(model.domain.cone.begin(), model.domain.cone.end(), char(1));
    CHECK(cones == 4);
    CHECK(t.coneVertices.size() == std::size_t(cones));
    CHECK(t.meanVertices == t.coneVertices);
    // One point per corner of a face at a cone, just inside that corner.
    const spline::SplineDomain& domain = model.domain;
    const spline::TriBSplineSpace space(domain, model.knots);
    std::size_t corners = 0, points = 0;
    for (const auto& face : domain.faces)
      for (int v : face) corners += domain.cone[std::size_t(v)] != 0;
    for (std::int64_t v : t.coneVertices)
      for (auto k = t.sampleOffsets[std::size_t(v)]; k < t.sampleOffsets[std::size_t(v) + 1]; ++k) {
        ++points;
        const spline::FacePoint& p = t.samplePoints[std::size_t(k)];
        const Eigen::Vector3d b = spline::toDomainPoint(space, p).barycentric;
        int corner = 0;
        b.maxCoeff(&corner);
        CHECK(domain.cone[std::size_t(domain.faces[std::size_t(p.face)][std::size_t(corner)])]);
        CHECK(b[corner] >= 0.9);
        CHECK(b[corner] < 1.0);
      }
    CHECK(points == corners);
    REQUIRE(!t.report.empty());
    CHECK(t.report[1].name == "cone_vertices");
    CHECK(t.report[1].value == double(cones));
  }
  SECTION("T-spline: the surface at the extraordinary vertices (caps), no means") {
    const spline::SplineModel model = cubeTSpline();
    const spline::ModelSurface surface(model, "cube.msp");
    const spline::ModelTessellation t = surface.tessellate(model.controlPoints, 4);
    CHECK(t.coneVertices.size() == 8);
    for (std::int64_t v : t.coneVertices) CHECK(model.tmesh.isExtraordinary(int(v)));
    CHECK(t.meanVertices.empty());
    CHECK(t.samplePoints.size() == t.mesh.positions.size());
  }
  SECTION("subdivision: the limit surface at the extraordinary vertices, no means") {
    const spline::SplineModel& model = test::headModel("subd");
    const spline::ModelSurface surface(model, "head.msp");
    const spline::ModelTessellation t = surface.tessellate(model.controlPoints, 2);
    CHECK(t.coneVertices.size() == std::size_t(model.tmesh.numExtraordinary()));
    CHECK(!t.coneVertices.empty());
    CHECK(t.meanVertices.empty());
    CHECK(t.samplePoints.size() == t.mesh.positions.size());
  }
}

TEST_CASE("model_surface: moving a control point changes the vertices of its column", "[spline]") {
  for (const std::string kind : {"tspline", "tribspline", "subd"}) {
    INFO(kind);
    const spline::SplineModel& model = test::headModel(kind);
    checkLocalEdit(model, int(model.controlPoints.rows() / 2), 3);
    const int atCone = rowAtCone(model, 3);
    REQUIRE(atCone >= 0);
    checkLocalEdit(model, atCone, 3);
  }
}

TEST_CASE("model_surface: control nets of every kind", "[spline]") {
  for (const std::string kind : {"tspline", "tribspline", "subd"}) {
    INFO(kind);
    checkNet(test::headModel(kind));
  }
  // The fit refined the head's T-spline: T-junctions were compared.
  CHECK(!spline::ModelSurface(test::headModel("tspline"), "head.msp")
             .controlNet()
             .tJunctions.empty());
  INFO("cube T-spline");
  checkNet(cubeTSpline());
  // The line x = 4 stops at (4, 4): one T-junction, a corner of the faces on its three sides.
  INFO("planar T-spline");
  const spline::SplineModel planar = planarTSpline();
  checkNet(planar);
  const spline::TSplineSpace space(planar.tmesh);
  const int junction =
      test::vertexAt(planar.tmesh, test::faceOrigins(planar.tmesh, Eigen::Vector2d(3.0, 4.0)),
                     Eigen::Vector2d(4.0, 4.0));
  REQUIRE(junction >= 0);
  CHECK(spline::ModelSurface(planar, "planar.msp").controlNet().tJunctions ==
        std::vector<int>{space.anchorOfVertex()[std::size_t(junction)]});
}

TEST_CASE("model_surface: control points or weights that do not fit name the file", "[spline]") {
  for (const std::string kind : {"tspline", "tribspline", "subd"}) {
    INFO(kind);
    spline::SplineModel model = test::headModel(kind);
    model.controlPoints.conservativeResize(model.controlPoints.rows() - 1, 3);
    CHECK_THROWS_AS(spline::ModelSurface(model, "/models/bad.msp"), structure::InputError);
    CHECK_THROWS_WITH(spline::ModelSurface(model, "/models/bad.msp"),
                      Contains("/models/bad.msp") && Contains("control points"));
  }
  spline::SplineModel model = test::headModel("tspline");
  model.weights = Eigen::VectorXd::Ones(3);
  CHECK_THROWS_WITH(spline::ModelSurface(model, "/models/w.msp"),
                    Contains("/models/w.msp") && Contains("weights"));
  const spline::SplineModel& good = test::headModel("subd");
  const spline::ModelSurface surface(good, "/models/good.msp");
  CHECK_THROWS_WITH(surface.tessellate(good.controlPoints, 0), Contains("/models/good.msp"));
  CHECK_THROWS_AS(surface.tessellate(Eigen::MatrixXd::Zero(3, 3), 2), structure::InputError);
}
