#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/intrinsic/holonomy_quantization.h"
#include "mspline/structure/intrinsic/intrinsic_overlay.h"
#include "mspline/structure/intrinsic/ricci_flips.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::IntrinsicOverlay;
using structure::IntrinsicTriangulation;
using structure::TriMesh;

namespace {

double triangleArea(double a, double b, double c) {
  return 0.25 * structure::fourTimesArea(a, b, c);
}

// max over overlay edges of |flat length - 3D length| / 3D length.
double maxLengthDeviation(const IntrinsicOverlay& overlay) {
  double worst = 0.0;
  for (const auto e : overlay.mesh.edges()) {
    const double spatial = overlay.mesh.calc_edge_length(e);
    worst = std::max(worst, std::abs(overlay.edgeLengths[e.idx()] - spatial) / spatial);
  }
  return worst;
}

// Random flips of interior edges whose two faces differ; returns the flip sequence.
std::vector<int> randomFlips(const TriMesh& mesh, int count, unsigned seed) {
  IntrinsicTriangulation tri(mesh);
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> pick(0, tri.edgeCount() - 1);
  while (tri.flipCount() < count) {
    const int e = pick(random);
    const int h = tri.halfedge(e);
    if (tri.twin(h) >= 0 && h / 3 != tri.twin(h) / 3) tri.flip(e);
  }
  return tri.flippedEdges();
}

// The lengths at u of the intrinsic triangulation that `flips` make of `input`.
Eigen::VectorXd flippedLengths(const TriMesh& input, const std::vector<int>& flips,
                               const Eigen::VectorXd& u) {
  IntrinsicTriangulation tri(input);
  for (int e : flips) tri.flip(e);
  return tri.lengths(u);
}

IntrinsicOverlay overlayAt(const TriMesh& input, const std::vector<int>& flips,
                           const Eigen::VectorXd& u) {
  return structure::intrinsicOverlay(input, flips, u, flippedLengths(input, flips, u));
}

// The overlay is a refinement of the input and of the intrinsic triangulation with the metric
// `lengths`: same topology, every cell positive in 3D and in the flat metric, areas adding up on
// both sides.
void checkOverlay(const std::string& name, const TriMesh& input, const std::vector<int>& flips,
                  const Eigen::VectorXd& lengths, const IntrinsicOverlay& overlay) {
  IntrinsicTriangulation tri(input);
  for (int e : flips) tri.flip(e);
  WARN(name << ": " << flips.size() << " flips, " << overlay.mesh.n_faces() << " overlay faces ("
            << input.n_faces() << " input), " << overlay.crossingInputEdge.size()
            << " crossings, length mismatch " << overlay.maxLengthMismatch);
  CHECK(overlay.mesh.n_vertices() == input.n_vertices() + overlay.crossingInputEdge.size());
  CHECK(structure::analyzeTopology(overlay.mesh).euler == structure::analyzeTopology(input).euler);
  CHECK(structure::analyzeTopology(overlay.mesh).boundaryLoops ==
        structure::analyzeTopology(input).boundaryLoops);
  CHECK(overlay.maxLengthMismatch <= 1e-9);
  REQUIRE(overlay.inputFace.size() == overlay.mesh.n_faces());
  REQUIRE(overlay.intrinsicFace.size() == overlay.mesh.n_faces());

  std::vector<double> spatialArea(input.n_faces(), 0.0);
  std::vector<double> flatArea(std::size_t(tri.faceCount()), 0.0);
  int nonPositive = 0;
  for (const auto f : overlay.mesh.faces()) {
    double l[3];
    int k = 0;
    for (const auto e : overlay.mesh.fe_range(f)) l[k++] = overlay.edgeLengths[e.idx()];
    const double flat = triangleArea(l[0], l[1], l[2]);
    const double spatial = overlay.mesh.calc_face_area(f);
    nonPositive += !(flat > 0.0) || !(spatial > 0.0);
    spatialArea[std::size_t(overlay.inputFace[f.idx()])] += spatial;
    flatArea[std::size_t(overlay.intrinsicFace[f.idx()])] += flat;
  }
  CHECK(nonPositive == 0);
  double spatialError = 0.0, flatError = 0.0;
  for (const auto f : input.faces())
    spatialError = std::max(spatialError, std::abs(spatialArea[f.idx()] - input.calc_face_area(f)) /
                                              input.calc_face_area(f));
  for (int f = 0; f < tri.faceCount(); ++f) {
    const double area = triangleArea(lengths[tri.edge(3 * f)], lengths[tri.edge(3 * f + 1)],
                                     lengths[tri.edge(3 * f + 2)]);
    flatError = std::max(flatError, std::abs(flatArea[std::size_t(f)] - area) / area);
  }
  INFO(name << ": worst relative area error per input face " << spatialError
            << ", per intrinsic face " << flatError);
  CHECK(spatialError <= 1e-9);
  CHECK(flatError <= 1e-9);
}

// eight.off's flat metric by the flip solver, to 1e-10, with one cone or with quantized cones.
struct EightWithFlips {
  TriMesh mesh = test::realMesh("eight.off");
  std::vector<structure::Cone> cones;
  structure::RicciFlipsResult solved;
};

EightWithFlips eightWithFlips(bool singleCone) {
  EightWithFlips out;
  structure::ConePlacementOptions placement;
  placement.singleCone = singleCone;
  placement.quantize = !singleCone;
  out.cones = structure::placeCones(out.mesh, placement).cones;
  const auto target =
      structure::flatTarget(out.mesh, out.cones, structure::BoundaryCondition::FixedScale);
  structure::RicciNewtonOptions options;
  options.tolerance = 1e-10 / (2 * kPi);
  out.solved = structure::solveVertexScalingWithFlips(out.mesh, target, options);
  REQUIRE(out.solved.ricci.converged);
  return out;
}

}  // namespace

TEST_CASE("intrinsic_overlay: without flips it is the input", "[structure]") {
  const TriMesh mesh = test::icosphere(2);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(Eigen::Index(mesh.n_vertices()));
  const IntrinsicOverlay overlay = overlayAt(mesh, {}, zero);
  CHECK(overlay.mesh.n_vertices() == mesh.n_vertices());
  CHECK(overlay.mesh.n_faces() == mesh.n_faces());
  CHECK(overlay.crossingInputEdge.empty());
  CHECK(overlay.inputFace == overlay.intrinsicFace);
  CHECK(maxLengthDeviation(overlay) <= 1e-12);
  checkOverlay("icosphere(2), no flips", mesh, {}, flippedLengths(mesh, {}, zero), overlay);
}

TEST_CASE("intrinsic_overlay: flips of a cyclic polygon keep its geometry", "[structure]") {
  // In a triangulated polygon inscribed in a circle every quadrilateral is cyclic, so Ptolemy
  // flips are Euclidean flips and the correspondence is the identity: each overlay edge has its
  // 3D length in the flat metric.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(0.1, 0.9);
  std::vector<OpenMesh::Vec3d> corners;
  const int n = 14;
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * kPi * (i + jitter(random)) / n;
    corners.emplace_back(std::cos(angle), std::sin(angle), 0.0);
  }
  const TriMesh mesh = test::polygonFan(corners);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(Eigen::Index(mesh.n_vertices()));
  for (unsigned seed : {1u, 2u, 3u}) {
    const std::vector<int> flips = randomFlips(mesh, 60, seed);
    const IntrinsicOverlay overlay = overlayAt(mesh, flips, zero);
    CHECK(overlay.crossingInputEdge.size() > 0);
    CHECK(maxLengthDeviation(overlay) <= 1e-10);
    checkOverlay("cyclic 14-gon, seed " + std::to_string(seed), mesh, flips,
                 flippedLengths(mesh, flips, zero), overlay);
  }
}

TEST_CASE("intrinsic_overlay: flip sequences that return leave no crossings", "[structure]") {
  // Five flips around a pentagon come back to its first triangulation (the pentagon relation of
  // Ptolemy flips); the replayed maps must compose to the identity, also for a pentagon that is
  // not cyclic.
  const TriMesh pentagon = test::polygonFan(
      {{0.0, 0.0, 0.0}, {1.0, -0.2, 0.1}, {1.6, 0.7, -0.2}, {0.9, 1.5, 0.3}, {-0.3, 1.1, 0.0}});
  IntrinsicTriangulation tri(pentagon);
  std::vector<int> diagonals;
  for (int e = 0; e < tri.edgeCount(); ++e)
    if (!tri.isBoundaryEdge(e)) diagonals.push_back(e);
  REQUIRE(diagonals.size() == 2);
  for (int step = 0; step < 5; ++step) tri.flip(diagonals[std::size_t(step % 2)]);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(5);
  const IntrinsicOverlay cycled = overlayAt(pentagon, tri.flippedEdges(), zero);
  CHECK(cycled.crossingInputEdge.empty());
  CHECK(cycled.mesh.n_faces() == 3);
  CHECK(maxLengthDeviation(cycled) <= 1e-12);

  // Random flips on a closed surface, then the same flips in reverse order.
  const TriMesh torus = test::torus(12, 8);
  std::vector<int> flips = randomFlips(torus, 300, 11);
  const Eigen::VectorXd u = Eigen::VectorXd::Random(Eigen::Index(torus.n_vertices())) * 0.3;
  const IntrinsicOverlay there = overlayAt(torus, flips, u);
  CHECK(there.crossingInputEdge.size() > 0);
  flips.insert(flips.end(), flips.rbegin(), flips.rend());
  const IntrinsicOverlay back = overlayAt(torus, flips, u);
  CHECK(back.crossingInputEdge.empty());
  CHECK(back.mesh.n_faces() == torus.n_faces());
}

TEST_CASE("intrinsic_overlay: the flip solver's metric on eight.off, laid out", "[structure]") {
  const EightWithFlips eight = eightWithFlips(true);
  const TriMesh& mesh = eight.mesh;
  const auto& cones = eight.cones;
  const auto& solved = eight.solved;
  const auto& flips = solved.triangulation.flippedEdges();
  REQUIRE(!flips.empty());
  const Eigen::VectorXd lengths = solved.triangulation.lengths(solved.ricci.u);
  const IntrinsicOverlay overlay =
      structure::intrinsicOverlay(mesh, flips, solved.ricci.u, lengths);
  checkOverlay("eight.off, single cone", mesh, flips, lengths, overlay);

  const structure::FlatLayout layout =
      structure::layoutFlatMetric(overlay.mesh, overlay.edgeLengths);
  WARN("eight.off overlay layout: " << layout.flippedTriangles << " flipped, edge length error "
                                    << layout.maxEdgeLengthError << ", " << layout.cones.size()
                                    << " cones");
  CHECK(layout.flippedTriangles == 0);
  CHECK(layout.maxEdgeLengthError <= 1e-8);
  REQUIRE(layout.cones.size() == 1);
  CHECK(layout.cones[0].vertex == cones[0].vertex);
  CHECK(std::abs(layout.cones[0].curvature - cones[0].curvature) <= 1e-9);
}

TEST_CASE("intrinsic_overlay: a metric off the conformal class, on eight.off", "[structure]") {
  // The flip solver's triangulation with quantized cones, then another metric on its triangles:
  // the handles' rotations made quarter turns. The cells follow each triangle affinely and still
  // tile both surfaces.
  const EightWithFlips eight = eightWithFlips(false);
  const TriMesh& mesh = eight.mesh;
  const auto& cones = eight.cones;
  const auto& solved = eight.solved;
  IntrinsicTriangulation flat = solved.triangulation;
  flat.setLogLengths0(flat.logLengths(solved.ricci.u));
  const auto seamless = structure::quantizeHolonomy(flat, cones);
  REQUIRE(seamless.converged);
  CHECK(seamless.maxLogLengthChange > 1e-3);
  CHECK(seamless.triangulation.flipCount() == solved.triangulation.flipCount() + seamless.flips);
  const Eigen::VectorXd rotation = structure::loopRotations(seamless.triangulation, seamless.loops);
  for (Eigen::Index k = 0; k < rotation.size(); ++k)
    CHECK(std::abs(std::remainder(rotation[k], kPi / 2)) <= 1e-10);
  const auto& flips = seamless.triangulation.flippedEdges();
  const IntrinsicOverlay overlay =
      structure::intrinsicOverlay(mesh, flips, solved.ricci.u, seamless.edgeLengths);
  checkOverlay("eight.off, quantized cones and handles", mesh, flips, seamless.edgeLengths,
               overlay);
  const structure::FlatLayout layout =
      structure::layoutFlatMetric(overlay.mesh, overlay.edgeLengths);
  CHECK(layout.flippedTriangles == 0);
  CHECK(layout.maxEdgeLengthError <= 1e-8);
  CHECK(layout.cones.size() == cones.size());
}

TEST_CASE("intrinsic_overlay: a thousand random flips keep the subdivision consistent",
          "[structure]") {
  // Random Ptolemy flips make edges that cross hundreds of input edges at grazing angles, where
  // rounding decided which face a piece of an input edge fell in (cheese.off's quantized metrics
  // failed so). Their Euclidean triangles need not exist, and crossings pile up at grazing
  // angles, so only the combinatorics is measured: the cells tile every input face exactly once.
  const TriMesh torus = test::torus(12, 8);
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const std::vector<int> flips = randomFlips(torus, 1000, seed);
    const Eigen::VectorXd u = Eigen::VectorXd::Random(Eigen::Index(torus.n_vertices())) * 0.3;
    const IntrinsicOverlay overlay = overlayAt(torus, flips, u);
    INFO("seed " << seed << ", " << overlay.crossingInputEdge.size() << " crossings");
    CHECK(overlay.crossingInputEdge.size() > 2000);
    CHECK(overlay.mesh.n_vertices() == torus.n_vertices() + overlay.crossingInputEdge.size());
    CHECK(structure::analyzeTopology(overlay.mesh).euler == 0);
    REQUIRE(overlay.inputFace.size() == overlay.mesh.n_faces());
    std::vector<double> area(torus.n_faces(), 0.0);
    for (const auto f : overlay.mesh.faces())
      area[std::size_t(overlay.inputFace[f.idx()])] += overlay.mesh.calc_face_area(f);
    double worst = 0.0;
    for (const auto f : torus.faces())
      worst = std::max(worst,
                       std::abs(area[f.idx()] - torus.calc_face_area(f)) / torus.calc_face_area(f));
    CHECK(worst <= 1e-9);
  }
}
