#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "spline/tspline.h"
#include "spline/tspline_bezier.h"
#include "spline/tspline_check.h"
#include "structure/errors.h"

using namespace mspline;
using spline::TMesh;
using spline::TSplineSpace;

namespace {

std::vector<double> range(int n) {
  std::vector<double> values;
  for (int i = 0; i <= n; ++i) values.push_back(i);
  return values;
}

// The unit cells of an n x n grid, some replaced by the merged rectangles [x0, y0, x1, y1].
TMesh gridWithMerges(int n, const std::vector<std::array<int, 4>>& merged) {
  std::vector<std::array<int, 4>> rectangles = merged;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool covered = std::any_of(merged.begin(), merged.end(), [&](const auto& r) {
        return i >= r[0] && i < r[2] && j >= r[1] && j < r[3];
      });
      if (!covered) rectangles.push_back({i, j, i + 1, j + 1});
    }
  Eigen::MatrixX2d lo(rectangles.size(), 2), hi(rectangles.size(), 2);
  for (std::size_t r = 0; r < rectangles.size(); ++r) {
    lo.row(Eigen::Index(r)) << rectangles[r][0], rectangles[r][1];
    hi.row(Eigen::Index(r)) << rectangles[r][2], rectangles[r][3];
  }
  return spline::planarTMesh(lo, hi);
}

// The 2 x 2 block [2,4]^2 of a 6 x 6 grid as one face (face 0): four T-junctions facing each
// other, so the T-mesh is not analysis-suitable.
TMesh mergedBlock() {
  return gridWithMerges(6, {{2, 2, 4, 4}});
}

// An 8 x 8 grid whose line x = 4 stops at the T-junction (4, 4) (face 0 at (3, 4)):
// analysis-suitable.
TMesh stoppedLine() {
  return gridWithMerges(8, {{3, 4, 5, 5}, {3, 5, 5, 6}, {3, 6, 5, 7}, {3, 7, 5, 8}});
}

// Global position of a vertex of a planar T-mesh: faces' frames are translations of the plane,
// and planarTMesh starts each face at its lower-left corner.
int vertexAt(const TMesh& mesh, const std::vector<Eigen::Vector2d>& origin, Eigen::Vector2d p) {
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (std::size_t k = 0; k < mesh.faces[f].vertices.size(); ++k)
      if ((origin[std::size_t(f)] + mesh.faces[f].positions[k] - p).norm() < 1e-12)
        return mesh.faces[f].vertices[k];
  return -1;
}

// Lower-left corners of the faces, walking from face 0 at `first`.
std::vector<Eigen::Vector2d> faceOrigins(const TMesh& mesh, const Eigen::Vector2d& first) {
  std::vector<Eigen::Vector2d> origin(mesh.faces.size(), first);
  std::vector<char> done(mesh.faces.size(), 0);
  std::vector<int> stack{0};
  done[0] = 1;
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    for (std::size_t k = 0; k < mesh.faces[f].vertices.size(); ++k) {
      const int g = mesh.faces[f].twinFace[k];
      if (g < 0 || done[std::size_t(g)]) continue;
      // A point x of f's frame is x + origin(f) globally and across(x) + origin(g).
      origin[std::size_t(g)] = origin[std::size_t(f)] - mesh.acrossEdge(f, int(k)).translation;
      done[std::size_t(g)] = 1;
      stack.push_back(g);
    }
  }
  return origin;
}

}  // namespace

TEST_CASE("tspline: a uniform grid has uniform knots, padded beyond its boundary", "[spline]") {
  const TSplineSpace space(spline::gridTMesh(range(8), range(8)));
  CHECK(space.numBasis() == 81);
  CHECK(space.missingAnchors().empty());
  for (const auto& anchor : space.anchors()) {
    const std::array<double, 5> uniform{-2, -1, 0, 1, 2};
    CHECK(anchor.sKnots == uniform);
    CHECK(anchor.tKnots == uniform);
  }
  // Faces one cell or more inside the boundary have all 16 functions: a partition of unity.
  std::mt19937 random(2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::TSplineBasisValue> basis;
  for (int j = 1; j < 7; ++j)
    for (int i = 1; i < 7; ++i) {
      space.basisAt(j * 8 + i, Eigen::Vector2d(unit(random), unit(random)), basis);
      double sum = 0.0;
      for (const auto& b : basis) sum += b.value;
      CHECK(basis.size() == 16);
      CHECK(sum == Approx(1.0).margin(1e-14));
    }
  space.basisAt(0, Eigen::Vector2d(0.5, 0.5), basis);
  CHECK(basis.size() == 9);
}

TEST_CASE("tspline: knots are inferred through T-junctions", "[spline]") {
  const TMesh mesh = mergedBlock();
  const TSplineSpace space(mesh);
  const auto origin = faceOrigins(mesh, {2, 2});
  CHECK(mesh.numVertices == 48);
  CHECK(space.numBasis() == 48);
  // Below the block: the vertical ray from (3, 1) meets y = 2, then nothing until y = 4.
  const auto& below = space.anchors()[space.anchorOfVertex()[vertexAt(mesh, origin, {3, 1})]];
  CHECK(below.tKnots == std::array<double, 5>{-2, -1, 0, 1, 3});
  CHECK(below.sKnots == std::array<double, 5>{-2, -1, 0, 1, 2});
  // At the T-junction (3, 2): up through the block to (3, 4), then (3, 5).
  const auto& junction = space.anchors()[space.anchorOfVertex()[vertexAt(mesh, origin, {3, 2})]];
  CHECK(junction.tKnots == std::array<double, 5>{-2, -1, 0, 2, 3});
  CHECK(junction.sKnots == std::array<double, 5>{-2, -1, 0, 1, 2});
  // Left of the block on its middle line: (1, 3) sees x = 2, then (4, 3) across the block.
  const auto& left = space.anchors()[space.anchorOfVertex()[vertexAt(mesh, origin, {1, 3})]];
  CHECK(left.sKnots == std::array<double, 5>{-2, -1, 0, 1, 3});
}

TEST_CASE("tspline: an analysis-suitable T-mesh is a partition of unity inside", "[spline]") {
  const TMesh mesh = stoppedLine();
  const TSplineSpace space(mesh);
  const auto origin = faceOrigins(mesh, {3, 4});
  CHECK(space.missingAnchors().empty());
  std::mt19937 random(4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::TSplineBasisValue> basis;
  double worst = 0.0;
  int samples = 0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const auto& face = mesh.faces[f];
    const Eigen::Vector2d lo = origin[std::size_t(f)];
    // Away from the boundary, where every function has its own knots.
    if (lo.minCoeff() < 2.0 || lo.x() + face.width > 6.0 || lo.y() + face.height > 6.0) continue;
    for (int s = 0; s < 50; ++s) {
      space.basisAt(f, Eigen::Vector2d(unit(random) * face.width, unit(random) * face.height),
                    basis);
      double sum = 0.0;
      for (const auto& b : basis) sum += b.value;
      worst = std::max(worst, std::abs(sum - 1.0));
      ++samples;
    }
  }
  CHECK(samples > 500);
  CHECK(worst <= 1e-12);
}

TEST_CASE("tspline: T-junctions facing each other need the rational normalization", "[spline]") {
  const TMesh mesh = mergedBlock();
  const TSplineSpace space(mesh);
  std::mt19937 random(5);
  Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
  spline::TSplineCheckOptions options;
  options.samples = 4000;
  const auto check = spline::checkTSpline(space, control, {}, options);
  // The block's neighbourhood sums to less (or more) than one; the rational form still evaluates.
  CHECK(check.normalizedSamples > 0);
  CHECK(check.partitionOfUnityError > 1e-6);
  CHECK(check.holeSamples == 0);
  CHECK(check.minDenominator > 0.1);
  CHECK(check.chartDiscrepancy <= 1e-14);
  CHECK(check.knotRouteDiscrepancy <= 1e-14);
  CHECK(check.bezierDiscrepancy <= 1e-12);
}

TEST_CASE("tspline: derivatives of the rational surface match finite differences", "[spline]") {
  const TMesh mesh = mergedBlock();
  const TSplineSpace space(mesh);
  std::mt19937 random(6);
  std::uniform_real_distribution<double> unit(0.05, 0.95), weight(0.5, 2.0);
  const Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
  Eigen::VectorXd weights(space.numBasis());
  for (Eigen::Index i = 0; i < weights.size(); ++i) weights[i] = weight(random);
  const double h = 1e-5;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const auto& face = mesh.faces[f];
    const Eigen::Vector2d p(unit(random) * face.width, unit(random) * face.height);
    const auto at = [&](double dx, double dy) {
      return space.evaluate(control, weights, f, p + Eigen::Vector2d(dx, dy), 1);
    };
    const auto point = space.evaluate(control, weights, f, p, 2);
    CHECK((point.ds - (at(h, 0).position - at(-h, 0).position) / (2 * h)).norm() < 1e-7);
    CHECK((point.dt - (at(0, h).position - at(0, -h).position) / (2 * h)).norm() < 1e-7);
    CHECK((point.dss - (at(h, 0).ds - at(-h, 0).ds) / (2 * h)).norm() < 1e-6);
    CHECK((point.dst - (at(0, h).ds - at(0, -h).ds) / (2 * h)).norm() < 1e-6);
    CHECK((point.dtt - (at(0, h).dt - at(0, -h).dt) / (2 * h)).norm() < 1e-6);
  }
}

TEST_CASE("tspline: Bezier extraction reproduces the T-spline", "[spline]") {
  for (const TMesh& mesh :
       {mergedBlock(), stoppedLine(), spline::gridTMesh(range(7), range(6), true, true)}) {
    const TSplineSpace space(mesh);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0), weight(0.5, 2.0);
    const Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
    Eigen::VectorXd weights(space.numBasis());
    for (Eigen::Index i = 0; i < weights.size(); ++i) weights[i] = weight(random);
    const spline::TSplineBezier bezier(space, control, weights);
    CHECK(bezier.numElements() >= mesh.numFaces());
    double worst = 0.0, worstDerivative = 0.0;
    for (int s = 0; s < 2000; ++s) {
      const int f = std::uniform_int_distribution<int>(0, mesh.numFaces() - 1)(random);
      const auto& face = mesh.faces[f];
      const Eigen::Vector2d p(unit(random) * face.width, unit(random) * face.height);
      const auto direct = space.evaluate(control, weights, f, p);
      Eigen::Vector3d x, du, dv;
      bezier.evaluate(f, p, x, &du, &dv);
      worst = std::max(worst, (x - direct.position).norm());
      worstDerivative =
          std::max({worstDerivative, (du - direct.ds).norm(), (dv - direct.dt).norm()});
    }
    CHECK(worst <= 1e-12);
    CHECK(worstDerivative <= 1e-11);
  }
}

TEST_CASE("tspline: a periodic grid is a closed partition of unity, seamless", "[spline]") {
  const TSplineSpace space(spline::gridTMesh(range(9), range(5), true, true));
  CHECK(space.numBasis() == 45);
  const Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
  spline::TSplineCheckOptions options;
  options.samples = 3000;
  const auto check = spline::checkTSpline(space, control, {}, options);
  CHECK(check.partitionOfUnityError <= 1e-14);
  CHECK(check.normalizedSamples == 0);
  CHECK(check.edgeSamples > 2000);
  CHECK(check.chartDiscrepancy <= 1e-15);
  CHECK(check.bezierDiscrepancy <= 1e-14);
}

TEST_CASE("tspline: wrong control point counts are refused", "[spline]") {
  const TSplineSpace space(spline::gridTMesh(range(4), range(4)));
  CHECK_THROWS_AS(space.evaluate(Eigen::MatrixXd::Zero(3, 3), {}, 0, Eigen::Vector2d(0.5, 0.5)),
                  structure::InputError);
  CHECK_THROWS_AS(space.evaluate(Eigen::MatrixXd::Zero(25, 3), Eigen::VectorXd::Ones(2), 0,
                                 Eigen::Vector2d(0.5, 0.5)),
                  structure::InputError);
  CHECK_THROWS_AS(spline::TSplineBezier(space, Eigen::MatrixXd::Zero(25, 2)),
                  structure::InputError);
}
