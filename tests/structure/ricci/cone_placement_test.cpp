#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <queue>

#include <Eigen/SparseCholesky>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/index_map.h"
#include "mspline/structure/intrinsic/ricci_flips.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/mesh/subdivide.h"
#include "mspline/structure/ricci/cone_file.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::BoundaryCondition;
using structure::Cone;
using structure::ConePlacementOptions;
using structure::RicciStatus;
using structure::TriMesh;

namespace {

double curvatureSum(const std::vector<Cone>& cones) {
  double sum = 0.0;
  for (const Cone& c : cones) sum += c.curvature;
  return sum;
}

// The shortest path along edges from `source` to every vertex (3D lengths), by Dijkstra.
std::vector<double> edgePathDistances(const TriMesh& mesh, int source) {
  std::vector<double> distance(mesh.n_vertices(), std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  distance[std::size_t(source)] = 0.0;
  queue.push({0.0, source});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[std::size_t(v)]) continue;
    for (const auto w : mesh.vv_range(TriMesh::VertexHandle(v))) {
      const double next = d + (mesh.point(w) - mesh.point(TriMesh::VertexHandle(v))).norm();
      if (next < distance[std::size_t(w.idx())]) {
        distance[std::size_t(w.idx())] = next;
        queue.push({next, w.idx()});
      }
    }
  }
  return distance;
}

// Newton on the placed cones, asked for an absolute curvature error of 1e-10; prints the figures
// the milestone reports (area distortion exp(2u) normalized by its geometric mean).
structure::RicciResult flattenChecked(const std::string& name, const TriMesh& mesh,
                                      const structure::ConePlacementResult& placement) {
  structure::RicciNewtonOptions options;
  options.tolerance = 1e-10 / (2.0 * kPi);
  const auto target = structure::flatTarget(mesh, placement.cones, BoundaryCondition::FixedScale);
  const auto result = structure::solveVertexScaling(mesh, target, options);
  Eigen::VectorXd u = result.u;
  if (analyzeTopology(mesh).closed) u.array() -= u.mean();
  std::ostringstream cones;
  for (std::size_t i = 0; i < placement.cones.size() && i < 12; ++i)
    cones << ' ' << placement.cones[i].vertex << ':' << placement.cones[i].curvature;
  WARN(name << ": " << placement.message << ";" << cones.str() << "; Newton: " << result.message
            << ", " << result.iterations << " iterations, error " << result.maxCurvatureError
            << ", " << result.seconds << " s, max |u| " << u.cwiseAbs().maxCoeff()
            << ", exp(2u) in [" << std::exp(2 * u.minCoeff()) << ", " << std::exp(2 * u.maxCoeff())
            << "]");
  return result;
}

// Most of a sphere: icosphere(3) without the faces whose centroid is below z = -0.6 (one boundary
// loop).
TriMesh sphericalCap() {
  TriMesh cap = test::icosphere(3);
  for (const auto f : cap.faces()) {
    OpenMesh::Vec3d centroid(0, 0, 0);
    for (const auto v : cap.fv_range(f)) centroid += cap.point(v);
    if (centroid[2] < -3 * 0.6) cap.delete_face(f, true);
  }
  cap.garbage_collection();
  return cap;
}

void checkConverged(const TriMesh& mesh, const structure::RicciResult& result) {
  INFO(result.message);
  REQUIRE(result.converged);
  CHECK(result.maxCurvatureError <= 1e-10);
  CHECK(structure::degenerateFaces(mesh, result.edgeLengths).empty());
}

}  // namespace

TEST_CASE("cone_placement: icosphere, automatic cones flatten it", "[structure]") {
  const TriMesh mesh = test::icosphere(3);
  const auto placement = structure::placeCones(mesh);
  REQUIRE(placement.cones.size() >= 3);
  CHECK(std::abs(curvatureSum(placement.cones) - 4 * kPi) <= 1e-12);
  CHECK(placement.quarterTurns.empty());
  for (const Cone& c : placement.cones) {
    CHECK_FALSE(mesh.is_boundary(TriMesh::VertexHandle(c.vertex)));
    CHECK(2 * kPi - c.curvature >= ConePlacementOptions{}.minConeAngle);
  }
  // One distortion per round, the last one below the default threshold.
  CHECK(placement.distortionPerRound.size() == placement.cones.size() + 1);
  CHECK(placement.distortionPerRound.back() <= ConePlacementOptions{}.maxDistortion);
  checkConverged(mesh, flattenChecked("icosphere(3)", mesh, placement));
}

TEST_CASE("cone_placement: a placement stopped at the maximum number of cones says so",
          "[structure]") {
  const TriMesh mesh = test::icosphere(3);
  CHECK_FALSE(structure::placeCones(mesh).reachedMaxCones);
  // A distortion no six cones reach: placement stops at six, valid, and reports it.
  ConePlacementOptions options;
  options.maxDistortion = 1e-3;
  options.maxCones = 6;
  const auto placement = structure::placeCones(mesh, options);
  CHECK(placement.reachedMaxCones);
  CHECK(placement.cones.size() == 6);
  CHECK(placement.distortionPerRound.back() > options.maxDistortion);
  CHECK_THAT(placement.message, Catch::Contains("reached the maximum number of cones"));
  CHECK(std::abs(curvatureSum(placement.cones) - 4 * kPi) <= 1e-12);
}

TEST_CASE("cone_placement: icosphere, quantized cones are quarter turns", "[structure]") {
  const TriMesh mesh = test::icosphere(3);
  ConePlacementOptions options;
  options.quantize = true;
  const auto placement = structure::placeCones(mesh, options);
  REQUIRE(placement.quarterTurns.size() == placement.cones.size());
  int turns = 0;
  for (std::size_t i = 0; i < placement.cones.size(); ++i) {
    const double q = placement.cones[i].curvature / (kPi / 2);
    CHECK(std::abs(q - std::round(q)) <= 1e-12);
    CHECK(placement.quarterTurns[i] == std::lround(q));
    CHECK(placement.quarterTurns[i] != 0);
    CHECK(placement.quarterTurns[i] <= 3);
    turns += placement.quarterTurns[i];
  }
  CHECK(turns == 8);
  CHECK(std::abs(curvatureSum(placement.cones) - 4 * kPi) <= 1e-12);
  checkConverged(mesh, flattenChecked("icosphere(3) quantized", mesh, placement));
}

TEST_CASE("cone_placement: requested counts", "[structure]") {
  const TriMesh sphere = test::icosphere(2);
  ConePlacementOptions options;
  options.targetCount = 6;
  const auto six = structure::placeCones(sphere, options);
  CHECK(six.cones.size() == 6);
  CHECK(std::abs(curvatureSum(six.cones) - 4 * kPi) <= 1e-12);
  // Cones are at least minSeparation edges apart.
  for (const Cone& a : six.cones)
    for (const auto w : sphere.vv_range(TriMesh::VertexHandle(a.vertex)))
      for (const Cone& b : six.cones) CHECK(w.idx() != b.vertex);
  checkConverged(sphere, flattenChecked("icosphere(2), 6 cones", sphere, six));

  // A sphere cannot be flat without cones, nor with a single one (angle -2 pi).
  options.targetCount = 0;
  CHECK_THROWS_AS(structure::placeCones(sphere, options), structure::InputError);
  options.targetCount = 1;
  CHECK_THROWS_AS(structure::placeCones(sphere, options), structure::InputError);

  // A torus is flat without cones, automatically and on request.
  const TriMesh torus = test::torus(40, 20);
  CHECK(structure::placeCones(torus).cones.empty());
  options.targetCount = 0;
  const auto none = structure::placeCones(torus, options);
  CHECK(none.cones.empty());
  // The torus's conformal factor is log of the distance to the axis, up to a constant: its half
  // range is log(1.4 / 0.6) / 2.
  CHECK(none.distortion == Approx(std::log(1.4 / 0.6) / 2).epsilon(0.02));
}

TEST_CASE("cone_placement: knot1.off, genus 1, zero cones", "[structure]") {
  const TriMesh mesh = test::realMesh("knot1.off");
  ConePlacementOptions options;
  options.targetCount = 0;
  const auto placement = structure::placeCones(mesh, options);
  CHECK(placement.cones.empty());
  CHECK(placement.distortion > 0.0);
  checkConverged(mesh, flattenChecked("knot1.off, 0 cones", mesh, placement));
}

TEST_CASE("cone_placement: genus 2 with a single cone", "[structure]") {
  ConePlacementOptions options;
  options.singleCone = true;
  for (const std::string name : {"doubleTorus(3)", "eight.off"}) {
    const TriMesh mesh = name == "eight.off" ? test::realMesh(name) : test::doubleTorus(3);
    const auto placement = structure::placeCones(mesh, options);
    REQUIRE(placement.cones.size() == 1);
    CHECK(placement.cones[0].curvature == -4 * kPi);
    CHECK(placement.quarterTurns == std::vector<int>{-8});
    CHECK_FALSE(mesh.is_boundary(TriMesh::VertexHandle(placement.cones[0].vertex)));
    // A cone of angle 6 pi squeezes its neighbourhood until, on the fixed input triangulation,
    // triangles degenerate: without intrinsic Delaunay flips the solve stops (on both meshes, at
    // every vertex of eight.off). The failure must be reported as such, never silent.
    const auto result = flattenChecked(name + ", single cone", mesh, placement);
    INFO(result.message);
    if (result.converged) {
      checkConverged(mesh, result);
    } else {
      CHECK(result.status != RicciStatus::SolverFailed);
      CHECK_THAT(result.message, Catch::Contains("flips are needed"));
    }
  }
  SECTION("only for closed genus >= 2") {
    CHECK_THROWS_AS(structure::placeCones(test::icosphere(1), options), structure::TopologyError);
    CHECK_THROWS_AS(structure::placeCones(test::torus(20, 10), options), structure::TopologyError);
    CHECK_THROWS_AS(structure::placeCones(test::gridDisk(8), options), structure::TopologyError);
  }
}

TEST_CASE("cone_placement: quantized cones of negative curvature stay at angles up to 4 pi",
          "[structure]") {
  // Genus 3: 16 quarter turns of negative curvature. Capped at one cone, automatic placement
  // goes on to the -chi = 4 cones that can carry them at four quarter turns each, and may place
  // half as many again.
  const TriMesh mesh = test::genusSurface(3, 3);
  REQUIRE(structure::analyzeTopology(mesh).euler == -4);
  ConePlacementOptions options;
  options.quantize = true;
  options.maxCones = 1;
  const auto placement = structure::placeCones(mesh, options);
  CHECK(placement.cones.size() >= 4);
  CHECK(placement.cones.size() <= 6);
  int turns = 0;
  for (int k : placement.quarterTurns) {
    CHECK(k >= -4);
    CHECK(k <= 3);
    turns += k;
  }
  CHECK(turns == -16);
  CHECK(std::abs(curvatureSum(placement.cones) + 8 * kPi) <= 1e-12);
}

TEST_CASE("cone_placement: turbine and femur, no cone beyond 4 pi below the cap", "[structure]") {
  // Within maxCones: the greedy placement used to leave cones of -7 quarter turns (angle 5.5 pi)
  // here; curvature beyond -4 now draws more cones instead.
  for (const char* name : {"turbine.off", "femur.off"}) {
    const TriMesh mesh = test::realMesh(name);
    ConePlacementOptions options;
    options.quantize = true;
    options.maxQuarterTurns = 1;  // as the T-spline layout places them: corners of valence >= 3
    const auto placement = structure::placeCones(mesh, options);
    INFO(name << ": " << placement.message);
    CHECK(long(placement.cones.size()) <= options.maxCones);
    int turns = 0;
    for (int k : placement.quarterTurns) {
      CHECK(k >= -4);
      CHECK(k <= 1);
      turns += k;
    }
    CHECK(turns == 4 * structure::analyzeTopology(mesh).euler);
  }
}

TEST_CASE("cone_placement: genus 2, automatic cones satisfy Gauss-Bonnet", "[structure]") {
  const TriMesh mesh = test::doubleTorus(3);
  ConePlacementOptions options;
  const auto placement = structure::placeCones(mesh, options);
  REQUIRE_FALSE(placement.cones.empty());
  CHECK(std::abs(curvatureSum(placement.cones) + 4 * kPi) <= 1e-12);
  checkConverged(mesh, flattenChecked("doubleTorus(3)", mesh, placement));
  options.quantize = true;
  const auto quantized = structure::placeCones(mesh, options);
  int turns = 0;
  for (int k : quantized.quarterTurns) turns += k;
  CHECK(turns == -8);
  // A cone of angle 4 pi on this coarse mesh: its triangles degenerate before the metric is
  // reached, so through intrinsic flips, as flatten does.
  structure::RicciNewtonOptions newton;
  newton.tolerance = 1e-10 / (2.0 * kPi);
  const auto target = structure::flatTarget(mesh, quantized.cones, BoundaryCondition::FixedScale);
  const auto flipped = structure::solveVertexScalingWithFlips(mesh, target, newton);
  INFO(flipped.ricci.message);
  CHECK(flipped.ricci.converged);
  CHECK(flipped.ricci.maxCurvatureError <= 1e-10);
}

TEST_CASE("cone_placement: surfaces with boundary keep u = 0 there", "[structure]") {
  // A flat disk needs no cone.
  const TriMesh disk = test::gridDisk(10);
  const auto flat = structure::placeCones(disk);
  CHECK(flat.cones.empty());
  CHECK(flat.distortion <= 1e-12);

  // Most of a sphere, flattened with its boundary lengths kept, needs interior cones.
  const TriMesh cap = sphericalCap();
  REQUIRE(structure::analyzeTopology(cap).boundaryLoops == 1);
  ConePlacementOptions options;
  const auto placement = structure::placeCones(cap, options);
  REQUIRE_FALSE(placement.cones.empty());
  CHECK(placement.distortionPerRound.front() > options.maxDistortion);
  CHECK(placement.distortion <= placement.distortionPerRound.front());
  for (const Cone& c : placement.cones)
    CHECK_FALSE(cap.is_boundary(TriMesh::VertexHandle(c.vertex)));
  checkConverged(cap, flattenChecked("capped icosphere(3)", cap, placement));

  options.quantize = true;
  const auto quantized = structure::placeCones(cap, options);
  for (std::size_t i = 0; i < quantized.cones.size(); ++i)
    CHECK(quantized.cones[i].curvature == quantized.quarterTurns[i] * (kPi / 2));
  checkConverged(cap, flattenChecked("capped icosphere(3) quantized", cap, quantized));
}

// The input's Gauss curvature and cotangent Laplacian, factorized with u = 0 held on the boundary
// and at `held` (a factorization of its own, independent of the Green's function updates
// placeCones uses).
class HeldLaplacian {
 public:
  HeldLaplacian(const TriMesh& mesh, const std::vector<int>& held)
      : map_(mesh.n_vertices(), heldVertices(mesh, held)) {
    const Eigen::VectorXd lengths = structure::edgeLengths(mesh);
    curvature = structure::vertexCurvatures(mesh, lengths);
    laplacian = structure::vertexScalingHessian(
        mesh, lengths, Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices())));
    solver_.compute(map_.restrict(laplacian));
    REQUIRE(solver_.info() == Eigen::Success);
  }
  // L u = rhs at the free vertices, u = 0 at the held ones.
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(rhs.size());
    map_.scatter(solver_.solve(map_.gather(rhs)), u);
    return u;
  }
  Eigen::VectorXd curvature;
  Eigen::SparseMatrix<double> laplacian;

 private:
  static std::vector<char> heldVertices(const TriMesh& mesh, const std::vector<int>& held) {
    std::vector<char> flags(mesh.n_vertices(), 0);
    for (const auto v : mesh.vertices()) flags[v.idx()] = mesh.is_boundary(v);
    for (int v : held) flags[std::size_t(v)] = 1;
    return flags;
  }
  structure::IndexMap map_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
};

// The cone curvatures K + L u with u the direct solve of L u = -K at the free vertices, u = 0 at
// the cones and on the boundary.
std::vector<double> directConeCurvatures(const TriMesh& mesh, const std::vector<Cone>& cones) {
  std::vector<int> held;
  for (const Cone& c : cones) held.push_back(c.vertex);
  const HeldLaplacian system(mesh, held);
  const Eigen::VectorXd linear =
      system.curvature + system.laplacian * system.solve(-system.curvature);
  std::vector<double> result;
  for (const Cone& c : cones) result.push_back(linear[c.vertex]);
  return result;
}

TEST_CASE("cone_placement: cone curvatures equal the direct constrained solve", "[structure]") {
  // Closed (vertex 0, the gauge of the base system, is among the icosphere's cones) and with a
  // boundary.
  const TriMesh cap = sphericalCap();
  for (const TriMesh& mesh : {test::icosphere(3), test::doubleTorus(12), cap}) {
    const auto placement = structure::placeCones(mesh);
    REQUIRE_FALSE(placement.cones.empty());
    const auto direct = directConeCurvatures(mesh, placement.cones);
    for (std::size_t i = 0; i < direct.size(); ++i)
      CHECK(placement.cones[i].curvature == Approx(direct[i]).margin(1e-9));
  }
  CHECK(structure::placeCones(test::icosphere(3)).cones.front().vertex == 0);
}

TEST_CASE("cone_placement: bunny00.off, automatic quantized cones", "[structure][slow]") {
  const TriMesh mesh = test::realMesh("bunny00.off");
  ConePlacementOptions options;
  options.quantize = true;
  const auto placement = structure::placeCones(mesh, options);
  int turns = 0;
  for (int k : placement.quarterTurns) turns += k;
  CHECK(turns == 8);
  const auto result = flattenChecked("bunny00.off quantized", mesh, placement);
  checkConverged(mesh, result);
  CHECK(result.iterations <= 20);
}

// Cone angles stay at most 4 pi.
constexpr int kLowestQuarterTurns = -4;

// The area-weighted squared conformal factor of the linear solve for quantized cones: no quarter
// turn moved between two of them (closed: the sum is fixed) or added to or taken from one (with a
// boundary) lowers it.
void checkRoundingIsLocallyBest(const TriMesh& mesh, const structure::ConePlacementResult& placed,
                                int largest) {
  const bool closed = analyzeTopology(mesh).closed;
  // Closed: vertex 0 held as the gauge.
  const HeldLaplacian system(mesh, closed ? std::vector<int>{0} : std::vector<int>{});
  const Eigen::VectorXd& curvature = system.curvature;
  Eigen::VectorXd area = Eigen::VectorXd::Zero(curvature.size());
  for (const auto f : mesh.faces()) {
    auto v = mesh.cfv_begin(f);
    const auto a = *v++, b = *v++, c = *v;
    const double third =
        ((mesh.point(b) - mesh.point(a)) % (mesh.point(c) - mesh.point(a))).norm() / 6.0;
    for (const auto w : {a, b, c}) area[w.idx()] += third;
  }
  const auto spread = [&](const Eigen::VectorXd& u) {
    const double mean = closed ? area.dot(u) / area.sum() : 0.0;
    return area.dot((u.array() - mean).square().matrix());
  };
  Eigen::VectorXd rhs = -curvature;
  std::vector<Eigen::VectorXd> green;
  for (const Cone& c : placed.cones) {
    rhs[c.vertex] += c.curvature;
    Eigen::VectorXd unit = Eigen::VectorXd::Zero(curvature.size());
    unit[c.vertex] = kPi / 2;
    green.push_back(system.solve(unit));
  }
  const Eigen::VectorXd u = system.solve(rhs);
  const double best = spread(u);
  const auto& k = placed.quarterTurns;
  int moves = 0;
  for (std::size_t i = 0; i < green.size(); ++i) {
    if (!closed) {
      if (k[i] < largest) CHECK(spread(u + green[i]) >= best * (1.0 - 1e-12));
      if (k[i] > kLowestQuarterTurns) CHECK(spread(u - green[i]) >= best * (1.0 - 1e-12));
      moves += 2;
      continue;
    }
    for (std::size_t j = 0; j < green.size(); ++j)
      if (j != i && k[i] < largest && k[j] > kLowestQuarterTurns) {
        CHECK(spread(u + green[i] - green[j]) >= best * (1.0 - 1e-12));
        ++moves;
      }
  }
  CHECK(moves > 0);
}

TEST_CASE("cone_placement: rounding to quarter turns keeps the conformal factor small",
          "[structure]") {
  // cow.off: the linearized distortion is 0.92 before rounding; rounding each cone on its own
  // made it 5.9 (opposite cones a hundredth of a cell apart once flat).
  const TriMesh mesh = test::realMesh("cow.off");
  ConePlacementOptions options;
  const auto continuous = structure::placeCones(mesh, options);
  CHECK(continuous.distortion <= 1.0);
  options.quantize = true;
  options.maxQuarterTurns = 2;
  const auto quantized = structure::placeCones(mesh, options);
  int turns = 0;
  for (int k : quantized.quarterTurns) turns += k;
  CHECK(turns == 8);
  CHECK(quantized.distortion < 3.0);
  checkRoundingIsLocallyBest(mesh, quantized, 2);
  // With a boundary, quarter turns are added or taken one cone at a time.
  const TriMesh cap = sphericalCap();
  ConePlacementOptions capOptions;
  capOptions.quantize = true;
  capOptions.maxDistortion = 0.2;
  const auto capCones = structure::placeCones(cap, capOptions);
  REQUIRE_FALSE(capCones.cones.empty());
  checkRoundingIsLocallyBest(cap, capCones, 3);
}

TEST_CASE("cone_placement: cone files", "[structure]") {
  const std::string dir = test::scratchDirectory("cone_file");
  const auto write = [&](const std::string& name, const std::string& text) {
    const std::string path = dir + "/" + name;
    std::ofstream(path) << text;
    return path;
  };

  SECTION("round trip is exact") {
    const std::vector<Cone> cones = {{12, kPi / 2}, {0, -4 * kPi}, {7, 0.1 + 0.2}, {3, 1e-300}};
    const auto back = structure::readConeFile(write("c.txt", structure::formatConeFile(cones)));
    REQUIRE(back.size() == cones.size());
    for (std::size_t i = 0; i < cones.size(); ++i) {
      CHECK(back[i].vertex == cones[i].vertex);
      CHECK(back[i].curvature == cones[i].curvature);
    }
  }
  SECTION("comments and blank lines") {
    const auto cones =
        structure::readConeFile(write("c.txt", "# cones\n\n  5 1.5   # a comment\n\t9\t-3e-1\r\n"));
    REQUIRE(cones.size() == 2);
    CHECK(cones[0].vertex == 5);
    CHECK(cones[0].curvature == 1.5);
    CHECK(cones[1].vertex == 9);
    CHECK(cones[1].curvature == -0.3);
  }
  SECTION("malformed lines name the file and the line") {
    for (const std::string bad :
         {"4", "4 1.0 2.0", "-1 1.0", "x 1.0", "4 pi", "4 1.0x", "4 nan", "4.5 1.0", "4 1e999"}) {
      const std::string path = write("bad.txt", "# header\n1 0.5\n" + bad + "\n");
      INFO(bad);
      CHECK_THROWS_WITH(structure::readConeFile(path),
                        Catch::Contains(path + ":3:") && Catch::Contains("'" + bad + "'"));
      CHECK_THROWS_AS(structure::readConeFile(path), structure::InputError);
    }
    const std::string twice = write("twice.txt", "1 0.5\n2 0.5\n1 0.25\n");
    CHECK_THROWS_WITH(structure::readConeFile(twice),
                      Catch::Contains(twice + ":3:") && Catch::Contains("listed twice"));
  }
  SECTION("a missing file is an I/O error") {
    CHECK_THROWS_AS(structure::readConeFile(dir + "/missing.txt"), structure::IoError);
  }
  SECTION("a directory is refused, not read as an empty list (issue 17)") {
    std::filesystem::create_directories(dir + "/folder");
    CHECK_THROWS_AS(structure::readConeFile(dir + "/folder"), structure::IoError);
    CHECK_THROWS_WITH(structure::readConeFile(dir + "/folder"), Catch::Contains(dir + "/folder"));
  }
}

TEST_CASE("cone_placement: automatic placement that cannot flatten is a failed computation",
          "[structure]") {
  // A needle: every vertex a cone, and the apex's angle still below pi/4.
  const TriMesh needle = structure::toTriMesh(test::needleSoup());
  CHECK_THROWS_AS(structure::placeCones(needle), structure::SolverError);
  CHECK_THROWS_WITH(structure::placeCones(needle),
                    Catch::Contains("cone placement") && Catch::Contains("4 cones"));
  // A count the caller asked for is the caller's to change.
  ConePlacementOptions options;
  options.targetCount = 1;
  CHECK_THROWS_AS(structure::placeCones(needle, options), structure::InputError);
}

TEST_CASE("cone_placement: coarse polyhedra get a cone at every corner that needs one",
          "[structure]") {
  // A unit tetrahedron: its corners are next to each other, closer than minSeparation, and carry
  // all the curvature; quantized, four quarter-turn multiples of at most 2 summing to 8.
  const TriMesh tetrahedron = structure::toTriMesh(test::tetrahedronSoup());
  const auto placement = structure::placeCones(tetrahedron);
  CHECK(placement.cones.size() == 4);
  CHECK(std::abs(curvatureSum(placement.cones) - 4 * kPi) <= 1e-12);
  ConePlacementOptions options;
  options.quantize = true;
  options.maxQuarterTurns = 2;
  const auto quantized = structure::placeCones(tetrahedron, options);
  REQUIRE(quantized.quarterTurns.size() == 4);
  for (int k : quantized.quarterTurns) CHECK(k == 2);
  checkConverged(tetrahedron, flattenChecked("tetrahedron, angles pi", tetrahedron, quantized));
  // An octahedron's six corners carry 4/3 of a quarter turn each: too few cones for at most one
  // quarter turn each until all six are placed.
  const TriMesh octahedron = structure::toTriMesh(test::octahedronSoup());
  options.maxQuarterTurns = 1;
  CHECK_THROWS_WITH(structure::placeCones(octahedron, options),
                    Catch::Contains("cannot be quantized"));
  options.maxQuarterTurns = 2;
  const auto octahedronCones = structure::placeCones(octahedron, options);
  int turns = 0;
  for (int k : octahedronCones.quarterTurns) turns += k;
  CHECK(turns == 8);
  CHECK(octahedronCones.quarterTurns.size() >= 4);
}

TEST_CASE("cone_placement: coarse polyhedra split at edge midpoints carry valence-3 corners",
          "[structure]") {
  ConePlacementOptions options;
  options.quantize = true;
  options.maxQuarterTurns = 1;
  // Eight cones of one quarter turn: the tetrahedron's 4 vertices need one split (10), the
  // octahedron's 6 one (18); the cube's 8 are enough.
  const TriMesh tetrahedron = structure::toTriMesh(test::tetrahedronSoup());
  const TriMesh octahedron = structure::toTriMesh(test::octahedronSoup());
  CHECK(structure::midpointLevelsForQuarterTurnCones(tetrahedron, 1) == 1);
  CHECK(structure::midpointLevelsForQuarterTurnCones(tetrahedron, 2) == 0);
  CHECK(structure::midpointLevelsForQuarterTurnCones(octahedron, 1) == 1);
  CHECK(structure::midpointLevelsForQuarterTurnCones(test::cubeSurface(1), 1) == 0);
  CHECK(structure::midpointLevelsForQuarterTurnCones(test::torus(6, 4), 1) == 0);
  CHECK(structure::midpointLevelsForQuarterTurnCones(test::gridDisk(1), 1) == 0);
  CHECK_THROWS_AS(structure::midpointLevelsForQuarterTurnCones(tetrahedron, 0),
                  structure::InputError);
  for (const auto& [name, coarse] :
       {std::pair{"tetrahedron", tetrahedron}, {"octahedron", octahedron}}) {
    INFO(name);
    CHECK_THROWS_WITH(structure::placeCones(coarse, options),
                      Catch::Contains("cannot be quantized"));
    const TriMesh mesh = structure::subdivideMidpoint(coarse);
    const auto placement = structure::placeCones(mesh, options);
    int turns = 0;
    for (int k : placement.quarterTurns) {
      CHECK(k <= 1);
      turns += k;
    }
    CHECK(turns == 8);
    CHECK(std::abs(curvatureSum(placement.cones) - 4 * kPi) <= 1e-12);
    checkConverged(mesh, flattenChecked(name, mesh, placement));
  }
}

TEST_CASE("cone_placement: quantized cones can be kept at angle pi or more", "[structure]") {
  // A sphere with a spike twice its radius: its tip gathers about three quarter turns.
  TriMesh mesh = test::icosphere(3);
  mesh.set_point(mesh.vertex_handle(0), mesh.point(mesh.vertex_handle(0)) * 2.0);
  ConePlacementOptions options;
  options.quantize = true;
  const auto sharp = structure::placeCones(mesh, options);
  CHECK(*std::max_element(sharp.quarterTurns.begin(), sharp.quarterTurns.end()) == 3);
  options.maxQuarterTurns = 2;
  const auto blunt = structure::placeCones(mesh, options);
  int turns = 0;
  for (int k : blunt.quarterTurns) {
    CHECK(k <= 2);
    turns += k;
  }
  CHECK(turns == 8);
  CHECK(std::abs(curvatureSum(blunt.cones) - 4 * kPi) <= 1e-12);
  checkConverged(mesh, flattenChecked("spiked icosphere, angles >= pi", mesh, blunt));
  options.maxQuarterTurns = 4;
  CHECK_THROWS_AS(structure::placeCones(mesh, options), structure::InputError);
}

TEST_CASE("cone_placement: a spike's curvature above the cap draws more cones to it",
          "[structure]") {
  // The spike's tip carries about three quarter turns. With corners of valence 3 (one quarter
  // turn per cone) it needs three cones or more near the tip; a single cone there, cut to one
  // quarter turn by rounding, sends the rest across the sphere (and its uncut angle, below pi/4,
  // made the automatic placement give up).
  TriMesh spiked = test::icosphere(3);
  spiked.set_point(spiked.vertex_handle(0), spiked.point(spiked.vertex_handle(0)) * 2.0);
  const TriMesh mesh = structure::subdivideMidpoint(structure::subdivideMidpoint(spiked));
  const auto tip = mesh.vertex_handle(0);
  ConePlacementOptions options;
  options.quantize = true;
  options.maxQuarterTurns = 1;
  const auto placement = structure::placeCones(mesh, options);
  int turns = 0, turnsNearTip = 0;
  for (std::size_t i = 0; i < placement.cones.size(); ++i) {
    CHECK(placement.quarterTurns[i] <= 1);
    turns += placement.quarterTurns[i];
    const auto p = mesh.point(mesh.vertex_handle(placement.cones[i].vertex));
    if ((p - mesh.point(tip)).norm() < 1.0) turnsNearTip += placement.quarterTurns[i];
  }
  CHECK(turns == 8);
  CHECK(turnsNearTip >= 3);
  CHECK(std::abs(curvatureSum(placement.cones) - 4 * kPi) <= 1e-12);
  checkConverged(mesh, flattenChecked("spiked icosphere, angles >= 3 pi / 2", mesh, placement));
}

TEST_CASE("cone_placement: cones kept a length apart along edges", "[structure]") {
  // The spiked sphere of the case above, twelve cones: two edges apart, two of them are closer
  // than 0.8 along edges.
  TriMesh spiked = test::icosphere(3);
  spiked.set_point(spiked.vertex_handle(0), spiked.point(spiked.vertex_handle(0)) * 2.0);
  const TriMesh mesh = structure::subdivideMidpoint(structure::subdivideMidpoint(spiked));
  const auto closest = [&](const structure::ConePlacementResult& placement) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const Cone& a : placement.cones) {
      const std::vector<double> distance = edgePathDistances(mesh, a.vertex);
      for (const Cone& b : placement.cones)
        if (b.vertex != a.vertex) nearest = std::min(nearest, distance[std::size_t(b.vertex)]);
    }
    return nearest;
  };
  ConePlacementOptions options;
  options.targetCount = 12;
  CHECK(closest(structure::placeCones(mesh, options)) < 0.8);
  options.minSeparationLength = 0.8;
  const auto apart = structure::placeCones(mesh, options);
  CHECK(apart.cones.size() == 12);
  CHECK(closest(apart) >= 0.8);
  CHECK(std::abs(curvatureSum(apart.cones) - 4 * kPi) <= 1e-12);
  checkConverged(mesh, flattenChecked("spiked icosphere, cones 0.8 apart", mesh, apart));
}
