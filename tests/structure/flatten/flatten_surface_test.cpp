#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/flatten/flatten_surface.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::Cone;
using structure::Flattening;
using structure::FlattenOptions;
using structure::TriMesh;

namespace {

// The curvature of the flat metric, recomputed from its edge lengths: 0 away from the cones, the
// cone's curvature at a cone.
double maxCurvatureMiss(const Flattening& flat) {
  const TriMesh& surface = flat.surface();
  Eigen::VectorXd wanted = Eigen::VectorXd::Zero(surface.n_vertices());
  for (const auto& cone : flat.cones) wanted[cone.vertex] = cone.curvature;
  const Eigen::VectorXd curvature = structure::vertexCurvatures(surface, flat.flatLengths);
  double miss = 0.0;
  for (auto v : surface.vertices())
    if (!surface.is_boundary(v))
      miss = std::max(miss, std::abs(curvature[v.idx()] - wanted[v.idx()]));
  return miss;
}

}  // namespace

TEST_CASE("flatten_surface: genus-1 knot") {
  const TriMesh mesh = test::realMesh("knot1.off");
  std::vector<std::string> messages;
  FlattenOptions options;
  options.quantize = true;
  options.name = "knot1.off";
  const Flattening flat = structure::flattenSurface(
      mesh, options, [&](const std::string& stage, double) { messages.push_back(stage); });
  INFO(flat.message);
  REQUIRE(flat.converged);
  CHECK(flat.flow.converged);
  CHECK(flat.flow.maxCurvatureError <= options.tolerance);
  // Gauss-Bonnet: a torus carries no total curvature, so the cones' curvatures sum to 0.
  double total = 0.0;
  for (const auto& cone : flat.cones) total += cone.curvature;
  CHECK(std::abs(total) < 1e-9);
  CHECK(maxCurvatureMiss(flat) < 1e-8);
  CHECK(flat.layout.flippedTriangles == 0);
  // knot1 is a flat torus without cones: its seams are translations, with nothing to quantize
  // (knot.off below has cones and quantized handle rotations).
  REQUIRE(flat.cones.empty());
  CHECK(flat.layout.hasPeriods);
  CHECK(!flat.holonomy);
  CHECK(flat.seamRotations.rotated == 0);
  CHECK(flat.seamRotations.maxQuarterTurnError < 1e-8);
  CHECK(flat.areaDistortion.min <= flat.areaDistortion.mean);
  CHECK(flat.areaDistortion.mean <= flat.areaDistortion.max);
  CHECK(&flat.surface() == &mesh);
  std::vector<std::string> stages;
  for (const auto& [name, seconds] : flat.stageSeconds) stages.push_back(name);
  CHECK(stages == std::vector<std::string>{"cones", "ricci_flow", "layout"});
  CHECK(messages.back() == "laying out");
}

TEST_CASE("flatten_surface: automatic cones are placed again when the handles cannot be quantized",
          "[structure][slow]") {
  // knot.off: the 8 cones placed first leave handle rotations whose quantization degenerates the
  // triangulation; joint.off (genus 2): the same with 2 cones.
  for (const auto& [name, loops] : {std::pair<const char*, std::size_t>{"knot.off", 2},
                                    std::pair<const char*, std::size_t>{"joint.off", 4}}) {
    INFO(name);
    const TriMesh mesh = test::realMesh(name);
    FlattenOptions options;
    options.quantize = true;
    options.maxConeQuarterTurns = 2;
    const Flattening flat = structure::flattenSurface(mesh, options);
    REQUIRE(flat.converged);
    REQUIRE(flat.holonomy);
    CHECK(flat.holonomy->loops.size() == loops);
    CHECK(flat.holonomy->converged);
    CHECK(flat.seamRotations.maxQuarterTurnError < 1e-8);
    CHECK(flat.layout.flippedTriangles == 0);
    CHECK(maxCurvatureMiss(flat) < 1e-8);
    REQUIRE(!flat.rejectedConeCounts.empty());
    CHECK(flat.rejectedConeCounts.size() <= 3);
    // The stages of every attempt are summed, not listed again.
    std::vector<std::string> stages;
    for (const auto& [stage, seconds] : flat.stageSeconds) stages.push_back(stage);
    CHECK(std::count(stages.begin(), stages.end(), "holonomy") == 1);

    // Cones asked for by number are the caller's: no other set is tried.
    options.coneCount = flat.rejectedConeCounts.front();
    const Flattening asked = structure::flattenSurface(mesh, options);
    REQUIRE(asked.holonomy);
    CHECK(!asked.holonomy->converged);
    CHECK(asked.rejectedConeCounts.empty());
  }
}

TEST_CASE("flatten_surface: genus 133, the handle rotations quantized with flips",
          "[structure][slow]") {
  // cheese.off: the flow needs intrinsic flips, and the Newton steps that make its 266 handle
  // loops quarter turns would degenerate the flip solver's triangles: the quantization flips
  // further, and the surface laid out is the common subdivision with its triangulation. Its
  // -1,056 quarter turns need at least 264 cones of angle at most 4 pi. Cone sets whose
  // common subdivision has cells of zero area, or whose layout through its slivers misses
  // quarter turns, are replaced (rejected counts).
  const TriMesh mesh = test::realMesh("cheese.off");
  FlattenOptions options;
  options.quantize = true;
  const Flattening flat = structure::flattenSurface(mesh, options);
  INFO(flat.message);
  REQUIRE(flat.converged);
  REQUIRE(flat.holonomy);
  CHECK(flat.holonomy->loops.size() == 266);
  CHECK(flat.holonomy->converged);
  CHECK(flat.holonomy->maxResidual <= 1e-11);
  CHECK(flat.holonomy->flips > 0);
  CHECK(flat.cones.size() >= 264);
  for (const Cone& cone : flat.cones) {
    const double quarters = cone.curvature / (kPi / 2);
    CHECK(std::abs(quarters - std::round(quarters)) <= 1e-12);
    CHECK(quarters >= -4.0 - 1e-12);
  }
  REQUIRE(flat.overlay);
  CHECK(flat.flips == flat.holonomy->triangulation.flipCount());
  CHECK(flat.layout.flippedTriangles == 0);
  CHECK(maxCurvatureMiss(flat) < 1e-8);
  // Every seam a whole number of quarter turns: what the quad layout needs.
  CHECK(flat.seamRotations.maxQuarterTurnError < 1e-5);
  CHECK(structure::analyzeTopology(flat.surface()).genus == 133);
}

TEST_CASE("flatten_surface: a flat torus without cones has periods") {
  const TriMesh mesh = test::torus(24, 12);
  FlattenOptions options;
  options.cones.emplace();
  const Flattening flat = structure::flattenSurface(mesh, options);
  REQUIRE(flat.converged);
  CHECK(flat.cones.empty());
  CHECK(maxCurvatureMiss(flat) < 1e-8);
  REQUIRE(flat.layout.hasPeriods);
  // Two independent periods span the lattice.
  const double cross = flat.layout.periods[0].x() * flat.layout.periods[1].y() -
                       flat.layout.periods[0].y() * flat.layout.periods[1].x();
  CHECK(std::abs(cross) > 1e-6);
  CHECK(!flat.holonomy);

  // Quantized, on a coarse torus (50 faces) where the automatic placement puts no cone: nothing to
  // quantize, where a Newton step on the handle rotations would be singular.
  const TriMesh coarse = test::realMesh("torus_quad.off");
  FlattenOptions quantized;
  quantized.quantize = true;
  quantized.maxConeQuarterTurns = 2;
  const Flattening seamless = structure::flattenSurface(coarse, quantized);
  REQUIRE(seamless.converged);
  CHECK(seamless.cones.empty());
  CHECK(!seamless.holonomy);
  CHECK(seamless.rejectedConeCounts.empty());
  CHECK(seamless.layout.hasPeriods);
}

TEST_CASE("flatten_surface: non-convergence is reported, not thrown") {
  const TriMesh mesh = test::realMesh("knot1.off");
  FlattenOptions options;
  options.maxIterations = 1;
  options.tolerance = 1e-14;
  options.name = "knot1.off";
  Flattening flat;
  REQUIRE_NOTHROW(flat = structure::flattenSurface(mesh, options));
  CHECK(!flat.converged);
  CHECK(!flat.flow.converged);
  CHECK(flat.message.rfind("knot1.off: the Ricci flow did not converge: ", 0) == 0);
  CHECK(flat.layout.cornerUV.size() == 0);
}

TEST_CASE("flatten_surface: boundary shapes") {
  SECTION("a fixed boundary becomes a circle") {
    const TriMesh mesh = test::gridDisk(8);
    FlattenOptions options;
    options.cones.emplace();
    options.boundary = structure::BoundaryShape::Fixed;
    const Flattening flat = structure::flattenSurface(mesh, options);
    REQUIRE(flat.converged);
    CHECK(maxCurvatureMiss(flat) < 1e-8);
    CHECK(flat.layout.flippedTriangles == 0);
    // Geodesic curvature pi - angle, spread by boundary length: equal edges on the square's
    // boundary give every boundary vertex the same share of 2 pi.
    const Eigen::VectorXd curvature = structure::vertexCurvatures(mesh, flat.flatLengths);
    const int boundaryVertices = 4 * 8;
    for (auto v : mesh.vertices())
      if (mesh.is_boundary(v))
        CHECK(std::abs(curvature[v.idx()] - 2 * kPi / boundaryVertices) < 1e-8);
  }
  SECTION("a rectangle needs one boundary loop") {
    const TriMesh mesh = test::cylinder(16, 4);
    FlattenOptions options;
    options.boundary = structure::BoundaryShape::Rectangle;
    options.cones.emplace();
    CHECK_THROWS_AS(structure::flattenSurface(mesh, options), structure::InputError);
  }
}

TEST_CASE("flatten_surface: degenerate input triangles go on with intrinsic flips") {
  // mannequin-devil's circular boundary makes input triangles degenerate: the flow continues on
  // an intrinsic Delaunay triangulation of the doubled surface, and the overlay is laid out.
  const TriMesh mesh = test::realMesh("mannequin-devil.off");
  FlattenOptions options;
  options.boundary = structure::BoundaryShape::Fixed;
  const Flattening flat = structure::flattenSurface(mesh, options);
  INFO(flat.message);
  REQUIRE(flat.converged);
  REQUIRE(flat.plainSolve);
  CHECK(flat.plainSolve->message.find("intrinsic Delaunay flips are needed") != std::string::npos);
  CHECK(flat.doubled);
  CHECK(flat.flips > 0);
  REQUIRE(flat.overlay);
  CHECK(&flat.surface() == &flat.overlay->mesh);
  CHECK(flat.overlay->maxLengthMismatch <= 1e-9);
  CHECK(flat.flow.maxCurvatureError <= options.tolerance);
  CHECK(flat.layout.flippedTriangles == 0);
  CHECK(flat.flatLengths.size() == Eigen::Index(flat.overlay->mesh.n_edges()));
  std::vector<std::string> stages;
  for (const auto& [name, seconds] : flat.stageSeconds) stages.push_back(name);
  CHECK(stages == std::vector<std::string>{"cones", "ricci_flow", "ricci_flow_flips", "layout"});
}

TEST_CASE("flatten_surface: the outcome of automatic cone placement is kept with the flattening",
          "[structure]") {
  const TriMesh mesh = test::icosphere(3);
  const Flattening automatic = structure::flattenSurface(mesh);
  REQUIRE(automatic.converged);
  CHECK_THAT(automatic.conePlacement,
             Catch::StartsWith(std::to_string(automatic.cones.size()) + " cones after"));
  CHECK_FALSE(automatic.reachedMaxCones);
  // Cones given: there was no placement.
  FlattenOptions given;
  given.cones = automatic.cones;
  const Flattening same = structure::flattenSurface(mesh, given);
  REQUIRE(same.converged);
  CHECK(same.conePlacement.empty());
  CHECK_FALSE(same.reachedMaxCones);
}

TEST_CASE("flatten_surface: seams that miss quarter turns by more than asked are rejected",
          "[structure]") {
  // Quantized, eight.off's seams miss quarter turns by rounding only; a tolerance below that miss
  // rejects its cone set, and another automatic set whose seams hold to it is taken.
  const TriMesh mesh = test::realMesh("eight.off");
  FlattenOptions options;
  options.quantize = true;
  const Flattening kept = structure::flattenSurface(mesh, options);
  REQUIRE(kept.converged);
  REQUIRE(kept.holonomy);
  REQUIRE(kept.holonomy->converged);
  CHECK(kept.rejectedConeCounts.empty());
  const double miss = kept.seamRotations.maxQuarterTurnError;
  INFO("seams miss quarter turns by " << miss);
  CHECK(miss <= options.seamTolerance);
  REQUIRE(miss > 0.0);
  options.seamTolerance = miss / 2.0;
  const Flattening strict = structure::flattenSurface(mesh, options);
  REQUIRE(strict.converged);
  CHECK(strict.rejectedConeCounts.size() >= 1);
  CHECK(strict.cones.size() != kept.cones.size());
  CHECK(strict.seamRotations.maxQuarterTurnError <= options.seamTolerance);
}
