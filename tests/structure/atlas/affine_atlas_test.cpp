#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "mspline/structure/atlas/affine_atlas.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/intrinsic/holonomy_quantization.h"
#include "mspline/structure/intrinsic/intrinsic_triangulation.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/topology/homotopy_basis.h"
#include "support/flat_metric.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::AffineAtlas;
using structure::RigidMotion;
using structure::TriMesh;

namespace {

// A flat metric as flatten computes it (the input triangulation, or the overlay after flips), laid
// out.
struct Flat {
  TriMesh surface;
  Eigen::VectorXd lengths;
  structure::FlatLayout layout;
};

Flat flatten(const TriMesh& mesh, const std::vector<structure::Cone>& cones) {
  test::FlatMetric metric = test::flatMetric(mesh, cones);
  Flat flat{std::move(metric.surface), std::move(metric.lengths), {}};
  flat.layout = structure::layoutFlatMetric(flat.surface, flat.lengths);
  REQUIRE(flat.layout.flippedTriangles == 0);
  return flat;
}

// The vertices around v in turning order (its link), for a vertex inside the surface.
std::vector<int> link(const TriMesh& mesh, int v) {
  std::vector<int> ring;
  for (const auto w : mesh.vv_range(TriMesh::VertexHandle(v))) ring.push_back(w.idx());
  return ring;
}

void checkAtlas(const std::string& name, const Flat& flat, const AffineAtlas& atlas) {
  WARN(name << ": " << atlas.charts.size() << " charts, " << atlas.transitions.size()
            << " transitions, kind " << structure::transitionKindName(atlas.kind)
            << ", transition residual " << atlas.maxTransitionResidual << ", cocycle residual "
            << atlas.maxCocycleResidual << ", " << atlas.cones.size() << " cones");
  CHECK(atlas.maxTransitionResidual <= 1e-10);
  CHECK(atlas.maxCocycleResidual <= 1e-10);
  CHECK(atlas.uncoveredFaces == 0);
  CHECK(atlas.charts.size() + atlas.cones.size() == flat.surface.n_vertices());
  // The charts carry the metric: its lengths come back from them.
  const Eigen::VectorXd lengths = structure::atlasEdgeLengths(flat.surface, atlas);
  CHECK(((lengths - flat.lengths).array() / flat.lengths.array()).abs().maxCoeff() <= 1e-9);

  // Random surface points: each lies in at least one chart, and point location in every chart
  // containing it finds it again.
  std::mt19937 random(5);
  std::uniform_int_distribution<int> face(0, int(flat.surface.n_faces()) - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const int f = face(random);
    Eigen::Vector3d b(unit(random), unit(random), unit(random));
    b /= b.sum();
    const auto points = structure::chartsContaining(flat.surface, atlas, f, b);
    REQUIRE(!points.empty());
    for (const auto& point : points) {
      const auto found = structure::locateInChart(flat.surface, atlas, point.chart, point.position);
      REQUIRE(found.face == f);
      worst = std::max(worst, (found.barycentric - b).cwiseAbs().maxCoeff());
    }
    // One point, several charts: the transitions agree on it.
    for (std::size_t k = 1; k < points.size(); ++k) {
      const auto& from = atlas.charts[std::size_t(points[0].chart)];
      const auto& to = atlas.charts[std::size_t(points[k].chart)];
      const RigidMotion t = atlas.transition(from.vertex, to.vertex);
      CHECK((t(points[0].position) - points[k].position).norm() <= 1e-10 * atlas.diameter);
    }
  }
  CHECK(worst <= 1e-9);
}

}  // namespace

TEST_CASE("affine_atlas: rigid motions compose and invert", "[structure]") {
  const RigidMotion a{0.7, {1.0, -2.0}}, b{-2.1, {0.5, 3.0}};
  const Eigen::Vector2d x(0.3, -1.7);
  CHECK((b.after(a)(x) - b(a(x))).norm() <= 1e-14);
  CHECK((a.inverse()(a(x)) - x).norm() <= 1e-14);
}

TEST_CASE("affine_atlas: knot1.off without cones is an affine (translation) structure",
          "[structure]") {
  const TriMesh mesh = test::realMesh("knot1.off");
  const Flat flat = flatten(mesh, {});
  const AffineAtlas atlas = structure::buildAffineAtlas(flat.surface, flat.lengths, flat.layout);
  checkAtlas("knot1.off", flat, atlas);
  CHECK(atlas.kind == structure::TransitionKind::Translation);
  CHECK(atlas.cones.empty());

  // Around a vertex: the identity. Along the homotopy loops: deck translations, integer
  // combinations m p0 + n p1 of the periods that are not zero.
  const RigidMotion around = structure::holonomy(atlas, link(mesh, 17));
  CHECK(std::abs(around.angle) <= 1e-10);
  CHECK(around.translation.norm() <= 1e-10 * atlas.diameter);
  REQUIRE(flat.layout.hasPeriods);
  Eigen::Matrix2d periods;
  periods << flat.layout.periods[0], flat.layout.periods[1];
  const auto basis = structure::computeHomotopyBasis(mesh);
  REQUIRE(basis.loops.size() == 2);
  for (auto loop : basis.loops) {
    if (loop.front() == loop.back()) loop.pop_back();
    const RigidMotion deck = structure::holonomy(atlas, loop);
    const Eigen::Vector2d mn = periods.inverse() * deck.translation;
    const Eigen::Vector2d rounded = mn.array().round();
    INFO("holonomy translation (" << deck.translation.transpose() << ") = " << mn.transpose()
                                  << " periods");
    CHECK(std::abs(deck.angle) <= 1e-10);
    CHECK((periods * rounded - deck.translation).norm() <= 1e-9 * atlas.diameter);
    CHECK(rounded.cwiseAbs().sum() >= 1.0);
  }
}

TEST_CASE("affine_atlas: quantized cones turn by quarter turns", "[structure]") {
  // On a sphere every loop is a product of loops around cones, so all transitions are quarter
  // turns. On eight.off the handles' rotations are what the conformal metric makes them until
  // quantizeHolonomy moves them to quarter turns too.
  for (const std::string name : {"bunny00.off", "eight.off"}) {
    const TriMesh mesh = test::realMesh(name);
    structure::ConePlacementOptions placement;
    placement.quantize = true;
    const auto cones = structure::placeCones(mesh, placement).cones;
    Flat flat = flatten(mesh, cones);
    if (name == "eight.off") {
      CHECK(structure::buildAffineAtlas(flat.surface, flat.lengths, flat.layout).kind ==
            structure::TransitionKind::Rigid);
      const auto seamless = structure::quantizeHolonomy(
          structure::IntrinsicTriangulation(flat.surface, flat.lengths), cones);
      REQUIRE(seamless.converged);
      flat.lengths = seamless.edgeLengths;
      flat.layout = structure::layoutFlatMetric(flat.surface, flat.lengths);
      REQUIRE(flat.layout.flippedTriangles == 0);
    }
    const AffineAtlas atlas = structure::buildAffineAtlas(flat.surface, flat.lengths, flat.layout);
    checkAtlas(name + " quantized", flat, atlas);
    CHECK(atlas.kind == structure::TransitionKind::Rotation90);
    CHECK(atlas.cones.size() == cones.size());

    // Around each cone, counter-clockwise, the holonomy rotates by the cone's curvature.
    int checked = 0;
    for (const auto& cone : atlas.cones) {
      auto ring = link(flat.surface, cone.vertex);
      std::reverse(ring.begin(), ring.end());
      bool charted = true;
      for (int w : ring) charted &= atlas.chartOfVertex[std::size_t(w)] >= 0;
      if (!charted) continue;
      const RigidMotion turn = structure::holonomy(atlas, ring);
      CHECK(std::abs(std::remainder(turn.angle - cone.curvature, 2 * kPi)) <= 1e-9);
      ++checked;
    }
    CHECK(checked > 0);
  }
}
