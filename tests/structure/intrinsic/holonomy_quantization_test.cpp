#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>

#include "mspline/structure/atlas/affine_atlas.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/intrinsic/holonomy_quantization.h"
#include "mspline/structure/intrinsic/intrinsic_triangulation.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::DualLoop;
using structure::IntrinsicTriangulation;
using structure::TriMesh;

namespace {

// The faces around vertex v, each left by its halfedge out of v: a small dual loop.
DualLoop loopAround(const IntrinsicTriangulation& tri, int v) {
  int first = 0;
  while (tri.tail(first) != v) ++first;
  DualLoop loop;
  int h = first;
  do {
    loop.halfedges.push_back(h);
    h = tri.next(tri.twin(h));
  } while (h != first);
  return loop;
}

structure::TransitionKind flatAtlasKind(const TriMesh& mesh, const Eigen::VectorXd& lengths) {
  const auto layout = structure::layoutFlatMetric(mesh, lengths);
  REQUIRE(layout.flippedTriangles == 0);
  const auto atlas = structure::buildAffineAtlas(mesh, lengths, layout);
  CHECK(atlas.maxTransitionResidual <= 1e-10);
  CHECK(atlas.maxCocycleResidual <= 1e-10);
  return atlas.kind;
}

bool isClosedDualLoop(const IntrinsicTriangulation& tri, const DualLoop& loop) {
  const auto& hs = loop.halfedges;
  for (std::size_t i = 0; i < hs.size(); ++i)
    if (tri.twin(hs[i]) / 3 != hs[(i + 1) % hs.size()] / 3) return false;
  return !hs.empty();
}

}  // namespace

TEST_CASE("holonomy_quantization: tree-cotree gives 2g closed dual loops", "[structure]") {
  CHECK(structure::homologyDualLoops(IntrinsicTriangulation(test::icosphere(2))).empty());
  const IntrinsicTriangulation torus(test::torus(20, 8));
  const IntrinsicTriangulation doubleTorus(test::doubleTorus(3));
  const auto torusLoops = structure::homologyDualLoops(torus);
  const auto doubleLoops = structure::homologyDualLoops(doubleTorus);
  CHECK(torusLoops.size() == 2);
  CHECK(doubleLoops.size() == 4);
  for (const auto& loop : torusLoops) CHECK(isClosedDualLoop(torus, loop));
  for (const auto& loop : doubleLoops) CHECK(isClosedDualLoop(doubleTorus, loop));
  CHECK_THROWS_AS(structure::homologyDualLoops(IntrinsicTriangulation(test::gridDisk(4))),
                  structure::TopologyError);
  // A flipped triangulation (loops and multiple edges allowed) gets its loops as well.
  IntrinsicTriangulation flipped(test::doubleTorus(3));
  for (int e = 0; e < flipped.edgeCount(); e += 3)
    if (flipped.twin(flipped.halfedge(e)) / 3 != flipped.halfedge(e) / 3) flipped.flip(e);
  const auto flippedLoops = structure::homologyDualLoops(flipped);
  CHECK(flippedLoops.size() == 4);
  for (const auto& loop : flippedLoops) CHECK(isClosedDualLoop(flipped, loop));
}

TEST_CASE("holonomy_quantization: a loop around a vertex turns by its curvature", "[structure]") {
  const TriMesh mesh = test::icosphere(2);
  const Eigen::VectorXd curvature = structure::vertexCurvatures(mesh, structure::edgeLengths(mesh));
  const IntrinsicTriangulation tri(mesh);
  for (int v : {0, 5, 40}) {
    const auto rotation = structure::loopRotations(tri, {loopAround(tri, v)});
    INFO("vertex " << v << ": rotation " << rotation[0] << ", curvature " << curvature[v]);
    CHECK(std::abs(std::remainder(rotation[0] - curvature[v], 2 * kPi)) <= 1e-12);
  }
}

TEST_CASE("holonomy_quantization: Jacobian matches finite differences", "[structure]") {
  const TriMesh mesh = test::doubleTorus(3);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  Eigen::VectorXd lengths = structure::edgeLengths(mesh);
  for (Eigen::Index e = 0; e < lengths.size(); ++e) lengths[e] *= std::exp(jitter(random));
  REQUIRE(structure::degenerateFaces(mesh, lengths).empty());

  const IntrinsicTriangulation tri(mesh, lengths);
  structure::HolonomyProblem problem;
  problem.loops = structure::homologyDualLoops(tri);
  problem.targetCurvature = Eigen::VectorXd::Zero(Eigen::Index(mesh.n_vertices()));
  problem.targetRotation = Eigen::VectorXd::Zero(Eigen::Index(problem.loops.size()));
  problem.droppedVertex = 7;
  const Eigen::MatrixXd jacobian = structure::holonomyJacobian(tri, problem);
  REQUIRE(jacobian.rows() == Eigen::Index(mesh.n_vertices() - 1 + problem.loops.size()));
  const double h = 1e-6;
  double worst = 0.0;
  for (Eigen::Index e = 0; e < lengths.size(); e += 7) {
    IntrinsicTriangulation plus = tri, minus = tri;
    Eigen::VectorXd logPlus = tri.logLengths0(), logMinus = tri.logLengths0();
    logPlus[e] += h;
    logMinus[e] -= h;
    plus.setLogLengths0(logPlus);
    minus.setLogLengths0(logMinus);
    const Eigen::VectorXd column = (structure::holonomyResiduals(plus, problem) -
                                    structure::holonomyResiduals(minus, problem)) /
                                   (2 * h);
    worst = std::max(worst, (column - jacobian.col(e)).cwiseAbs().maxCoeff());
  }
  CHECK(worst <= 1e-7);
}

TEST_CASE("holonomy_quantization: a double torus with quantized cones becomes seamless",
          "[structure]") {
  const TriMesh mesh = test::doubleTorus(4);
  structure::ConePlacementOptions placement;
  placement.quantize = true;
  const auto cones = structure::placeCones(mesh, placement).cones;
  structure::RicciNewtonOptions options;
  options.tolerance = 1e-13;
  const auto flow =
      structure::solveVertexScaling(mesh, structure::flatTarget(mesh, cones), options);
  REQUIRE(flow.converged);

  const IntrinsicTriangulation tri(mesh, flow.edgeLengths);
  const auto result = structure::quantizeHolonomy(tri, cones);
  WARN("doubleTorus(4), " << cones.size() << " cones: " << result.iterations
                          << " Newton steps, residual " << result.maxResidual
                          << ", log length change " << result.maxLogLengthChange << ", rotations "
                          << result.initialRotation.transpose() << " -> "
                          << result.targetRotation.transpose());
  REQUIRE(result.converged);
  REQUIRE(result.loops.size() == 4);
  // Its triangles could take the steps: the metric lives on the mesh's own triangles.
  REQUIRE(result.flips == 0);
  // The conformal metric's handle rotations are not all quarter turns: there was work to do.
  const Eigen::VectorXd off = result.initialRotation - result.targetRotation;
  CHECK(off.cwiseAbs().maxCoeff() > 1e-3);
  CHECK(flatAtlasKind(mesh, flow.edgeLengths) == structure::TransitionKind::Rigid);

  // Same cones, flat elsewhere, every handle a quarter turn, no degenerate triangle.
  const Eigen::VectorXd& lengths = result.edgeLengths;
  CHECK(structure::degenerateFaces(mesh, lengths).empty());
  const Eigen::VectorXd curvature = structure::vertexCurvatures(mesh, lengths);
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(curvature.size());
  for (const auto& cone : cones) expected[cone.vertex] = cone.curvature;
  CHECK((curvature - expected).cwiseAbs().maxCoeff() <= 1e-11);
  const Eigen::VectorXd rotation = structure::loopRotations(result.triangulation, result.loops);
  for (Eigen::Index k = 0; k < rotation.size(); ++k) {
    const double quarters = rotation[k] / (kPi / 2);
    CHECK(std::abs(quarters - std::round(quarters)) <= 1e-11);
  }
  // The atlas of the new metric: every transition a quarter turn plus a translation.
  CHECK(flatAtlasKind(mesh, lengths) == structure::TransitionKind::Rotation90);
}

TEST_CASE("holonomy_quantization: without flips, blocked steps end the iteration", "[structure]") {
  // knot.off with its quantized cones: the steps that would make its two handle loops quarter
  // turns degenerate the input's triangles at once. Crawling on does not get there either.
  const TriMesh mesh = test::realMesh("knot.off");
  structure::ConePlacementOptions placement;
  placement.quantize = true;
  const auto cones = structure::placeCones(mesh, placement).cones;
  const auto flow = structure::solveVertexScaling(mesh, structure::flatTarget(mesh, cones));
  REQUIRE(flow.converged);
  const IntrinsicTriangulation tri(mesh, flow.edgeLengths);
  structure::HolonomyQuantizationOptions options;
  options.flips = false;
  const auto stopped = structure::quantizeHolonomy(tri, cones, options);
  options.maxBlockedSteps = 0;
  const auto crawled = structure::quantizeHolonomy(tri, cones, options);
  INFO(cones.size() << " cones; stopped after " << stopped.iterations << " steps at "
                    << stopped.maxResidual << " (" << stopped.message << "), crawled "
                    << crawled.iterations << " steps to " << crawled.maxResidual << " ("
                    << crawled.message << ")");
  CHECK(!stopped.converged);
  CHECK(stopped.iterations < options.maxIterations);
  CHECK(stopped.message.find("block the way") != std::string::npos);
  CHECK(stopped.flips == 0);
  CHECK(!crawled.converged);
  CHECK(crawled.iterations == options.maxIterations);
  CHECK(crawled.maxResidual > 1e-3);
}
