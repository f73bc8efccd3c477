#include <catch2/catch.hpp>

#include <algorithm>

#include "mspline/spline/model/build_spline.h"
#include "mspline/spline/model/quad_layout_flattening.h"
#include "mspline/spline/quality/surface_quality.h"
#include "support/test_data.h"

using namespace mspline;

namespace {

// The flattening `spline --kind tspline` makes of a real mesh.
structure::Flattening tsplineFlattening(const structure::TriMesh& mesh) {
  structure::FlattenOptions flattenOptions;
  flattenOptions.quantize = true;
  flattenOptions.maxConeQuarterTurns = 2;
  structure::Flattening flattening = structure::flattenSurface(mesh, flattenOptions);
  REQUIRE(flattening.converged);
  return flattening;
}

// The T-spline `spline --kind tspline` makes of a real mesh, fitted with `options`.
spline::SplineModel tsplineOf(const structure::TriMesh& mesh,
                              const spline::SurfaceFitOptions& options,
                              spline::ControlPointFit& fit) {
  const structure::Flattening flattening = tsplineFlattening(mesh);
  spline::BuildSplineOptions buildOptions;
  buildOptions.kind = spline::SpaceKind::TSpline;
  buildOptions.control = 6000;
  spline::SplineSpaceBuild build = spline::buildSpline(flattening, buildOptions);
  fit = spline::fitControlPoints(build, options);
  return build.model;
}

// beam.off's T-spline space with a corner of valence 3 at each of its eight corners.
spline::SplineSpaceBuild beamSpace(const structure::TriMesh& mesh) {
  spline::BuildSplineOptions build;
  build.kind = spline::SpaceKind::TSpline;
  build.control = 1000;
  const spline::QuadLayoutFlattening quad = spline::quadLayoutFlattening(mesh, 3, build);
  REQUIRE(quad.midpointSubdivisions == 0);
  const structure::Flattening flattening = structure::flattenSurface(mesh, quad.options);
  REQUIRE(flattening.converged);
  return spline::buildSpline(flattening, build);
}

// Samples (vertices included) per cell of the build's T-mesh.
std::vector<int> samplesPerCell(const spline::SplineSpaceBuild& build) {
  std::vector<int> count(build.model.tmesh.faces.size(), 0);
  for (const auto& site : build.tmeshSites) ++count[std::size_t(site.face)];
  return count;
}

}  // namespace

TEST_CASE("build_spline: the faired T-spline of cactus.off has no folds", "[spline][slow]") {
  // With about one control point per two samples, a fit without fairing folded between them
  // (426 folded triangles, the surface 3% of the diagonal away from the mesh).
  const structure::TriMesh mesh = test::realMesh("cactus.off");
  spline::ControlPointFit fit;
  const spline::SplineModel model = tsplineOf(mesh, {}, fit);
  CHECK(fit.smoothing > 0.0);
  CHECK(fit.correctionRounds == 3);
  CHECK(fit.missingAnchors == 0);
  CHECK(fit.samplesOutside == 0);
  const spline::SurfaceQuality quality = spline::measureQuality(model, &mesh);
  const spline::SurfaceDistances& d = quality.distances;
  CAPTURE(d.scanToSurface.rms, d.scanToSurface.max, d.surfaceToScan.rms, d.surfaceToScan.max);
  CHECK(quality.folds.total() == 0);
  CHECK(std::max(d.scanToSurface.rms, d.surfaceToScan.rms) <= 1e-3);
  CHECK(std::max(d.scanToSurface.max, d.surfaceToScan.max) <= 5e-3);
  // C1: the dihedral angles halve with the tessellation step.
  CHECK(quality.smoothness.p99Ratio.value_or(0.0) > 1.8);
  // The surface vertices' parameters follow the samples' parameter correction.
  for (std::size_t v = 0; v < model.surfaceVertexTMeshPoints.size(); ++v)
    CHECK(model.surfaceVertexTMeshPoints[v].face >= 0);
}

TEST_CASE("build_spline: a fixed smoothing weight and no correction are kept", "[spline]") {
  const structure::TriMesh mesh = test::realMesh("cactus.off");
  spline::SurfaceFitOptions options;
  options.smoothing = 1e-3;
  options.correctionRounds = 0;
  spline::ControlPointFit fit;
  const spline::SplineModel model = tsplineOf(mesh, options, fit);
  CHECK(fit.smoothing == 1e-3);
  CHECK(fit.correctionRounds == 0);
  CHECK(model.controlPoints.allFinite());
}

TEST_CASE("build_spline: a box's T-spline on its six faces is smooth and fold-free", "[spline]") {
  // beam.off with a corner of valence 3 at each of its eight corners: the layout is the box's
  // faces. Spline and scan agree so well that the held-out errors level off as the smoothing
  // goes down; choosing the least of them (1e-7) let parameter correction fold the surface into
  // fins along the edges (5,712 folded triangles here; 19,958 with 6,000 control points).
  const structure::TriMesh mesh = test::realMesh("beam.off");
  spline::SplineSpaceBuild space = beamSpace(mesh);
  CHECK(space.grid.rectangles == 6);
  CHECK(space.grid.frameAngle == 0.0);
  const spline::ControlPointFit fit = spline::fitControlPoints(space, {});
  CHECK(fit.smoothing >= 1e-4);
  const spline::SurfaceQuality quality = spline::measureQuality(space.model, &mesh);
  const spline::SurfaceDistances& d = quality.distances;
  CAPTURE(fit.smoothing, d.scanToSurface.max, d.surfaceToScan.max);
  CHECK(quality.folds.total() == 0);
  // The sharp edges are rounded within a cell (about 2 % of the diagonal here).
  CHECK(std::max(d.scanToSurface.max, d.surfaceToScan.max) <= 2e-2);
  CHECK(quality.smoothness.p99Ratio.value_or(0.0) > 1.8);
}

TEST_CASE("build_spline: long thin faces sample every cell", "[spline]") {
  // beam.off's long sides are two triangles each with 6 degree corners: a grid of points in
  // barycentric steps was nine times sparser along them than across, and missed whole cells.
  const structure::TriMesh mesh = test::realMesh("beam.off");
  const spline::SplineSpaceBuild space = beamSpace(mesh);
  const std::vector<int> count = samplesPerCell(space);
  const auto [fewest, most] = std::minmax_element(count.begin(), count.end());
  CAPTURE(count.size(), *fewest, *most, space.tmeshSites.size());
  // About 3 samples per cell on a lattice as fine one way as the other.
  CHECK(*fewest >= 1);
  CHECK(*most <= 8);
}

TEST_CASE("build_spline: a dense scan's cells far from its vertices in the flat metric get samples",
          "[spline]") {
  // bunny00.off has more vertices than the samples wanted, but the flat metric spreads them
  // thinly where it shrinks the surface: counted over the whole mesh, vertices were the only
  // samples and 31 of 3,105 cells had none. Counted per face, a few cells still fall between the
  // points of faces that cross them.
  const structure::TriMesh mesh = test::realMesh("bunny00.off");
  const structure::Flattening flattening = tsplineFlattening(mesh);
  spline::BuildSplineOptions buildOptions;
  buildOptions.kind = spline::SpaceKind::TSpline;
  buildOptions.control = 3000;
  const spline::SplineSpaceBuild build = spline::buildSpline(flattening, buildOptions);
  REQUIRE(double(mesh.n_vertices()) > 3.0 * build.model.tmesh.numFaces());
  const std::vector<int> count = samplesPerCell(build);
  const auto empty = std::count(count.begin(), count.end(), 0);
  CAPTURE(mesh.n_vertices(), count.size(), build.tmeshSites.size());
  CHECK(empty * 500 <= std::ptrdiff_t(count.size()));
}

TEST_CASE("build_spline: cells split around cones get samples as dense as their control points",
          "[spline]") {
  // elephant.off's vertices are fewer than the samples wanted, so points inside faces make up
  // most of them. Its cones without room for caps get two or three rings of cells split.
  const structure::Flattening flattening = tsplineFlattening(test::realMesh("elephant.off"));
  spline::BuildSplineOptions buildOptions;
  buildOptions.kind = spline::SpaceKind::TSpline;
  buildOptions.control = 3000;
  for (const bool denser : {false, true}) {
    buildOptions.denserWhereSplit = denser;
    spline::SplineSpaceBuild build = spline::buildSpline(flattening, buildOptions);
    const int cells = build.model.tmesh.numFaces();
    spline::splitCellsAroundCones(build);
    REQUIRE(build.model.tmesh.numFaces() > cells);
    // Mean samples per cell among the cells split (a quarter of a cell or less) and the others.
    double splitSamples = 0.0, splitCells = 0.0, wholeSamples = 0.0, wholeCells = 0.0;
    const std::vector<int> count = samplesPerCell(build);
    for (std::size_t f = 0; f < count.size(); ++f) {
      const auto& face = build.model.tmesh.faces[f];
      const bool split = face.width * face.height < 0.3;
      (split ? splitSamples : wholeSamples) += count[f];
      (split ? splitCells : wholeCells) += 1.0;
    }
    const double ratio = (splitSamples / splitCells) / (wholeSamples / wholeCells);
    CAPTURE(denser, splitCells, wholeCells, ratio);
    if (denser)
      CHECK((ratio > 0.6 && ratio < 1.6));
    else
      CHECK(ratio < 0.5);
  }
}
