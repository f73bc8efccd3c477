#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>

#include "mspline/spline/model/model_surface.h"
#include "mspline/spline/quality/surface_quality.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "support/test_tmeshes.h"

using namespace mspline;

namespace {

// A T-spline on the open (columns x rows)-cell grid, control point (i, j) of the grid vertex
// (i, j) moved to point(i, j).
spline::SplineModel gridModel(int columns, int rows,
                              const std::function<Eigen::Vector3d(int, int)>& point) {
  spline::SplineModel model;
  model.kind = spline::SplineKind::TSpline;
  model.tmesh = spline::gridTMesh(test::unitKnots(columns), test::unitKnots(rows));
  Eigen::MatrixXd vertexPoints(model.tmesh.numVertices, 3);
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i <= columns; ++i)
      vertexPoints.row(j * (columns + 1) + i) = point(i, j).transpose();
  const spline::TSplineSpace space(model.tmesh);
  model.controlPoints = test::anchorControl(space, vertexPoints);
  model.weights = Eigen::VectorXd::Ones(space.numBasis());
  return model;
}

// The scan of `model`: its surface tessellated at `resolution`, every vertex then moved by
// offset(position, normal). The model's surface becomes that scan (its vertices at the
// tessellation's parameters), as a fit leaves it.
structure::TriMesh scanOf(
    spline::SplineModel& model, int resolution,
    const std::function<Eigen::Vector3d(const Eigen::Vector3d&, const Eigen::Vector3d&)>& offset) {
  const spline::ModelSurface surface(model, "grid");
  spline::ModelTessellation t = surface.tessellate(model.controlPoints, resolution);
  model.surfaceVertexTMeshPoints.clear();
  for (std::size_t v = 0; v < t.mesh.positions.size(); ++v) {
    auto& p = t.mesh.positions[v];
    const Eigen::Vector3d moved =
        offset(Eigen::Vector3d(p[0], p[1], p[2]),
               Eigen::Vector3d(t.normals[v][0], t.normals[v][1], t.normals[v][2]));
    p = {moved.x(), moved.y(), moved.z()};
    model.surfaceVertexTMeshPoints.push_back(t.samplePoints[std::size_t(t.sampleOffsets[v])]);
  }
  model.surfaceVertices = structure::pointMatrix(t.mesh.positions);
  model.surfaceFaces = structure::triangleIndices(t.mesh);
  return structure::toTriMesh(t.mesh);
}

const auto unmoved = [](const Eigen::Vector3d& p, const Eigen::Vector3d&) { return p; };

Eigen::Vector3d flat(int i, int j) {
  return {double(i), double(j), 0.0};
}

// A smooth bump over the grid.
Eigen::Vector3d curved(int i, int j) {
  return {double(i), double(j), 2.0 * std::sin(0.5 * i) * std::cos(0.4 * j)};
}

}  // namespace

TEST_CASE("surface_quality: a flat patch is flat, fold-free and on its planar scan", "[spline]") {
  spline::SplineModel model = gridModel(6, 5, flat);
  const structure::TriMesh scan = scanOf(model, 2, unmoved);
  const spline::SurfaceQuality q = spline::measureQuality(model, &scan);
  CHECK(q.withScan);
  CHECK(q.smoothness.coarse.max == 0.0);
  CHECK(q.smoothness.fine.max == 0.0);
  CHECK(q.smoothness.coarse.pairs > 0);
  CHECK(q.smoothness.creases == 0);
  CHECK(q.folds.total() == 0);
  CHECK(q.folds.triangles > 0);
  // Every scan vertex is measured, and lies on the surface; the surface covers the scan exactly
  // (a tensor-product grid with planar control points has a rectangle as image).
  CHECK(q.distances.scanToSurface.count == int(scan.n_vertices()));
  // (Newton stops where its gains are at the rounding of the positions.)
  CHECK(q.distances.scanToSurface.max < 1e-10);
  CHECK(q.distances.surfaceToScan.max < 1e-12);
  CHECK(q.distances.unconvergedProjections == 0);
  // Uniform in the middle, squeezed towards the open boundary by the normalization.
  CHECK(q.regularity.minRelativeJacobian > 0.0);
  CHECK(q.regularity.minRelativeJacobian < 1.0);
}

TEST_CASE("surface_quality: the scan moved by delta is delta away both ways", "[spline]") {
  const double delta = 0.01;
  for (const auto& point : {std::function<Eigen::Vector3d(int, int)>(flat),
                            std::function<Eigen::Vector3d(int, int)>(curved)}) {
    spline::SplineModel model = gridModel(6, 5, point);
    // Along the surface's own normals: every scan vertex's closest surface point is its base
    // point (delta is far below the radius of curvature).
    const structure::TriMesh scan =
        scanOf(model, 2, [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
          return Eigen::Vector3d(p + delta * n);
        });
    const double diagonal = structure::boundingBoxDiagonal(scan);
    const spline::SurfaceQuality q = spline::measureQuality(model, &scan);
    CHECK(q.distances.diagonal == Approx(diagonal));
    CHECK(q.distances.scanToSurface.rms == Approx(delta / diagonal).epsilon(1e-9));
    CHECK(q.distances.scanToSurface.max == Approx(delta / diagonal).epsilon(1e-9));
    CHECK(q.distances.unconvergedProjections == 0);
    CHECK(q.folds.againstScan == 0);
  }
  // Flat: the surface samples are delta from the moved plane, exactly.
  spline::SplineModel model = gridModel(6, 5, flat);
  const structure::TriMesh scan =
      scanOf(model, 2, [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
        return Eigen::Vector3d(p + delta * n);
      });
  const spline::SurfaceQuality q = spline::measureQuality(model, &scan);
  const double diagonal = structure::boundingBoxDiagonal(scan);
  CHECK(q.distances.surfaceToScan.rms == Approx(delta / diagonal).epsilon(1e-12));
  CHECK(q.distances.surfaceToScan.max == Approx(delta / diagonal).epsilon(1e-12));
  CHECK(q.distances.surfaceToScan.p99 == Approx(delta / diagonal).epsilon(1e-12));
}

TEST_CASE("surface_quality: halving the spacing halves the dihedral angles of a smooth surface",
          "[spline]") {
  spline::SplineModel model = gridModel(8, 8, curved);
  const spline::SurfaceQuality q = spline::measureQuality(model, nullptr);
  CHECK_FALSE(q.withScan);
  CHECK(q.distances.scanToSurface.count == 0);
  CHECK(q.folds.total() == 0);
  CHECK(q.smoothness.coarse.resolution == 3);
  CHECK(q.smoothness.fine.resolution == 6);
  CHECK(q.smoothness.fine.p99 > 0.0);
  CHECK(q.smoothness.p99Ratio.value_or(0.0) > 1.7);
  CHECK(q.smoothness.p99Ratio.value_or(99.0) < 2.3);
}

TEST_CASE("surface_quality: a plane has no p99 ratio", "[spline]") {
  // Every dihedral angle is round-off: their quotient would be noise, not a smoothness figure.
  spline::SplineModel model =
      gridModel(4, 4, [](int i, int j) { return Eigen::Vector3d(i, 0.5 * j, 0.0); });
  const spline::SurfaceQuality q = spline::measureQuality(model, nullptr);
  CHECK(q.smoothness.fine.p99 < spline::SurfaceSmoothness::kFlatDegrees);
  CHECK_FALSE(q.smoothness.p99Ratio.has_value());
  CHECK(q.smoothness.creases == 0);
  // A slight bend brings it back.
  model = gridModel(4, 4, [](int i, int j) { return Eigen::Vector3d(i, 0.5 * j, 0.01 * i * i); });
  const spline::SurfaceQuality bent = spline::measureQuality(model, nullptr);
  REQUIRE(bent.smoothness.p99Ratio.has_value());
  CHECK(*bent.smoothness.p99Ratio > 1.7);
}

TEST_CASE("surface_quality: a crease keeps its dihedral angle at any resolution", "[spline]") {
  // Three equal control columns in the middle: the surface is two planes meeting along the
  // knot line x = 2 at the angle 2 atan(1/2) between their normals. Narrow, so that more than 1%
  // of the pairs are on the crease.
  const auto creased = [](int i, int j) {
    const double x = i < 1 ? i - 1.0 : i > 3 ? i - 3.0 : 0.0;
    return Eigen::Vector3d(x, j, 0.5 * std::abs(x));
  };
  spline::SplineModel model = gridModel(4, 2, creased);
  const spline::SurfaceQuality q = spline::measureQuality(model, nullptr);
  const double crease = 2.0 * std::atan(0.5) * 180.0 / kPi;
  CHECK(q.smoothness.coarse.max == Approx(crease).epsilon(1e-9));
  CHECK(q.smoothness.fine.max == Approx(crease).epsilon(1e-9));
  CHECK(q.smoothness.fine.p99 == Approx(crease).epsilon(1e-9));
  CHECK(q.smoothness.p99Ratio.value_or(99.0) < 1.3);
  CHECK(q.smoothness.creases > 0);
  CHECK(q.folds.total() == 0);
  // The crease pairs are the marked faces of a picture.
  const spline::ModelSurface surface(model, "creased");
  const structure::PolygonSoup t = surface.tessellate(model.controlPoints, 4).mesh;
  const std::vector<char> marked = spline::creasedFaces(t, 30.0);
  int count = 0;
  for (const char m : marked) count += m;
  // A triangle on either side of each of the 8 crease segments (4 per face side, 2 faces).
  CHECK(count == 16);
  const std::vector<char> none = spline::creasedFaces(t, crease + 1.0);
  CHECK(std::count(none.begin(), none.end(), 1) == 0);
}

TEST_CASE("surface_quality: folds are judged against the scan's triangles, not its vertex normals",
          "[spline]") {
  // The scan: the flat grid's rectangle, with a large flap folded back under each side (a thin
  // sheet's rim). The flaps outweigh the rectangle in every corner's area-weighted normal, so
  // normals interpolated from the vertices point down all over the rectangle; its triangles
  // point up, as the flat surface does.
  spline::SplineModel model = gridModel(6, 5, flat);
  structure::PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {6, 0, 0}, {6, 5, 0}, {0, 5, 0}};
  soup.faces = {{0, 1, 2}, {0, 2, 3}};
  const std::array<std::array<double, 3>, 4> under = {
      {{3.0, 60.0, -1.0}, {-54.0, 2.5, -1.0}, {3.0, -55.0, -1.0}, {60.0, 2.5, -1.0}}};
  for (std::int64_t k = 0; k < 4; ++k) {
    soup.positions.push_back(under[std::size_t(k)]);
    soup.faces.push_back({(k + 1) % 4, k, 4 + k});
  }
  const structure::TriMesh scan = structure::toTriMesh(soup);
  model.surfaceVertices = structure::pointMatrix(soup.positions);
  model.surfaceFaces = structure::triangleIndices(soup);
  model.surfaceVertexTMeshPoints.assign(soup.positions.size(), {0, {0.0, 0.0}});
  const spline::SurfaceQuality q = spline::measureQuality(model, &scan);
  CHECK(q.folds.triangles > 0);
  CHECK(q.folds.againstScan == 0);
  CHECK(q.distances.surfaceToScan.max < 1e-12);
}

TEST_CASE("surface_quality: a flipped scan triangle is judged by its neighbours' normals",
          "[spline]") {
  // The scan: the grid's rectangle just below the flat surface, and a sliver hinged on its front
  // edge and folded back over it, facing down (scanners leave such slivers at rims: a quarter of
  // the data set has scan triangles folded against a neighbour). Above the sliver, the surface
  // is closer to it than to the rectangle.
  spline::SplineModel model = gridModel(6, 5, flat);
  structure::PolygonSoup soup;
  soup.positions = {{0, 0, -0.01}, {6, 0, -0.01}, {6, 5, -0.01}, {0, 5, -0.01}, {3, 1.5, 0.0}};
  soup.faces = {{0, 1, 2}, {0, 2, 3}, {1, 0, 4}};
  const structure::TriMesh scan = structure::toTriMesh(soup);
  model.surfaceVertices = structure::pointMatrix(soup.positions);
  model.surfaceFaces = structure::triangleIndices(soup);
  model.surfaceVertexTMeshPoints.assign(soup.positions.size(), {0, {0.0, 0.0}});
  spline::QualityOptions options;
  options.details = true;
  const spline::ModelSurface surface(model, "flat");
  const spline::SurfaceQuality q =
      spline::measureQuality(model, surface, model.controlPoints, &scan, options);
  // Some of the surface's closest scan points are on the sliver: the rectangle is 0.01 away.
  const Eigen::VectorXd& d = q.details.surfaceDistances;
  REQUIRE((d.array() < 0.009).count() > 0);
  CHECK(q.folds.againstScan == 0);
  // A fold of the surface over the rectangle still counts, although the rectangle's triangle
  // has the sliver for a neighbour.
  const spline::TSplineSpace space(model.tmesh);
  const int row = space.anchorOfVertex()[3 * 7 + 3];
  REQUIRE(row >= 0);
  Eigen::MatrixXd pulled = model.controlPoints;
  pulled(row, 0) += 3.0;
  CHECK(spline::measureQuality(model, surface, pulled, &scan, options).folds.againstScan > 0);
}

TEST_CASE("surface_quality: a crumpled fin of the scan excuses the surface only near its folds",
          "[spline]") {
  // The scan in the (x, z) plane, drawn along y over the flat surface: a sheet below it that
  // folds back over itself (facing down), then up into a steep fin and down again to the sheet.
  // Over the part folded back the flat surface faces away from its closest scan triangles, as a
  // smooth fit does where a scanner left a crumpled fin; those within a coarse triangle's length
  // (about 0.47 here) of a fold are excused, the others are folds.
  const auto measure = [](const std::vector<std::array<double, 2>>& section) {
    spline::SplineModel model = gridModel(6, 5, flat);
    structure::PolygonSoup soup;
    for (const auto& [x, z] : section) {
      soup.positions.push_back({x, 0.0, z});
      soup.positions.push_back({x, 5.0, z});
    }
    for (std::int64_t k = 0; k + 1 < std::int64_t(section.size()); ++k) {
      soup.faces.push_back({2 * k, 2 * k + 2, 2 * k + 3});
      soup.faces.push_back({2 * k, 2 * k + 3, 2 * k + 1});
    }
    const structure::TriMesh scan = structure::toTriMesh(soup);
    model.surfaceVertices = structure::pointMatrix(soup.positions);
    model.surfaceFaces = structure::triangleIndices(soup);
    model.surfaceVertexTMeshPoints.assign(soup.positions.size(), {0, {0.0, 0.0}});
    return spline::measureQuality(model, &scan).folds;
  };
  // Folded back from x = 5 to 1: most of it is far from both folds.
  const spline::SurfaceFolds wide =
      measure({{0, -0.05}, {5, -0.05}, {1, -0.01}, {1.1, 1.0}, {5.5, -0.05}, {6, -0.05}});
  CHECK(wide.atScanFolds > 0);
  CHECK(wide.againstScan > wide.atScanFolds);
  // Folded back from x = 3.2 to 3: all of it is near one.
  const spline::SurfaceFolds narrow =
      measure({{0, -0.05}, {3.2, -0.05}, {3, -0.01}, {3.02, 0.3}, {3.4, -0.05}, {6, -0.05}});
  CHECK(narrow.atScanFolds > 0);
  CHECK(narrow.againstScan == 0);
}

TEST_CASE("surface_quality: a control point pulled through the surface folds it", "[spline]") {
  spline::SplineModel model = gridModel(6, 6, flat);
  const structure::TriMesh scan = scanOf(model, 2, unmoved);
  CHECK(spline::measureQuality(model, &scan).folds.total() == 0);
  // Vertex (3, 3) moved past its neighbours (3 along x): the surface turns over in the plane.
  const spline::TSplineSpace space(model.tmesh);
  const int row = space.anchorOfVertex()[3 * 7 + 3];
  REQUIRE(row >= 0);
  Eigen::MatrixXd pulled = model.controlPoints;
  pulled(row, 0) += 3.0;
  const spline::ModelSurface surface(model, "folded");
  spline::QualityOptions options;
  options.details = true;
  const spline::SurfaceQuality q = spline::measureQuality(model, surface, pulled, &scan, options);
  CHECK(q.folds.againstScan > 0);
  CHECK(q.folds.adjacentPairs > 0);
  CHECK(q.folds.worstAgainstScanDegrees == Approx(180.0));
  CHECK(q.folds.fraction == Approx(double(q.folds.againstScan) / q.folds.triangles));
  CHECK(int(q.details.folds.size()) == q.folds.total());
  CHECK(q.smoothness.fine.max == Approx(180.0));
  // Where the surface turns over, its area element vanishes.
  CHECK(q.regularity.minRelativeJacobian < 0.05);
  // The worst fold is where the pulled point went.
  CHECK((q.folds.worstAgainstScan.position - Eigen::Vector3d(4.5, 3.0, 0.0)).norm() < 3.0);
  // Details: one entry per scan vertex and per surface sample.
  CHECK(q.details.scanDistances.size() == Eigen::Index(scan.n_vertices()));
  CHECK(q.details.scanClosest.size() == scan.n_vertices());
  CHECK(q.details.surfaceDistances.size() == Eigen::Index(q.details.surfaceSamples.size()));
}

TEST_CASE("surface_quality: bad input is refused, naming it", "[spline]") {
  spline::SplineModel model = gridModel(4, 4, flat);
  const structure::TriMesh scan = scanOf(model, 2, unmoved);
  spline::SplineModel other = gridModel(4, 4, curved);
  const structure::TriMesh otherScan = scanOf(other, 2, unmoved);
  spline::QualityOptions options;
  options.name = "m.msp";
  options.scanName = "other.off";
  CHECK_THROWS_WITH(spline::measureQuality(model, &otherScan, options),
                    Catch::StartsWith("other.off: not the scan m.msp was fitted to"));
  structure::TriMesh nanScan = scan;
  nanScan.set_point(*nanScan.vertices_begin(), structure::TriMesh::Point(0.0, std::nan(""), 0.0));
  CHECK_THROWS_WITH(spline::measureQuality(model, &nanScan, options),
                    Catch::StartsWith("other.off: a vertex position is not finite"));
  const spline::ModelSurface surface(model, "m.msp");
  Eigen::MatrixXd broken = model.controlPoints;
  broken(0, 0) = std::nan("");
  CHECK_THROWS_WITH(spline::measureQuality(model, surface, broken, &scan, options),
                    Catch::StartsWith("m.msp: the control points"));
  options.resolution = 0;
  CHECK_THROWS_AS(spline::measureQuality(model, &scan, options), structure::InputError);
}
