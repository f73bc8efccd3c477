#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/layout_tmesh.h"
#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_refine.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/motorcycle_layout.h"
#include "support/flat_metric.h"
#include "support/test_data.h"
#include "support/test_tmeshes.h"

using namespace mspline;
using spline::FaceSplit;
using spline::TMesh;
using spline::TSplineRefinement;
using spline::TSplineSpace;
using test::planarVertices;
using test::randomPoints;
using test::randomWeights;

namespace {

constexpr int kCells = 10;

// kCells + 1 increasing knot lines from 0, spacings in [0.5, 1.5] (or all 1).
std::vector<double> knotLines(std::mt19937& rng, bool uniform) {
  std::uniform_real_distribution<double> spacing(0.5, 1.5);
  std::vector<double> lines{0.0};
  for (int i = 0; i < kCells; ++i) lines.push_back(lines.back() + (uniform ? 1.0 : spacing(rng)));
  return lines;
}

// splitIntoFour's definition, one face at a time: splitFace along x through the middle, then each
// half along y; points on the far part of a cut follow it.
void splitOneByOne(TMesh& mesh, const std::vector<int>& faces,
                   std::vector<spline::FacePoint>& points) {
  const auto half = [&](int face, int axis) {
    const spline::TMeshFace& f = mesh.faces[std::size_t(face)];
    const double middle = 0.5 * (axis == 0 ? f.width : f.height);
    const int far = mesh.numFaces();
    mesh = spline::splitFace(mesh, face, axis, middle);
    for (auto& p : points)
      if (p.face == face && p.position[axis] >= middle) {
        p.face = far;
        p.position[axis] -= middle;
      }
  };
  for (const int face : faces) {
    const int right = mesh.numFaces();
    half(face, 0);
    half(face, 1);
    half(right, 1);
  }
}

double bboxDiagonal(const Eigen::MatrixXd& control) {
  return (control.colwise().maxCoeff() - control.colwise().minCoeff()).norm();
}

Eigen::Vector2d randomPointIn(const spline::TMeshFace& face, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  return {unit(rng) * face.width, unit(rng) * face.height};
}

// The refined surface is the input one at `samples` random points of the refined T-mesh: the
// largest |new - old| is below 1e-12 of the bounding box diagonal in position, and of the largest
// |old ds, dt| in the derivatives ds, dt.
void checkSameSurface(const std::string& name, const TSplineSpace& space,
                      const Eigen::MatrixXd& control, const Eigen::VectorXd& weights,
                      const TSplineRefinement& refined, int samples, std::mt19937& rng) {
  std::uniform_int_distribution<int> anyFace(0, refined.space.mesh().numFaces() - 1);
  double position = 0.0, derivative = 0.0, derivativeScale = 0.0;
  for (int s = 0; s < samples; ++s) {
    const int face = anyFace(rng);
    const Eigen::Vector2d p = randomPointIn(refined.space.mesh().faces[face], rng);
    const spline::RefinedFaceOrigin& origin = refined.faceOrigin[face];
    const auto before = space.evaluate(control, weights, origin.face, p + origin.offset);
    const auto after = refined.space.evaluate(refined.control, refined.weights, face, p);
    REQUIRE(before.denominator > 0.0);
    REQUIRE(after.denominator > 0.0);
    position = std::max(position, (after.position - before.position).norm());
    derivative =
        std::max({derivative, (after.ds - before.ds).norm(), (after.dt - before.dt).norm()});
    derivativeScale = std::max({derivativeScale, before.ds.norm(), before.dt.norm()});
  }
  position /= bboxDiagonal(control);
  derivative /= derivativeScale;
  WARN(name << ": max deviation: position " << position << ", derivatives " << derivative);
  CHECK(position < 1e-12);
  CHECK(derivative < 1e-12);
}

int indexOf(const std::vector<double>& lines, double x) {
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (std::abs(lines[i] - x) < 1e-9) return static_cast<int>(i);
  FAIL("no knot line at " << x);
  return -1;
}

// max |sum_i N_i - 1| at `samples` random points of the faces with `use` set, and the smallest
// rational denominator there.
struct UnityCheck {
  double maxDeviation = 0.0;
  int worstFace = -1;
  Eigen::Vector2d worstPoint = Eigen::Vector2d::Zero();
  double minDenominator = INFINITY;
};

UnityCheck checkUnity(const TSplineSpace& space, const std::vector<char>& use, int samples,
                      std::mt19937& rng) {
  UnityCheck check;
  std::vector<int> faces;
  for (int f = 0; f < space.mesh().numFaces(); ++f)
    if (use[f]) faces.push_back(f);
  REQUIRE(!faces.empty());
  std::uniform_int_distribution<std::size_t> anyFace(0, faces.size() - 1);
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), rng);
  const Eigen::VectorXd weights = randomWeights(space.numBasis(), rng);
  std::vector<spline::TSplineBasisValue> basis;
  for (int s = 0; s < samples; ++s) {
    const int face = faces[anyFace(rng)];
    const Eigen::Vector2d p = randomPointIn(space.mesh().faces[face], rng);
    space.basisAt(face, p, basis);
    double sum = 0.0;
    for (const auto& b : basis) sum += b.value;
    if (std::abs(sum - 1.0) > check.maxDeviation)
      check.maxDeviation = std::abs(sum - 1.0), check.worstFace = face, check.worstPoint = p;
    const auto point = space.evaluate(control, weights, face, p, 0);
    REQUIRE(point.position.allFinite());
    check.minDenominator = std::min(check.minDenominator, point.denominator);
  }
  return check;
}

// Per face of a T-mesh cut from the grid on xs x ys: whether it lies in the inner cells, those
// not touching the open boundary. On the others only three of the four B-splines per direction
// that a cubic span needs exist (the rays' padding adds knots, not functions), so the blending
// functions sum to less than one there and the rational normalization takes over.
std::vector<char> innerFaces(const TMesh& mesh, const std::vector<double>& xs,
                             const std::vector<double>& ys) {
  const std::vector<Eigen::Vector2d> positions = planarVertices(mesh);
  std::vector<char> inner(mesh.faces.size(), 0);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const spline::TMeshFace& face = mesh.faces[f];
    const Eigen::Vector2d lo = positions[face.vertices[0]];
    const Eigen::Vector2d hi = lo + Eigen::Vector2d(face.width, face.height);
    inner[f] = lo.x() > xs[1] - 1e-9 && hi.x() < xs[kCells - 1] + 1e-9 && lo.y() > ys[1] - 1e-9 &&
               hi.y() < ys[kCells - 1] + 1e-9;
  }
  return inner;
}

TMesh applySplits(TMesh mesh, const std::vector<FaceSplit>& splits) {
  for (const FaceSplit& s : splits) mesh = spline::splitFace(mesh, s.face, s.axis, s.coordinate);
  return mesh;
}

}  // namespace

TEST_CASE("tspline_refine: splitFace inserts T-junctions into the neighbours", "[spline]") {
  std::mt19937 rng(11);
  const std::vector<double> xs = knotLines(rng, false), ys = knotLines(rng, false);
  const TMesh grid = spline::gridTMesh(xs, ys);
  const int f = 4 * kCells + 4;
  const double w = grid.faces[f].width, h = grid.faces[f].height;
  const TMesh once = spline::splitFace(grid, f, 0, 0.3 * w);
  REQUIRE(once.numFaces() == grid.numFaces() + 1);
  REQUIRE(once.numVertices == grid.numVertices + 2);
  CHECK(once.faces[f].width == Approx(0.3 * w).epsilon(1e-14));
  CHECK(once.faces[grid.numFaces()].width == Approx(0.7 * w).epsilon(1e-14));
  CHECK(once.faces[grid.numFaces()].height == Approx(h).epsilon(1e-14));
  // The face below has the new vertex on its top side, the face above on its bottom side.
  const int below = f - kCells, above = f + kCells;
  REQUIRE(once.faces[below].vertices.size() == 5);
  REQUIRE(once.faces[above].vertices.size() == 5);
  CHECK(once.faces[below].vertices[3] == grid.numVertices);
  CHECK((once.faces[below].positions[3] - Eigen::Vector2d(0.3 * w, ys[4] - ys[3])).norm() < 1e-14);
  CHECK(once.faces[above].vertices[1] == grid.numVertices + 1);
  CHECK((once.faces[above].positions[1] - Eigen::Vector2d(0.3 * w, 0.0)).norm() < 1e-14);
  for (int v : {grid.numVertices, grid.numVertices + 1}) {
    CHECK(once.quarterTurnsAround[v] == 4);
    CHECK(!once.isExtraordinary(v));
  }
  // Continuing the cut into the face below reuses the T-junction and adds one vertex.
  const TMesh twice = spline::splitFace(once, below, 0, 0.3 * w + 1e-12);
  CHECK(twice.numVertices == once.numVertices + 1);
  CHECK(twice.faces[below].vertices.size() == 4);
  CHECK(twice.faces[below].width == Approx(0.3 * w).epsilon(1e-14));
  // A horizontal cut of the right part: its left end is a vertex of the cut edge.
  const TMesh third = spline::splitFace(twice, grid.numFaces(), 1, 0.5 * h);
  CHECK(third.numVertices == twice.numVertices + 2);
  CHECK(third.faces[f].vertices.size() == 5);
  CHECK((third.faces[f].positions[2] - Eigen::Vector2d(0.3 * w, 0.5 * h)).norm() < 1e-14);
}

TEST_CASE("tspline_refine: partition of unity on T-meshes with split faces", "[spline]") {
  std::mt19937 rng(12);
  const std::vector<double> xs = knotLines(rng, false), ys = knotLines(rng, false);
  const TMesh grid = spline::gridTMesh(xs, ys);
  const auto at = [&](int i, int j) { return j * kCells + i; };
  const auto widthOf = [&](int i) { return xs[i + 1] - xs[i]; };
  const auto heightOf = [&](int j) { return ys[j + 1] - ys[j]; };

  // Vertical cuts in columns 3 to 5, rows 3 to 5, and a horizontal cut in face (7, 7): the
  // T-junction extensions (two faces ahead, one behind) are vertical near the first and
  // horizontal in row 7 from column 5 on, so none meet: the T-mesh is analysis-suitable, and the
  // blending functions sum to one on every inner face.
  const TMesh suitable = applySplits(grid, {{at(3, 3), 0, 0.4 * widthOf(3)},
                                            {at(4, 4), 0, 0.5 * widthOf(4)},
                                            {at(5, 4), 0, 0.3 * widthOf(5)},
                                            {at(7, 7), 1, 0.5 * heightOf(7)}});
  const TSplineSpace space(suitable);
  CHECK(space.missingAnchors().empty());
  CHECK(space.numBasis() == suitable.numVertices);
  std::vector<char> inner = innerFaces(suitable, xs, ys);
  const UnityCheck unity = checkUnity(space, inner, 4000, rng);
  WARN("analysis-suitable, inner faces: max |sum N - 1| = " << unity.maxDeviation);
  CHECK(unity.maxDeviation < 1e-12);
  CHECK(unity.minDenominator > 0.0);
  // Faces along the open boundary: less than one, and the rational surface is still defined.
  for (char& use : inner) use = !use;
  const UnityCheck boundary = checkUnity(space, inner, 4000, rng);
  WARN("faces along the boundary: max |sum N - 1| = "
       << boundary.maxDeviation << ", min denominator " << boundary.minDenominator);
  CHECK(boundary.maxDeviation > 0.1);
  CHECK(boundary.minDenominator > 0.0);

  // A vertical cut in (4, 4) next to a horizontal one in (5, 4): the horizontal cut's left
  // T-junction extends across the vertical cut, where the top T-junction's edge extension runs.
  const TMesh crossing =
      applySplits(grid, {{at(4, 4), 0, 0.5 * widthOf(4)}, {at(5, 4), 1, 0.5 * heightOf(4)}});
  const TSplineSpace crossed(crossing);
  const UnityCheck broken = checkUnity(crossed, innerFaces(crossing, xs, ys), 4000, rng);
  WARN("crossing extensions, inner faces: max |sum N - 1| = "
       << broken.maxDeviation << " on face " << broken.worstFace << " at ("
       << broken.worstPoint.transpose() << "), min denominator " << broken.minDenominator);
  CHECK(broken.minDenominator > 0.0);
}

TEST_CASE("tspline_refine: refinement leaves the surface unchanged", "[spline]") {
  // Cuts as fractions of their face: parallel cuts (the refined T-mesh stays analysis-suitable
  // and contains the old space), crossing cuts (it does not until the cuts are extended), and a
  // cut of a cut (face 100 is the right part of face 44).
  struct Case {
    const char* name;
    bool uniform;
    std::vector<FaceSplit> fractions;
    bool needsExtension;
  };
  const std::vector<Case> cases{
      {"uniform, parallel cuts", true, {{44, 0, 0.5}, {36, 0, 0.25}, {73, 1, 0.6}}, false},
      {"non-uniform, parallel cuts", false, {{44, 0, 0.5}, {36, 0, 0.25}, {73, 1, 0.6}}, false},
      {"non-uniform, crossing cuts", false, {{44, 0, 0.5}, {45, 1, 0.5}}, true},
      {"non-uniform, cuts crossing further",
       false,
       {{44, 0, 0.5}, {45, 1, 0.5}, {34, 1, 0.3}, {56, 0, 0.2}},
       true},
      {"non-uniform, a cut of a cut", false, {{44, 0, 0.5}, {100, 1, 0.5}}, false}};
  int seed = 20;
  for (const Case& c : cases) {
    std::mt19937 rng(++seed);
    const std::vector<double> xs = knotLines(rng, c.uniform), ys = knotLines(rng, c.uniform);
    TMesh mesh = spline::gridTMesh(xs, ys);
    const TSplineSpace space(mesh);
    const Eigen::MatrixXd control = randomPoints(space.numBasis(), rng);
    const Eigen::VectorXd weights = randomWeights(space.numBasis(), rng);
    std::vector<FaceSplit> splits;
    for (const FaceSplit& s : c.fractions) {
      const spline::TMeshFace& face = mesh.faces[s.face];
      splits.push_back({s.face, s.axis, s.coordinate * (s.axis == 0 ? face.width : face.height)});
      mesh = spline::splitFace(mesh, splits.back().face, s.axis, splits.back().coordinate);
    }
    const TSplineRefinement refined = spline::refine(space, control, weights, splits);
    WARN(c.name << ": residual " << refined.residual << ", extra splits " << refined.extraSplits
                << " in " << refined.extensionRounds << " rounds, " << refined.changedFunctions
                << " changed functions, " << refined.unknowns << " unknowns, " << refined.samples
                << " samples, min weight " << refined.minWeight);
    REQUIRE(refined.converged);
    CHECK(refined.residual <= 1e-12);
    CHECK((refined.extraSplits > 0) == c.needsExtension);
    CHECK(refined.space.mesh().numFaces() ==
          space.mesh().numFaces() + static_cast<int>(splits.size()) + refined.extraSplits);
    CHECK(refined.space.numBasis() == refined.space.mesh().numVertices);
    CHECK(refined.minWeight > 0.0);
    checkSameSurface(c.name, space, control, weights, refined, 10000, rng);
  }
}

TEST_CASE("tspline_refine: a full knot line is Boehm's knot insertion", "[spline]") {
  std::mt19937 rng(31);
  const std::vector<double> xs = knotLines(rng, false), ys = knotLines(rng, false);
  const TSplineSpace space(spline::gridTMesh(xs, ys));
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), rng);
  const Eigen::VectorXd weights = randomWeights(space.numBasis(), rng);
  const int column = 4;
  const double inserted = xs[column] + 0.3 * (xs[column + 1] - xs[column]);
  std::vector<FaceSplit> splits;
  for (int j = 0; j < kCells; ++j)
    splits.push_back({j * kCells + column, 0, inserted - xs[column]});
  const TSplineRefinement refined = spline::refine(space, control, weights, splits);
  REQUIRE(refined.converged);
  CHECK(refined.extraSplits == 0);
  REQUIRE(refined.space.numBasis() == space.numBasis() + kCells + 1);

  // The grid's functions are the tensor B-splines of these knots (the rays' padding repeats the
  // first and last spacings beyond the boundary).
  const double first = xs[1] - xs[0], last = xs[kCells] - xs[kCells - 1];
  std::vector<double> knots{xs[0] - 2 * first, xs[0] - first};
  knots.insert(knots.end(), xs.begin(), xs.end());
  knots.push_back(xs[kCells] + last);
  knots.push_back(xs[kCells] + 2 * last);
  const int k = column + 2;  // knots[k] <= inserted < knots[k + 1]
  REQUIRE((knots[k] <= inserted && inserted < knots[k + 1]));
  std::vector<double> refinedLines = xs;
  refinedLines.insert(refinedLines.begin() + column + 1, inserted);

  const auto homogeneous = [&](int i, int j) {
    const int a = space.anchorOfVertex()[j * (kCells + 1) + i];
    Eigen::Vector4d h;
    h << weights[a] * control.row(a).transpose(), weights[a];
    return h;
  };
  const std::vector<Eigen::Vector2d> positions = planarVertices(refined.space.mesh());
  double maxError = 0.0;
  for (int b = 0; b < refined.space.numBasis(); ++b) {
    const int vertex = refined.space.anchors()[b].vertex;
    const int i = indexOf(refinedLines, positions[vertex].x());
    const int j = indexOf(ys, positions[vertex].y());
    Eigen::Vector4d expected;
    if (i <= k - 3) {
      expected = homogeneous(i, j);
    } else if (i >= k + 1) {
      expected = homogeneous(i - 1, j);
    } else {
      const double alpha = (inserted - knots[i]) / (knots[i + 3] - knots[i]);
      expected = (1.0 - alpha) * homogeneous(i - 1, j) + alpha * homogeneous(i, j);
    }
    Eigen::Vector4d actual;
    actual << refined.weights[b] * refined.control.row(b).transpose(), refined.weights[b];
    maxError = std::max(maxError, (actual - expected).cwiseAbs().maxCoeff());
  }
  WARN("Boehm: max |homogeneous control - Boehm's| = " << maxError);
  CHECK(maxError < 1e-12);
}

TEST_CASE("tspline_refine: a cut next to the open boundary is reported", "[spline]") {
  // In the first column the cut changes the spacing that rays repeat beyond the boundary: the
  // boundary functions' padded knots move, and no extension brings the old ones back.
  std::mt19937 rng(41);
  const std::vector<double> xs = knotLines(rng, true), ys = knotLines(rng, true);
  const TSplineSpace space(spline::gridTMesh(xs, ys));
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), rng);
  spline::RefineOptions options;
  options.maxExtensionRounds = 12;
  const TSplineRefinement refined =
      spline::refine(space, control, {}, {{5 * kCells, 0, 0.5}}, options);
  WARN("boundary column: residual " << refined.residual << ", extra splits "
                                    << refined.extraSplits);
  CHECK(!refined.converged);
  CHECK(refined.residual > 1e-6);
}

TEST_CASE("tspline_refine: refinement on a periodic grid", "[spline]") {
  std::mt19937 rng(51);
  const std::vector<double> xs = knotLines(rng, false), ys = knotLines(rng, false);
  const TSplineSpace space(spline::gridTMesh(xs, ys, true, true));
  REQUIRE(space.numBasis() == kCells * kCells);
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), rng);
  const Eigen::VectorXd weights = randomWeights(space.numBasis(), rng);
  const std::vector<FaceSplit> splits{{2 * kCells + 7, 1, 0.5 * (ys[3] - ys[2])},
                                      {9 * kCells + 1, 0, 0.5 * (xs[2] - xs[1])}};
  const TSplineRefinement refined = spline::refine(space, control, weights, splits);
  WARN("periodic grid: residual " << refined.residual << ", extra splits " << refined.extraSplits
                                  << " in " << refined.extensionRounds << " rounds");
  REQUIRE(refined.converged);
  checkSameSurface("periodic", space, control, weights, refined, 10000, rng);
}

TEST_CASE("tspline_refine: a cut closes around a periodic grid", "[spline]") {
  // With a tolerance no residual meets, the cut is extended until it has no open end: once
  // around the torus, a full knot line (9 more faces), after which the grid is a tensor grid again.
  std::mt19937 rng(52);
  const std::vector<double> xs = knotLines(rng, false), ys = knotLines(rng, false);
  const TSplineSpace space(spline::gridTMesh(xs, ys, true, true));
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), rng);
  const Eigen::VectorXd weights = randomWeights(space.numBasis(), rng);
  spline::RefineOptions options;
  options.tolerance = -1.0;
  const TSplineRefinement refined = spline::refine(
      space, control, weights, {{3 * kCells + 6, 0, 0.4 * (xs[7] - xs[6])}}, options);
  WARN("closing cut: residual " << refined.residual << ", extra splits " << refined.extraSplits
                                << " in " << refined.extensionRounds << " rounds");
  CHECK(!refined.converged);
  CHECK(refined.extraSplits == kCells - 1);
  CHECK(refined.space.mesh().numFaces() == kCells * (kCells + 1));
  CHECK(refined.space.numBasis() == kCells * (kCells + 1));
  for (const spline::TMeshFace& face : refined.space.mesh().faces) CHECK(face.vertices.size() == 4);
  CHECK(refined.residual < 1e-12);
  checkSameSurface("closing cut", space, control, weights, refined, 2000, rng);
}

TEST_CASE("tspline_refine: faces with turned frames", "[spline]") {
  // The grid's faces with (i + j) even get frames turned by a quarter turn (x along the old
  // y axis): the same surface, but crossing their sides turns frames.
  std::mt19937 rng(53);
  const std::vector<double> xs = knotLines(rng, false), ys = knotLines(rng, false);
  const TMesh grid = spline::gridTMesh(xs, ys);
  std::vector<spline::TMeshFace> faces = grid.faces;
  std::vector<char> turned(faces.size(), 0);
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      if ((i + j) % 2 != 0) continue;
      spline::TMeshFace& face = faces[j * kCells + i];
      const double w = face.width;
      std::rotate(face.vertices.begin(), face.vertices.begin() + 1, face.vertices.end());
      std::rotate(face.positions.begin(), face.positions.begin() + 1, face.positions.end());
      for (Eigen::Vector2d& p : face.positions) p = Eigen::Vector2d(p.y(), w - p.x());
      turned[j * kCells + i] = 1;
    }
  const TSplineSpace space(spline::buildTMesh(grid.numVertices, faces));
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), rng);
  const Eigen::VectorXd weights = randomWeights(space.numBasis(), rng);
  // Faces 44 and 55 are turned: a cut along their frame's x = const runs along the grid's y.
  REQUIRE((turned[44] && turned[55] && !turned[45]));
  const auto fraction = [&](int face, int axis, double t) {
    const spline::TMeshFace& f = space.mesh().faces[face];
    return FaceSplit{face, axis, t * (axis == 0 ? f.width : f.height)};
  };
  const TSplineRefinement refined = spline::refine(
      space, control, weights,
      {fraction(44, 0, 0.5), fraction(45, 0, 0.5), fraction(55, 1, 0.3), fraction(62, 0, 0.7)});
  WARN("turned frames: residual " << refined.residual << ", extra splits " << refined.extraSplits
                                  << " in " << refined.extensionRounds << " rounds, "
                                  << refined.changedFunctions << " changed functions");
  REQUIRE(refined.converged);
  // The same cuts in the grid's frames (turned x is grid y, turned y is width - grid x) change
  // the same functions and need the same extensions.
  const TSplineSpace plain(grid);
  const auto plainFraction = [&](int face, int axis, double t) {
    const spline::TMeshFace& f = grid.faces[face];
    return FaceSplit{face, axis, t * (axis == 0 ? f.width : f.height)};
  };
  const TSplineRefinement reference =
      spline::refine(plain, control, weights,
                     {plainFraction(44, 1, 0.5), plainFraction(45, 0, 0.5),
                      plainFraction(55, 0, 0.7), plainFraction(62, 1, 0.7)});
  REQUIRE(reference.converged);
  CHECK(refined.extraSplits == reference.extraSplits);
  CHECK(refined.changedFunctions == reference.changedFunctions);
  CHECK(refined.unknowns == reference.unknowns);
  checkSameSurface("turned frames", space, control, weights, refined, 10000, rng);
}

TEST_CASE("tspline_refine: no splits keep the control points", "[spline]") {
  std::mt19937 rng(61);
  const TSplineSpace space(spline::gridTMesh(knotLines(rng, false), knotLines(rng, false)));
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), rng);
  const Eigen::VectorXd weights = randomWeights(space.numBasis(), rng);
  const TSplineRefinement refined = spline::refine(space, control, weights, {});
  CHECK(refined.converged);
  CHECK(refined.unknowns == 0);
  CHECK(refined.changedFunctions == 0);
  // w c / w: equal up to rounding.
  CHECK((refined.control - control).cwiseAbs().maxCoeff() < 1e-15);
  CHECK((refined.weights - weights).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("tspline_refine: bad input throws", "[spline]") {
  std::mt19937 rng(71);
  const TMesh grid = spline::gridTMesh(knotLines(rng, true), knotLines(rng, true));
  using structure::InputError;
  CHECK_THROWS_AS(spline::splitFace(grid, -1, 0, 0.5), InputError);
  CHECK_THROWS_AS(spline::splitFace(grid, grid.numFaces(), 0, 0.5), InputError);
  CHECK_THROWS_AS(spline::splitFace(grid, 0, 2, 0.5), InputError);
  CHECK_THROWS_AS(spline::splitFace(grid, 0, -1, 0.5), InputError);
  CHECK_THROWS_AS(spline::splitFace(grid, 0, 0, 0.0), InputError);
  CHECK_THROWS_AS(spline::splitFace(grid, 0, 1, 1.0), InputError);
  CHECK_THROWS_AS(spline::splitFace(grid, 0, 0, -0.5), InputError);
  CHECK_THROWS_AS(spline::splitFace(grid, 0, 0, 1.5), InputError);
  CHECK_THROWS_AS(spline::splitFace(grid, 0, 0, std::nan("")), InputError);
  const TSplineSpace space(grid);
  const Eigen::MatrixXd control = randomPoints(space.numBasis(), rng);
  CHECK_THROWS_AS(spline::refine(space, control.topRows(3), {}, {}), InputError);
  CHECK_THROWS_AS(spline::refine(space, control, Eigen::VectorXd::Ones(3), {}), InputError);
  CHECK_THROWS_WITH(spline::refine(space, control, {}, {{44, 0, 0.5}, {44, 0, 0.7}}),
                    Catch::Contains("split 1"));
}

TEST_CASE("tspline_refine: faces split into four at once as one after another", "[spline][slow]") {
  // A layout T-mesh of a real genus-2 mesh: T-junctions, turned frames across seams, cones.
  const test::FlatMetric flat = test::seamlessFlatMetric(test::realMesh("eight.off"));
  const structure::MotorcycleLayout layout(flat.surface, flat.lengths);
  double area = 0.0;
  for (const auto& r : layout.rectangles()) area += r.width() * r.height();
  spline::LayoutTMeshOptions options;
  options.cellSize = std::sqrt(area / 200.0);
  const TMesh start = spline::layoutTMesh(layout, options).mesh;
  std::mt19937 rng(7);
  for (const double share : {0.05, 0.3, 1.0}) {
    CAPTURE(share);
    // Two rounds: the second splits quarters and faces next to T-junctions the first made.
    TMesh atOnce = start, oneByOne = start;
    std::vector<spline::FacePoint> points, pointsOneByOne;
    for (int round = 0; round < 2; ++round) {
      std::vector<int> faces;
      for (int f = 0; f < atOnce.numFaces(); ++f)
        if (std::uniform_real_distribution<double>(0.0, 1.0)(rng) < share) faces.push_back(f);
      std::shuffle(faces.begin(), faces.end(), rng);
      for (int k = 0; k < 3 * atOnce.numFaces(); ++k) {
        const int f = int(rng() % std::uint32_t(atOnce.numFaces()));
        points.push_back({f, test::randomPointIn(atOnce.faces[std::size_t(f)], rng)});
      }
      pointsOneByOne = points;
      spline::splitIntoFour(atOnce, faces, points);
      splitOneByOne(oneByOne, faces, pointsOneByOne);
      REQUIRE(atOnce.numVertices == oneByOne.numVertices);
      REQUIRE(atOnce.numFaces() == oneByOne.numFaces());
      for (int f = 0; f < atOnce.numFaces(); ++f) {
        const spline::TMeshFace& a = atOnce.faces[std::size_t(f)];
        const spline::TMeshFace& b = oneByOne.faces[std::size_t(f)];
        REQUIRE(a.vertices == b.vertices);
        CHECK(a.twinFace == b.twinFace);
        CHECK(a.twinEdge == b.twinEdge);
        for (std::size_t k = 0; k < a.positions.size(); ++k)
          CHECK((a.positions[k] - b.positions[k]).norm() <= 1e-12 * a.width);
      }
      CHECK(atOnce.quarterTurnsAround == oneByOne.quarterTurnsAround);
      for (std::size_t k = 0; k < points.size(); ++k) {
        CHECK(points[k].face == pointsOneByOne[k].face);
        CHECK((points[k].position - pointsOneByOne[k].position).norm() <= 1e-12);
      }
      oneByOne = atOnce;
    }
  }
  TMesh mesh = start;
  std::vector<spline::FacePoint> none;
  CHECK_THROWS_AS(spline::splitIntoFour(mesh, {3, 3}, none), structure::InputError);
  CHECK_THROWS_AS(spline::splitIntoFour(mesh, {start.numFaces()}, none), structure::InputError);
}
