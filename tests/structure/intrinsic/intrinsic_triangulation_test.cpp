#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/index_map.h"
#include "mspline/structure/intrinsic/intrinsic_triangulation.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::IntrinsicTriangulation;
using structure::TriMesh;

namespace {

// Two triangles (p0, p1, p2) and (p0, p2, p3) sharing the diagonal p0 p2.
TriMesh quadrilateral(const std::array<OpenMesh::Vec3d, 4>& p) {
  TriMesh mesh;
  std::array<TriMesh::VertexHandle, 4> v;
  for (int i = 0; i < 4; ++i) v[i] = mesh.add_vertex(p[i]);
  mesh.add_face(v[0], v[1], v[2]);
  mesh.add_face(v[0], v[2], v[3]);
  return mesh;
}

int edgeBetween(const IntrinsicTriangulation& tri, int a, int b) {
  for (int e = 0; e < tri.edgeCount(); ++e) {
    const auto v = tri.edgeVertices(e);
    if ((v[0] == a && v[1] == b) || (v[0] == b && v[1] == a)) return e;
  }
  return -1;
}

// The corner table is consistent: twins pair up on one edge with opposite directions, and every
// edge's halfedge belongs to it.
void checkConnectivity(const IntrinsicTriangulation& tri) {
  int bad = 0;
  for (int h = 0; h < 3 * tri.faceCount(); ++h) {
    const int t = tri.twin(h);
    if (t < 0) continue;
    bad += tri.twin(t) != h || tri.edge(t) != tri.edge(h) || tri.tip(t) != tri.tail(h) ||
           tri.tail(t) != tri.tip(h);
  }
  for (int e = 0; e < tri.edgeCount(); ++e) bad += tri.edge(tri.halfedge(e)) != e;
  CHECK(bad == 0);
}

}  // namespace

TEST_CASE(
    "intrinsic_triangulation: a Ptolemy flip of a cyclic quadrilateral gives the other "
    "diagonal",
    "[structure]") {
  std::array<OpenMesh::Vec3d, 4> p;
  const double angle[4] = {0.3, 1.9, 3.4, 5.0};
  for (int i = 0; i < 4; ++i) p[i] = {2.5 * std::cos(angle[i]), 2.5 * std::sin(angle[i]), 0.0};
  const TriMesh mesh = quadrilateral(p);
  IntrinsicTriangulation tri(mesh);
  const int diagonal = edgeBetween(tri, 0, 2);
  REQUIRE(diagonal >= 0);
  const Eigen::VectorXd before = tri.lengths(Eigen::VectorXd::Zero(4));
  // Concyclic: opposite angles sum to pi, the Delaunay tie.
  CHECK(std::abs(tri.delaunayCosineSum(diagonal, Eigen::VectorXd::Zero(4))) <= 1e-14);
  const double energyBefore =
      structure::intrinsicEnergy(tri, Eigen::VectorXd::Zero(4), Eigen::VectorXd::Zero(4));

  tri.flip(diagonal);
  checkConnectivity(tri);
  CHECK(tri.flipCount() == 1);
  CHECK_FALSE(tri.isInputEdge(diagonal));
  const auto ends = tri.edgeVertices(diagonal);
  CHECK(std::min(ends[0], ends[1]) == 1);
  CHECK(std::max(ends[0], ends[1]) == 3);
  const Eigen::VectorXd after = tri.lengths(Eigen::VectorXd::Zero(4));
  const double trueDiagonal = (p[1] - p[3]).norm();
  CHECK(std::abs(after[diagonal] - trueDiagonal) <= 1e-14 * trueDiagonal);
  // Ptolemy: product of the diagonals = sum of the products of opposite sides.
  const auto side = [&](int a, int b) { return after[edgeBetween(tri, a, b)]; };
  CHECK(std::abs(before[diagonal] * after[diagonal] -
                 (side(0, 1) * side(2, 3) + side(1, 2) * side(3, 0))) <= 1e-13);
  for (int e = 0; e < tri.edgeCount(); ++e)
    if (e != diagonal) CHECK(after[e] == before[e]);
  // Orientation is kept: both faces still wind counterclockwise in the plane.
  for (const auto& f : tri.faces()) {
    const OpenMesh::Vec3d n = (p[f[1]] - p[f[0]]) % (p[f[2]] - p[f[0]]);
    CHECK(n[2] > 0.0);
  }
  // The energy does not change at a Delaunay tie.
  CHECK(
      std::abs(structure::intrinsicEnergy(tri, Eigen::VectorXd::Zero(4), Eigen::VectorXd::Zero(4)) -
               energyBefore) <= 1e-13);
  // Flipping back restores the original length exactly up to rounding (Ptolemy is an involution).
  tri.flip(diagonal);
  CHECK(std::abs(tri.lengths(Eigen::VectorXd::Zero(4))[diagonal] - before[diagonal]) <=
        1e-14 * before[diagonal]);
  CHECK_THROWS_AS(tri.flip(edgeBetween(tri, 0, 1)), structure::InternalError);
}

TEST_CASE("intrinsic_triangulation: flips commute with vertex scaling", "[structure]") {
  // A non-cyclic quadrilateral whose diagonal p0 p2 is not Delaunay: the flip makes it Delaunay,
  // and the flipped length at u equals the Ptolemy length computed from the scaled sides.
  const TriMesh mesh = quadrilateral({OpenMesh::Vec3d(0, 0, 0), OpenMesh::Vec3d(3, -0.4, 0),
                                      OpenMesh::Vec3d(6, 0, 0), OpenMesh::Vec3d(3, 0.5, 0)});
  IntrinsicTriangulation tri(mesh);
  const Eigen::VectorXd u = (Eigen::VectorXd(4) << 0.3, -0.7, 1.1, 0.2).finished();
  const int diagonal = edgeBetween(tri, 0, 2);
  const Eigen::VectorXd scaled = tri.lengths(u);
  const auto side = [&](int a, int b) { return scaled[edgeBetween(tri, a, b)]; };
  const double expected = (side(0, 1) * side(2, 3) + side(1, 2) * side(3, 0)) / scaled[diagonal];
  CHECK(tri.delaunayCosineSum(diagonal, Eigen::VectorXd::Zero(4)) < -1.0);
  CHECK(tri.flipToDelaunay(Eigen::VectorXd::Zero(4)) == 1);
  CHECK(std::abs(tri.lengths(u)[diagonal] - expected) <= 1e-13 * expected);
  CHECK(tri.delaunayCosineSum(diagonal, Eigen::VectorXd::Zero(4)) >= 0.0);
}

TEST_CASE(
    "intrinsic_triangulation: flipping to Delaunay terminates with opposite angles at most "
    "pi",
    "[structure]") {
  for (const std::string name : {"eight.off", "mannequin-devil.off", "torus"}) {
    const TriMesh mesh = name == "torus" ? test::torus(24, 12) : test::realMesh(name);
    const auto topology = structure::analyzeTopology(mesh);
    IntrinsicTriangulation tri(mesh);
    // Strong random scale factors make many triangles violate the triangle inequality.
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-2.0, 2.0);
    Eigen::VectorXd u(tri.vertexCount());
    for (int v = 0; v < tri.vertexCount(); ++v) u[v] = uniform(random);
    const long flips = tri.flipToDelaunay(u);
    WARN(name << ": " << flips << " flips to Delaunay at random u");
    CHECK(flips > 0);
    CHECK(tri.flipCount() == flips);
    checkConnectivity(tri);
    const Eigen::VectorXd angles = structure::intrinsicCornerAngles(tri, u);
    double worst = 0.0;
    for (int h = 0; h < 3 * tri.faceCount(); ++h)
      if (tri.twin(h) >= 0) worst = std::max(worst, angles[h] + angles[tri.twin(h)] - kPi);
    CHECK(worst <= 1e-12);
    // On a closed surface every triangle of the Delaunay triangulation satisfies the triangle
    // inequality; with a boundary (never flipped) random scale factors can leave some that do not.
    const Eigen::VectorXd l = tri.lengths(u);
    int degenerate = 0, atBoundary = 0;
    for (int f = 0; f < tri.faceCount(); ++f) {
      std::array<double, 3> s = {l[tri.edge(3 * f)], l[tri.edge(3 * f + 1)],
                                 l[tri.edge(3 * f + 2)]};
      if (s[0] + s[1] > s[2] && s[1] + s[2] > s[0] && s[2] + s[0] > s[1]) continue;
      bool boundary = false;
      for (int k = 0; k < 3; ++k) boundary = boundary || tri.twin(3 * f + k) < 0;
      (boundary ? atBoundary : degenerate) += 1;
    }
    WARN(name << ": degenerate triangles " << atBoundary << " with a boundary edge, " << degenerate
              << " others");
    if (topology.closed) CHECK(degenerate + atBoundary == 0);
    // Gauss-Bonnet holds for any metric on the triangulation.
    const Eigen::VectorXd k = structure::intrinsicCurvatures(tri, u);
    CHECK(std::abs(k.sum() - 2 * kPi * topology.euler) <= 1e-9);
    // Already Delaunay: nothing more to flip.
    CHECK(tri.flipToDelaunay(u) == 0);
  }
}

TEST_CASE("intrinsic_triangulation: Hessian and gradient match finite differences", "[structure]") {
  const TriMesh mesh = test::torus(12, 6);
  IntrinsicTriangulation tri(mesh);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(-0.5, 0.5);
  Eigen::VectorXd u(tri.vertexCount());
  for (int v = 0; v < tri.vertexCount(); ++v) u[v] = uniform(random);
  tri.flipToDelaunay(u);
  const Eigen::VectorXd target = Eigen::VectorXd::Zero(tri.vertexCount());
  const structure::IndexMap all(std::size_t(tri.vertexCount()), {});
  const Eigen::MatrixXd hessian = Eigen::MatrixXd(structure::intrinsicHessian(tri, u, all));
  const Eigen::VectorXd gradient = structure::intrinsicGradient(tri, u, target);
  const double h = 1e-6;
  double hessianError = 0.0, gradientError = 0.0;
  for (int v = 0; v < tri.vertexCount(); v += 7) {
    Eigen::VectorXd plus = u, minus = u;
    plus[v] += h;
    minus[v] -= h;
    const Eigen::VectorXd column = (structure::intrinsicGradient(tri, plus, target) -
                                    structure::intrinsicGradient(tri, minus, target)) /
                                   (2 * h);
    hessianError = std::max(hessianError, (column - hessian.col(v)).cwiseAbs().maxCoeff());
    const double slope = (structure::intrinsicEnergy(tri, plus, target) -
                          structure::intrinsicEnergy(tri, minus, target)) /
                         (2 * h);
    gradientError = std::max(gradientError, std::abs(slope - gradient[v]));
  }
  CHECK(hessianError <= 1e-6);
  CHECK(gradientError <= 1e-6);
  CHECK(std::abs(hessian.sum()) <= 1e-9);
}
