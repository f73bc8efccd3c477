#include <catch2/catch.hpp>

#include <cmath>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/intrinsic/ricci_flips.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::BoundaryCondition;
using structure::RicciStatus;
using structure::TriMesh;

namespace {

// Solves with flips, reports the figures, and checks the result independently: curvatures from
// the returned intrinsic edge lengths and faces, Gauss-Bonnet, valid triangles, Delaunay.
structure::RicciFlipsResult solveWithFlipsAndCheck(const std::string& name, const TriMesh& mesh,
                                                   const structure::CurvatureTarget& target) {
  structure::RicciNewtonOptions options;
  options.tolerance = 1e-10 / (2 * kPi);
  const auto out = structure::solveVertexScalingWithFlips(mesh, target, options);
  const auto& result = out.ricci;
  WARN(name << ": " << result.message << "; " << result.iterations << " iterations, " << out.flips
            << " flips (" << out.trialFlips << " in all trials), " << out.inputEdgesFlipped
            << " of " << mesh.n_edges() << " input edges flipped, error "
            << result.maxCurvatureError << ", " << result.seconds << " s");
  INFO(name << ": " << result.message);
  REQUIRE(result.converged);
  CHECK(result.maxCurvatureError <= 1e-10);
  CHECK(result.log.size() == static_cast<std::size_t>(result.iterations) + 1);
  for (std::size_t i = 1; i < result.log.size(); ++i)
    CHECK(result.log[i].energy < result.log[i - 1].energy + 1e-9);
  CHECK(result.degenerateFaces.empty());

  const auto& tri = out.triangulation;
  REQUIRE(out.faces.size() == mesh.n_faces());
  REQUIRE(result.edgeLengths.size() == static_cast<Eigen::Index>(mesh.n_edges()));
  Eigen::VectorXd angleSum = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  int degenerate = 0;
  for (int f = 0; f < tri.faceCount(); ++f) {
    // Side k is the edge from corner k to corner k + 1 of out.faces[f].
    std::array<double, 3> side;
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k;
      const int a = out.faces[f][k], b = out.faces[f][(k + 1) % 3];
      REQUIRE(tri.tail(h) == a);
      REQUIRE(tri.tip(h) == b);
      side[k] = result.edgeLengths[tri.edge(h)];
    }
    degenerate += !structure::satisfiesTriangleInequality(side[0], side[1], side[2]);
    const auto angle = structure::triangleAngles(side[0], side[1], side[2]);
    // The angle opposite side k sits at corner k + 2.
    for (int k = 0; k < 3; ++k) angleSum[out.faces[f][(k + 2) % 3]] += angle[k];
  }
  CHECK(degenerate == 0);
  double worst = 0.0, total = 0.0;
  for (const auto v : mesh.vertices()) {
    const double k = (mesh.is_boundary(v) ? kPi : 2 * kPi) - angleSum[v.idx()];
    total += k;
    if (!target.fixed[v.idx()]) worst = std::max(worst, std::abs(k - target.curvature[v.idx()]));
  }
  CHECK(worst <= 1e-10);
  CHECK(std::abs(total - 2 * kPi * structure::analyzeTopology(mesh).euler) <= 1e-8);
  // The final triangulation is Delaunay at the solution.
  Eigen::VectorXd u = result.u;
  double cosineSum = 0.0;
  for (int e = 0; e < tri.edgeCount(); ++e)
    cosineSum = std::min(cosineSum, tri.delaunayCosineSum(e, u));
  CHECK(cosineSum >= -1e-12);
  return out;
}

}  // namespace

TEST_CASE("ricci_flips: without flips needed it matches the plain solver", "[structure]") {
  // The two energies agree wherever the input triangulation is Delaunay, so when it is Delaunay
  // at u = 0 and at the plain solution, both solvers must find the same u.
  const TriMesh mesh = test::torus(32, 12);
  const auto target = structure::flatTarget(mesh, {});
  const auto plain = structure::solveVertexScaling(mesh, target);
  REQUIRE(plain.converged);
  const structure::IntrinsicTriangulation input(mesh);
  double cosineSum = 0.0;
  for (int e = 0; e < input.edgeCount(); ++e) {
    cosineSum = std::min(cosineSum, input.delaunayCosineSum(e, plain.u));
    cosineSum = std::min(cosineSum, input.delaunayCosineSum(e, 0 * plain.u));
  }
  REQUIRE(cosineSum >= -1e-13);  // rectangles of the grid are Delaunay ties
  const auto flips = solveWithFlipsAndCheck("torus(32, 12), no cones", mesh, target);
  CHECK(flips.flips == 0);
  CHECK((flips.ricci.u - plain.u).cwiseAbs().maxCoeff() <= 1e-9);

  // knot1.off is not Delaunay at u = 0: a few flips, and a slightly different conformal class.
  const TriMesh knot = test::realMesh("knot1.off");
  const auto knotTarget = structure::flatTarget(knot, {});
  const auto knotPlain = structure::solveVertexScaling(knot, knotTarget);
  const auto knotFlips = solveWithFlipsAndCheck("knot1.off, no cones", knot, knotTarget);
  WARN("knot1.off: max |u_flips - u_plain| = "
       << (knotFlips.ricci.u - knotPlain.u).cwiseAbs().maxCoeff());
  CHECK(knotFlips.flips > 0);
}

TEST_CASE("ricci_flips: eight.off with automatic cones and with a single cone", "[structure]") {
  const TriMesh mesh = test::realMesh("eight.off");
  SECTION("automatic cones") {
    const auto placement = structure::placeCones(mesh);
    const auto out = solveWithFlipsAndCheck(
        "eight.off, " + std::to_string(placement.cones.size()) + " automatic cones", mesh,
        structure::flatTarget(mesh, placement.cones));
    CHECK(out.ricci.iterations <= 50);
  }
  SECTION("single cone") {
    structure::ConePlacementOptions options;
    options.singleCone = true;
    const auto placement = structure::placeCones(mesh, options);
    REQUIRE(placement.cones.size() == 1);
    const auto target = structure::flatTarget(mesh, placement.cones);
    // The plain solver cannot do it on the input triangulation.
    CHECK_FALSE(structure::solveVertexScaling(mesh, target).converged);
    const auto out = solveWithFlipsAndCheck("eight.off, single cone", mesh, target);
    CHECK(out.flips > 0);
    CHECK(out.inputEdgesFlipped > 0);
  }
}

TEST_CASE("ricci_flips: mannequin-devil.off with a fixed boundary", "[structure]") {
  const TriMesh mesh = test::realMesh("mannequin-devil.off");
  const auto target = structure::flatTarget(mesh, {}, BoundaryCondition::FixedScale);
  const auto out = solveWithFlipsAndCheck("mannequin-devil.off, fixed boundary", mesh, target);
  CHECK(out.flips > 0);
  // Boundary edges are never flipped and keep their lengths (u = 0 there).
  const auto& tri = out.triangulation;
  const Eigen::VectorXd l0 = structure::edgeLengths(mesh);
  double boundaryChange = 0.0;
  for (const auto e : mesh.edges()) {
    if (!mesh.is_boundary(e)) continue;
    CHECK(tri.isInputEdge(e.idx()));
    boundaryChange = std::max(boundaryChange,
                              std::abs(out.ricci.edgeLengths[e.idx()] - l0[e.idx()]) / l0[e.idx()]);
  }
  CHECK(boundaryChange <= 1e-14);
}
