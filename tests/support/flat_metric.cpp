#include "support/flat_metric.h"

#include <catch2/catch.hpp>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/flatten/flatten_surface.h"
#include "mspline/structure/intrinsic/intrinsic_flattening.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "support/test_data.h"
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

FlatMetric clusteredConesCow() {
  // (vertex, quarter turns of curvature)
  static const int cones[][2] = {
      {2334, 2},  {2735, 2},  {922, 2},   {1294, 2},  {956, -3}, {2276, 2}, {750, 2},  {2105, 2},
      {2087, -2}, {1106, -2}, {1955, -2}, {1395, 2},  {2296, 2}, {720, -2}, {2836, 2}, {2761, -2},
      {601, -2},  {1006, 2},  {2447, 2},  {2147, 2},  {882, 2},  {2236, 2}, {777, 2},  {1320, -2},
      {1155, 1},  {2842, -2}, {2446, 2},  {1948, -2}, {1005, 2}, {594, -2}, {2845, 1}, {615, -1},
      {2547, -2}, {2074, -1}, {2596, 1},  {1401, -2}, {1404, 1}, {733, -2}, {1969, -1}};
  structure::FlattenOptions options;
  options.cones.emplace();
  for (const auto& [vertex, quarters] : cones)
    options.cones->push_back({vertex, quarters * kPi / 2});
  const structure::TriMesh mesh = realMesh("cow.off");
  const structure::Flattening flattening = structure::flattenSurface(mesh, options);
  REQUIRE(flattening.converged);
  return {flattening.surface(), flattening.flatLengths};
}

}  // namespace mspline::test
