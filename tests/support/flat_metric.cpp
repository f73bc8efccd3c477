#include "support/flat_metric.h"

#include <catch2/catch.hpp>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/flatten/flatten_surface.h"
#include "mspline/structure/intrinsic/intrinsic_flattening.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "support/test_meshes.h"

namespace mspline::test {

FlatMetric flatMetric(const structure::TriMesh& mesh, const std::vector<structure::Cone>& cones) {
  const auto target = structure::flatTarget(mesh, cones);
  structure::RicciNewtonOptions options;
  options.tolerance = 1e-12 / (2 * kPi);
  const auto plain = structure::solveVertexScaling(mesh, target, options);
  if (plain.converged) return {mesh, plain.edgeLengths};
  const auto flipped = structure::flattenWithFlips(mesh, target, options);
  REQUIRE(flipped.solve.ricci.converged);
  return {flipped.overlay.mesh, flipped.overlay.edgeLengths};
}

FlatMetric seamlessFlatMetric(const structure::TriMesh& mesh) {
  structure::FlattenOptions options;
  options.quantize = true;
  options.maxConeQuarterTurns = 2;
  const structure::Flattening flattening = structure::flattenSurface(mesh, options);
  REQUIRE(flattening.converged);
  return {flattening.surface(), flattening.flatLengths};
}

FlatMetric eightConeSphere() {
  std::vector<structure::Cone> cones;
  for (int v : {3, 40, 97, 151, 230, 333, 407, 560}) cones.push_back({v, kPi / 2.0});
  return flatMetric(icosphere(3), cones);
}

}  // namespace mspline::test
