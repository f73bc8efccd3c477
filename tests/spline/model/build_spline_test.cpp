#include <catch2/catch.hpp>

#include <algorithm>

#include "mspline/spline/model/build_spline.h"
#include "mspline/spline/quality/surface_quality.h"
#include "support/test_data.h"

using namespace mspline;

namespace {

// The T-spline `spline --kind tspline` makes of a real mesh, fitted with `options`.
spline::SplineModel tsplineOf(const structure::TriMesh& mesh,
                              const spline::SurfaceFitOptions& options,
                              spline::ControlPointFit& fit) {
  structure::FlattenOptions flattenOptions;
  flattenOptions.quantize = true;
  flattenOptions.maxConeQuarterTurns = 2;
  const structure::Flattening flattening = structure::flattenSurface(mesh, flattenOptions);
  REQUIRE(flattening.converged);
  spline::BuildSplineOptions buildOptions;
  buildOptions.kind = spline::SpaceKind::TSpline;
  buildOptions.control = 6000;
  spline::SplineSpaceBuild build = spline::buildSpline(flattening, buildOptions);
  fit = spline::fitControlPoints(build, options);
  return build.model;
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
  CHECK(quality.smoothness.p99Ratio > 1.8);
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
