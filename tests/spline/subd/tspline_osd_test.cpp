#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "mspline/spline/subd/catmull_clark_limit.h"
#include "mspline/spline/subd/tspline_osd.h"
#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_bezier.h"
#include "mspline/spline/tspline/tspline_cap.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "support/test_tmeshes.h"

using namespace mspline;
using spline::OsdComparison;
using spline::OsdFaceClass;
using spline::TSplineSpace;
using test::anchorControl;
using test::cubeTMesh;
using test::CubeTMesh;
using test::randomPoints;

namespace {

std::vector<double> knotLines(int count, double spacing = 1.0) {
  std::vector<double> knots;
  for (int i = 0; i < count; ++i) knots.push_back(i * spacing);
  return knots;
}

// Independent of compareWithOpenSubdiv's sampling: at `perFace` random points of every regular
// face, TSplineSpace::evaluate, TSplineBezier and OpenSubdiv (on tsplineControlNet) agree in
// position and first derivatives (d/du = width d/dx). Returns the largest relative difference
// (positions to the bounding box diagonal, derivatives to the largest derivative met).
double regularFacesAgreement(const TSplineSpace& space, const Eigen::MatrixXd& control,
                             const OsdComparison& comparison, int perFace) {
  const spline::TSplineControlNet net = spline::tsplineControlNet(space, control);
  spline::CatmullClarkOptions options;
  options.boundary = spline::BoundaryRule::None;
  const spline::CatmullClarkLimit limit(net.points, net.faces, options);
  const spline::TSplineBezier bezier(space, control);
  const double scale = (control.colwise().maxCoeff() - control.colwise().minCoeff()).norm();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double positionError = 0.0, derivativeError = 0.0, derivativeScale = 0.0;
  for (int f = 0; f < space.mesh().numFaces(); ++f) {
    if (comparison.faceClass[f] != OsdFaceClass::Regular) continue;
    const spline::TMeshFace& face = space.mesh().faces[f];
    for (int k = 0; k < perFace; ++k) {
      const double u = unit(rng), v = unit(rng);
      const Eigen::Vector2d p(u * face.width, v * face.height);
      const auto reference = limit.evaluate(f, u, v);
      REQUIRE(reference.has_value());
      const spline::TSplinePoint direct = space.evaluate(control, {}, f, p, 1);
      Eigen::Vector3d position, ds, dt;
      bezier.evaluate(f, p, position, &ds, &dt);
      CHECK(direct.denominator == Approx(1.0).epsilon(1e-13));
      derivativeScale = std::max({derivativeScale, reference->du.norm(), reference->dv.norm()});
      positionError = std::max({positionError, (direct.position - reference->position).norm(),
                                (position - reference->position).norm()});
      derivativeError = std::max({derivativeError, (face.width * direct.ds - reference->du).norm(),
                                  (face.height * direct.dt - reference->dv).norm(),
                                  (face.width * ds - reference->du).norm(),
                                  (face.height * dt - reference->dv).norm()});
    }
  }
  return std::max(positionError / scale, derivativeError / std::max(derivativeScale, 1e-300));
}

}  // namespace

TEST_CASE("tspline_osd: a uniform planar grid is OpenSubdiv's limit on every regular face",
          "[spline]") {
  const int n = 10;
  const TSplineSpace space(spline::gridTMesh(knotLines(n), knotLines(n)));
  REQUIRE(space.numBasis() == n * n);
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), 3);
  spline::OsdCompareOptions options;
  options.samples = 20 * (n - 1) * (n - 1);
  const OsdComparison c = spline::compareWithOpenSubdiv(space, control, {}, options);
  INFO("regular " << c.regularFaces << ", deviation " << c.regularMaxDeviation << ", derivatives "
                  << c.regularMaxDerivativeDeviation);
  CHECK(c.regularFaces == (n - 3) * (n - 3));
  CHECK(c.irregularFaces == 0);
  CHECK(c.facesWithoutSurface == (n - 1) * (n - 1) - (n - 3) * (n - 3));
  CHECK(c.samples == 20 * (n - 3) * (n - 3));
  CHECK(c.regularSamples == c.samples);
  CHECK(c.regularMaxDeviation <= 1e-12);
  CHECK(c.regularMaxDerivativeDeviation <= 1e-12);
  CHECK(c.derivativeScale > 0.1);  // random points: derivatives of order one
  CHECK(c.msplinePointsPerSecond > 0.0);
  CHECK(c.osdPointsPerSecond > 0.0);
  // The inner faces are exactly the regular ones, and TSplineSpace::evaluate agrees too.
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const bool inner = i >= 1 && j >= 1 && i + 2 < n && j + 2 < n;
      CHECK((c.faceClass[j * (n - 1) + i] == OsdFaceClass::Regular) == inner);
    }
  CHECK(regularFacesAgreement(space, control, c, 4) <= 1e-12);
}

TEST_CASE("tspline_osd: equal knot intervals other than one agree in the face parameters",
          "[spline]") {
  // Intervals 2 x 0.5: OpenSubdiv's d/du is 2 d/dx and d/dv is d/dy / 2.
  const int n = 8;
  const TSplineSpace space(spline::gridTMesh(knotLines(n, 2.0), knotLines(n, 0.5)));
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), 4);
  const OsdComparison c = spline::compareWithOpenSubdiv(space, control, {});
  CHECK(c.regularFaces == (n - 3) * (n - 3));
  CHECK(c.regularMaxDeviation <= 1e-12);
  CHECK(c.regularMaxDerivativeDeviation <= 1e-12);
  CHECK(regularFacesAgreement(space, control, c, 2) <= 1e-12);
}

TEST_CASE("tspline_osd: unequal knot intervals and weights make faces irregular", "[spline]") {
  const int n = 14;
  // Cell column 4 is twice as wide. The 16 functions over cell column i have knots on the vertex
  // lines i - 3 .. i + 4, so the face is uniform only when cell 4 is not among cells i - 3 .. i
  // + 3.
  std::vector<double> x = knotLines(n);
  for (int i = 5; i < n; ++i) x[i] += 1.0;
  const TSplineSpace space(spline::gridTMesh(x, knotLines(n)));
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), 5);
  const OsdComparison c = spline::compareWithOpenSubdiv(space, control, {});
  int expectedRegular = 0;
  for (int j = 1; j + 2 < n; ++j)
    for (int i = 1; i + 2 < n; ++i) {
      const bool uniform = i + 3 < 4 || i - 3 > 4;
      expectedRegular += uniform;
      CHECK((c.faceClass[j * (n - 1) + i] == OsdFaceClass::Regular) == uniform);
    }
  REQUIRE(expectedRegular == 4 * (n - 3));  // cell columns 8 .. 11
  CHECK(c.regularFaces == expectedRegular);
  CHECK(c.irregularFaces == (n - 3) * (n - 3) - expectedRegular);
  CHECK(c.regularMaxDeviation <= 1e-12);
  CHECK(c.irregularMaxDeviation > 1e-6);  // a different spline on the same net

  // One weight other than 1: the 16 faces around its anchor are rational, the rest agree.
  const TSplineSpace uniform(spline::gridTMesh(knotLines(n), knotLines(n)));
  Eigen::VectorXd weights = Eigen::VectorXd::Ones(uniform.numBasis());
  weights[uniform.anchorOfVertex()[4 * n + 4]] = 2.0;
  const OsdComparison w =
      spline::compareWithOpenSubdiv(uniform, randomPoints(uniform.numBasis(), 6), weights);
  CHECK(w.regularFaces == (n - 3) * (n - 3) - 16);
  CHECK(w.irregularFaces == 16);
  CHECK(w.regularMaxDeviation <= 1e-12);
  CHECK(w.irregularMaxDeviation > 1e-6);
}

TEST_CASE("tspline_osd: a periodic torus grid is regular everywhere", "[spline]") {
  const int n = 16, m = 8;
  const TSplineSpace space(spline::gridTMesh(knotLines(n + 1), knotLines(m + 1), true, true));
  REQUIRE(space.numBasis() == n * m);
  Eigen::MatrixXd vertexPoints(n * m, 3);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n, b = 2 * kPi * j / m, r = 1.0 + 0.4 * std::cos(b);
      vertexPoints.row(j * n + i) << r * std::cos(a), r * std::sin(a), 0.4 * std::sin(b);
    }
  const Eigen::MatrixXd control = anchorControl(space, vertexPoints);
  spline::OsdCompareOptions options;
  options.samples = 4000;
  const OsdComparison c = spline::compareWithOpenSubdiv(space, control, {}, options);
  INFO("deviation " << c.regularMaxDeviation << ", derivatives "
                    << c.regularMaxDerivativeDeviation);
  CHECK(c.regularFaces == n * m);
  CHECK(c.irregularFaces == 0);
  CHECK(c.facesWithoutSurface == 0);
  CHECK(c.samples == options.samples);
  CHECK(c.regularMaxDeviation <= 1e-12);
  CHECK(c.regularMaxDerivativeDeviation <= 1e-12);
  CHECK(regularFacesAgreement(space, control, c, 2) <= 1e-12);
}

TEST_CASE("tspline_osd: a cube with 8 valence-3 vertices agrees but on the cap faces", "[spline]") {
  const int k = 8;
  const CubeTMesh cube = cubeTMesh(k, 9);
  const spline::TMesh& mesh = cube.mesh;
  REQUIRE(mesh.numFaces() == 6 * k * k);
  REQUIRE(mesh.numVertices == 6 * k * k + 2);
  int extraordinary = 0;
  for (int v = 0; v < mesh.numVertices; ++v)
    if (mesh.isExtraordinary(v)) {
      ++extraordinary;
      CHECK(mesh.quarterTurnsAround[v] == 3);
    }
  REQUIRE(extraordinary == 8);
  const TSplineSpace space(mesh);
  CHECK(space.missingAnchors().empty());
  const Eigen::MatrixXd control = anchorControl(space, cube.vertexPoints);
  spline::OsdCompareOptions options;
  options.samples = 20 * mesh.numFaces();
  const OsdComparison c = spline::compareWithOpenSubdiv(space, control, {}, options);
  WARN("cube k = " << k << ": " << c.regularFaces << " regular, " << c.irregularFaces
                   << " irregular faces; regular deviation " << c.regularMaxDeviation
                   << " (derivatives " << c.regularMaxDerivativeDeviation
                   << "), irregular (caps against Gregory patches) deviation "
                   << c.irregularMaxDeviation << " (derivatives "
                   << c.irregularMaxDerivativeDeviation << "); " << c.msplinePointsPerSecond
                   << " vs " << c.osdPointsPerSecond << " points/s");
  // The net is the control points everywhere. Only the 3 faces around each corner (the caps) are
  // irregular; the faces next to them are uniform B-splines of the net, as OpenSubdiv's.
  CHECK(c.facesWithoutSurface == 0);
  CHECK(c.irregularFaces == 8 * 3);
  CHECK(c.regularFaces == 6 * k * k - 8 * 3);
  CHECK(c.samples == options.samples);
  CHECK(c.regularMaxDeviation <= 1e-12);
  CHECK(c.regularMaxDerivativeDeviation <= 1e-12);
  CHECK(c.irregularMaxDeviation > 0.0);
  // Two surfaces of one net near its points: the caps and the Gregory patches differ by a small
  // fraction of the cube.
  CHECK(c.irregularMaxDeviation < 0.01);
  for (int f = 0; f < mesh.numFaces(); ++f)
    CHECK((c.faceClass[f] == OsdFaceClass::Irregular) == (space.capFace(f) != nullptr));
  CHECK(regularFacesAgreement(space, control, c, 2) <= 1e-12);
}

TEST_CASE("tspline_osd: a T-mesh with T-junctions is refused", "[spline]") {
  // Two cells below one twice as wide: vertex 4 is a T-junction on the top face's side.
  std::vector<spline::TMeshFace> faces(3);
  faces[0].vertices = {0, 1, 4, 3};
  faces[0].positions = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  faces[1].vertices = {1, 2, 5, 4};
  faces[1].positions = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  faces[2].vertices = {3, 4, 5, 7, 6};
  faces[2].positions = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {0, 1}};
  const TSplineSpace space(spline::buildTMesh(8, faces));
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), 1);
  CHECK_THROWS_AS(spline::compareWithOpenSubdiv(space, control, {}), structure::InputError);
  CHECK_THROWS_WITH(spline::compareWithOpenSubdiv(space, control, {}),
                    Catch::Contains("T-junctions") && Catch::Contains("face 2"));
  CHECK_THROWS_AS(spline::tsplineControlNet(space, control), structure::InputError);
}

TEST_CASE("tspline_osd: unanchored vertices get ring averages of anchored ones", "[spline]") {
  const CubeTMesh cube = cubeTMesh(8, 2);
  const spline::TMesh& mesh = cube.mesh;
  // Leave out the corners and their rings (what models before caps had no control point for).
  std::vector<char> placed(std::size_t(mesh.numVertices), 1);
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(mesh.numVertices));
  for (const auto& face : mesh.faces)
    for (std::size_t k = 0; k < 4; ++k) {
      neighbours[face.vertices[k]].push_back(face.vertices[(k + 1) % 4]);
      neighbours[face.vertices[(k + 1) % 4]].push_back(face.vertices[k]);
    }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  for (const auto& face : mesh.faces)
    for (int v : face.vertices)
      if (mesh.isExtraordinary(v))
        for (int u : face.vertices) placed[u] = 0;
  Eigen::MatrixXd points = cube.vertexPoints;
  spline::fillByRingAverages(mesh, points, placed, "test");
  int unanchored = 0;
  for (int v = 0; v < mesh.numVertices; ++v) {
    if (placed[v]) {
      CHECK(points.row(v) == cube.vertexPoints.row(v));
      continue;
    }
    ++unanchored;
    // First ring: the placed neighbours' average.
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    int count = 0;
    for (int u : neighbours[v])
      if (placed[u]) sum += cube.vertexPoints.row(u), ++count;
    if (count > 0) CHECK((points.row(v) - sum / count).norm() <= 1e-15);
  }
  // Each corner and the 6 vertices of its 3 faces.
  CHECK(unanchored == 8 * 7);
  // The net of a capped T-spline is its control points.
  const TSplineSpace space(mesh);
  const Eigen::MatrixXd control = anchorControl(space, cube.vertexPoints);
  const spline::TSplineControlNet net = spline::tsplineControlNet(space, control);
  CHECK(net.points == cube.vertexPoints);
  CHECK_THROWS_AS(spline::tsplineControlNet(space, control, Eigen::MatrixXd::Zero(3, 3)),
                  structure::InputError);
}
