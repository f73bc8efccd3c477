#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_adaptive_fit.h"
#include "mspline/spline/tspline/tspline_cap.h"
#include "mspline/spline/tspline/tspline_fit_space.h"
#include "mspline/structure/core/constants.h"
#include "support/test_tmeshes.h"

using namespace mspline;

TEST_CASE("tspline_adaptive_fit: refines where a bump is and reaches the tolerance", "[spline]") {
  // A periodic 12 x 12 grid over the flat torus [0,12)^2 as a height field with a narrow bump
  // at (6, 6) that the coarse cells cannot follow.
  const int n = 12;
  const spline::TMesh mesh = spline::gridTMesh(test::unitKnots(n), test::unitKnots(n), true, true);
  const auto height = [](double x, double y) {
    const double r2 = (x - 6.0) * (x - 6.0) + (y - 6.0) * (y - 6.0);
    return 0.8 * std::exp(-r2 / 0.15);
  };
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::FacePoint> parameters;
  Eigen::MatrixX3d targets(40 * n * n, 3);
  for (Eigen::Index k = 0; k < targets.rows(); ++k) {
    const double x = n * unit(random), y = n * unit(random);
    const int i = std::min(n - 1, int(x)), j = std::min(n - 1, int(y));
    parameters.push_back({j * n + i, Eigen::Vector2d(x - i, y - j)});
    // Periodic in x and y: a torus-like embedding keeps the surface closed.
    const double a = 2.0 * kPi * x / n, b = 2.0 * kPi * y / n;
    const double lift = height(x, y);
    targets.row(k) << (4.0 + std::cos(b)) * std::cos(a), (4.0 + std::cos(b)) * std::sin(a),
        std::sin(b) + lift;
  }
  spline::TSplineAdaptiveFitOptions options;
  options.tolerance = 4e-3;
  options.maxControlPoints = 600;
  options.maxRefinements = 5;
  const spline::TSplineAdaptiveFitResult result =
      spline::fitTSplineAdaptively(mesh, parameters, targets, options);
  REQUIRE(result.rounds.size() >= 2);
  INFO("first rms " << result.rounds.front().rmsError << " max " << result.rounds.front().maxError
                    << ", last rms " << result.rounds.back().rmsError << " max "
                    << result.rounds.back().maxError << " with "
                    << result.rounds.back().controlPoints << " control points");
  CHECK(result.rounds.front().maxError > options.maxErrorFactor * options.tolerance);
  CHECK(result.rounds.back().maxError < 0.5 * result.rounds.front().maxError);
  CHECK(result.reachedTolerance);
  CHECK(result.rounds.back().controlPoints <= options.maxControlPoints);
  // Refinement is local: new faces only near the bump (cells within three of (6, 6)).
  CHECK(result.mesh.numTJunctions() > 0);
  CHECK(result.mesh.numFaces() < 2 * n * n);
  // The parameters stay on the refined mesh's faces.
  for (const auto& p : result.parameters) {
    REQUIRE(p.face >= 0);
    REQUIRE(p.face < result.mesh.numFaces());
    const auto& face = result.mesh.faces[std::size_t(p.face)];
    CHECK(p.position.x() >= -1e-12);
    CHECK(p.position.x() <= face.width + 1e-12);
  }
}

namespace {

// Samples of the torus of radii 4 and 1 over a periodic n x n grid of unit cells.
struct TorusSamples {
  spline::TMesh mesh;
  std::vector<spline::FacePoint> parameters;
  Eigen::MatrixX3d targets;
};

Eigen::Vector3d torusAt(double x, double y, int n) {
  const double a = 2.0 * kPi * x / n, b = 2.0 * kPi * y / n;
  return {(4.0 + std::cos(b)) * std::cos(a), (4.0 + std::cos(b)) * std::sin(a), std::sin(b)};
}

TorusSamples torusSamples(int n, int perCell) {
  TorusSamples t{spline::gridTMesh(test::unitKnots(n), test::unitKnots(n), true, true), {}, {}};
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  t.targets.resize(perCell * n * n, 3);
  for (Eigen::Index k = 0; k < t.targets.rows(); ++k) {
    const int face = int(k % (n * n));
    const Eigen::Vector2d inCell(unit(random), unit(random));
    t.parameters.push_back({face, inCell});
    t.targets.row(k) = torusAt(face % n + inCell.x(), face / n + inCell.y(), n).transpose();
  }
  return t;
}

}  // namespace

TEST_CASE("tspline_adaptive_fit: refines where only the surface strays from the scan", "[spline]") {
  // The samples are all on the torus, and the first fit reaches the tolerance on them; the
  // measurement sees more: the "scan" has a dent at the middle of face (6, 6) that no sample
  // holds. That face is refined and the dent's point fitted.
  const int n = 12;
  const TorusSamples t = torusSamples(n, 12);
  const int face = 6 * n + 6;
  const Eigen::Vector3d dent =
      torusAt(6.5, 6.5, n) + 0.1 * Eigen::Vector3d(torusAt(6.5, 6.5, n)).normalized();
  spline::TSplineAdaptiveFitOptions options;
  options.tolerance = 4e-3;
  options.maxControlPoints = 400;
  options.maxRefinements = 3;
  std::vector<double> strayDistances;
  options.measure = [&](const spline::TMesh& mesh, const spline::SurfaceFitResult& fit) {
    const spline::TSplineSpace space(mesh);
    const Eigen::VectorXd weights;
    const spline::TSplineFitSpace fitSpace(space, weights);
    // From the dent's sample once there is one, else from the middle of the unsplit face.
    const spline::FacePoint at = fit.parameters.size() > t.parameters.size()
                                     ? fit.parameters.back()
                                     : spline::FacePoint{face, Eigen::Vector2d(0.5, 0.5)};
    const double distance =
        spline::projectOntoSurface(fitSpace, fit.controlPoints, at, dent, 30).distance;
    strayDistances.push_back(distance);
    spline::TSplineSurfaceCheck check;
    check.accepted = distance <= options.maxErrorFactor * options.tolerance;
    if (!check.accepted) {
      check.strays.push_back(at);
      check.strayTargets = dent.transpose();
    }
    return check;
  };
  const spline::TSplineAdaptiveFitResult result =
      spline::fitTSplineAdaptively(t.mesh, t.parameters, t.targets, options);
  REQUIRE(result.rounds.size() >= 2);
  INFO("distances of the dent " << strayDistances.front() << " .. " << strayDistances.back());
  // The samples alone were within the tolerance: only the measurement refined.
  CHECK(result.rounds.front().rmsError <= options.tolerance);
  CHECK(result.rounds.front().maxError <= options.maxErrorFactor * options.tolerance);
  CHECK(result.rounds.front().splitFaces >= 1);
  CHECK(result.rounds.front().addedSamples == 1);
  CHECK(result.mesh.faces[std::size_t(face)].width < 1.0);
  CHECK(strayDistances.back() < 0.5 * strayDistances.front());
  // The result's parameters are the input samples'.
  CHECK(result.parameters.size() == t.parameters.size());
  CHECK(result.fit.parameters.size() > t.parameters.size());
}

TEST_CASE("tspline_adaptive_fit: a fold stiffens the fairing there instead of refining",
          "[spline]") {
  const int n = 12;
  const TorusSamples t = torusSamples(n, 12);
  const int folded = 3 * n + 4;
  spline::TSplineAdaptiveFitOptions options;
  options.tolerance = 4e-3;
  options.maxRefinements = 2;
  int calls = 0;
  std::vector<double> lambdas;
  options.measure = [&](const spline::TMesh&, const spline::SurfaceFitResult& fit) {
    lambdas.push_back(fit.lambda);
    spline::TSplineSurfaceCheck check;
    // A fold reported by the first measurement.
    if (calls++ == 0) {
      check.folds.push_back({folded, Eigen::Vector2d(0.5, 0.5)});
      check.accepted = false;
    }
    return check;
  };
  const spline::TSplineAdaptiveFitResult result =
      spline::fitTSplineAdaptively(t.mesh, t.parameters, t.targets, options);
  REQUIRE(result.rounds.size() == 2);
  CHECK(result.rounds.front().stiffenedFaces == 1);
  CHECK(result.rounds.front().splitFaces == 0);
  CHECK(result.mesh.numFaces() == n * n);
  CHECK(result.reachedTolerance);
  // The same smoothing weight (chosen once), relative to the same typical functions.
  CHECK(lambdas[1] == Approx(lambdas[0]).epsilon(1e-2));
}

TEST_CASE(
    "tspline_adaptive_fit: of the rounds within the tolerance, the one that folds least is "
    "returned, and when none is, of those nearly as close as the closest",
    "[spline]") {
  // Every measurement reports a stray point (each round refines a face and takes a sample). When
  // the third round's distances are out of tolerance, the second round (the fewest folds of those
  // within) is returned with its T-mesh, fit and parameters. When no round is within, the rounds
  // whose excess (measured RMS over the tolerance) is within 1.25 times the least count as equally
  // close, and the one that folds least of those is returned.
  struct Case {
    const char* name;
    std::vector<int> folds;
    std::vector<double> excess;  // per round; 0: within the tolerance
    int kept;
  };
  const int n = 12;
  const TorusSamples t = torusSamples(n, 12);
  for (const Case& c :
       {Case{"two within", {4, 1, 0}, {0.0, 0.0, 1.5}, 1},
        Case{"none within, all about as close", {4, 0, 1}, {2.0, 1.9, 1.8}, 1},
        Case{"none within, the unfolded one too far", {4, 1, 0}, {2.0, 1.5, 2.0}, 1},
        Case{"none within, the last", {4, 1, 0}, {2.0, 1.9, 1.8}, 2}}) {
    INFO(c.name);
    spline::TSplineAdaptiveFitOptions options;
    options.tolerance = 4e-3;
    options.maxRefinements = 2;
    std::vector<int> facesMeasured;
    options.measure = [&](const spline::TMesh& mesh, const spline::SurfaceFitResult&) {
      const int round = int(facesMeasured.size());
      facesMeasured.push_back(mesh.numFaces());
      spline::TSplineSurfaceCheck check;
      check.strays.push_back({(2 + 5 * round) * n + 3, Eigen::Vector2d(0.5, 0.5)});
      // 0.01 off the torus: beyond the tolerance, within the maximum wanted.
      const Eigen::Vector3d onTorus = torusAt(3.5, 2.5 + 5 * round, n);
      const Eigen::Vector3d tubeCentre =
          4.0 * Eigen::Vector3d(onTorus.x(), onTorus.y(), 0.0).normalized();
      check.strayTargets = (onTorus + 0.01 * (onTorus - tubeCentre)).transpose();
      check.foldCount = c.folds[std::size_t(round)];
      const double excess = c.excess[std::size_t(round)];
      check.distancesWithin = excess == 0.0;
      check.rms = excess * options.tolerance;
      check.accepted = false;
      return check;
    };
    const spline::TSplineAdaptiveFitResult result =
        spline::fitTSplineAdaptively(t.mesh, t.parameters, t.targets, options);
    // No faces to act on: the repair fits nothing.
    REQUIRE(result.rounds.size() == 3);
    REQUIRE(facesMeasured.size() == 3);
    CHECK(facesMeasured[0] < facesMeasured[1]);
    CHECK(facesMeasured[1] < facesMeasured[2]);
    for (std::size_t k = 0; k < 3; ++k) {
      CHECK(result.rounds[k].rmsError <= options.tolerance);
      CHECK(result.rounds[k].maxError <= options.maxErrorFactor * options.tolerance);
      CHECK(result.rounds[k].folds == c.folds[k]);
      CHECK(result.rounds[k].measuredRms == c.excess[k] * options.tolerance);
    }
    CHECK(result.keptRound == c.kept);
    CHECK_FALSE(result.reachedTolerance);
    CHECK(result.mesh.numFaces() == facesMeasured[std::size_t(c.kept)]);
    CHECK(result.fit.rmsError == result.rounds[std::size_t(c.kept)].rmsError);
    CHECK(result.fit.controlPoints.rows() == result.rounds[std::size_t(c.kept)].controlPoints);
    REQUIRE(result.parameters.size() == t.parameters.size());
    for (const auto& p : result.parameters) CHECK(p.face < result.mesh.numFaces());
  }
}

TEST_CASE(
    "tspline_adaptive_fit: a round within the tolerance that folds is repaired by the remedy "
    "that unfolds it",
    "[spline]") {
  // Every measurement that reports folds puts them on face (4, 3) as triangles facing away from
  // the scan, with nothing else to act on (no strays, no adjacent folds), so the refinement ends
  // after its first round. Two repair searches follow, one correcting the samples' parameters,
  // then one holding them; each step fits the four remedies (split the face, stiffen it, the
  // same with its 8 neighbours) from the round it keeps, and keeps the one that folds least, only
  // when it is within the tolerance (when the round repaired is out of it: its excess within 1.25
  // times the least the rounds met) and folds less. The search's end that folds less is
  // returned; a search stops at a fit without folds, and the second runs only when the first
  // still folds.
  struct Case {
    const char* name;
    std::vector<int> folds;     // per measurement: the first round, then every repair fit
    std::vector<int> repairOf;  // per repair fit
    int heldFrom;               // the first fit of the search holding the parameters
    int outOfTolerance;         // the measurement whose distances are out of tolerance (-1: none)
    double excess;              // that measurement's RMS over the tolerance
    int kept;
  };
  const std::vector<int> fromFirst(8, 0);
  const int n = 12;
  const TorusSamples t = torusSamples(n, 12);
  const int face = 3 * n + 4;
  const std::array<int, 4> remediedFaces{1, 1, 9, 9};
  const std::array<int, 4> facesAfter{n * n + 3, n * n, n * n + 27, n * n};
  for (const Case& c :
       {Case{"the split unfolds (nothing more is fitted)", {1, 0}, {0}, 2, -1, 0.0, 1},
        Case{"stiffening around, holding the parameters, unfolds",
             {1, 2, 1, 3, 1, 1, 1, 1, 0},
             fromFirst,
             5,
             -1,
             0.0,
             8},
        Case{"every remedy folds more", {1, 2, 3, 2, 2, 2, 3, 2, 2}, fromFirst, 5, -1, 0.0, 0},
        Case{"the split unfolds but strays", {1, 0, 1, 1, 1, 1, 1, 1, 1}, fromFirst, 5, 1, 1.1, 0},
        Case{"out of tolerance, the split unfolds within it", {1, 0}, {0}, 2, 0, 3.0, 1},
        Case{"two steps", {2, 3, 1, 3, 3, 2, 2, 0}, {0, 0, 0, 0, 2, 2, 2}, 8, -1, 0.0, 7}}) {
    INFO(c.name);
    spline::TSplineAdaptiveFitOptions options;
    options.tolerance = 4e-3;
    std::vector<int> facesMeasured;
    std::vector<int> correctionsMeasured;
    options.measure = [&](const spline::TMesh& mesh, const spline::SurfaceFitResult& fit) {
      const int call = int(facesMeasured.size());
      facesMeasured.push_back(mesh.numFaces());
      correctionsMeasured.push_back(fit.rounds);
      spline::TSplineSurfaceCheck check;
      check.foldCount = c.folds.at(std::size_t(call));
      if (check.foldCount > 0) check.facingAway.push_back({face, Eigen::Vector2d(0.5, 0.5)});
      check.distancesWithin = call != c.outOfTolerance;
      if (!check.distancesWithin) check.rms = c.excess * options.tolerance;
      check.accepted = check.distancesWithin && check.foldCount == 0;
      return check;
    };
    const spline::TSplineAdaptiveFitResult result =
        spline::fitTSplineAdaptively(t.mesh, t.parameters, t.targets, options);
    REQUIRE(result.rounds.size() == c.folds.size());
    CHECK(result.rounds[0].rmsError <= options.tolerance);
    CHECK(result.rounds[0].stiffenedFaces == 0);
    CHECK(result.rounds[0].splitFaces == 0);
    CHECK(result.rounds[0].repairOf == -1);
    for (std::size_t k = 1; k < result.rounds.size(); ++k) {
      const auto& round = result.rounds[k];
      const bool held = int(k) >= c.heldFrom;
      const std::size_t remedy = (k - (held ? std::size_t(c.heldFrom) : 1)) % 4;
      CHECK(round.folds == c.folds[k]);
      CHECK(round.repairOf == c.repairOf[k - 1]);
      CHECK(round.parametersHeld == held);
      CHECK(int(round.remedy) == int(remedy));
      CHECK(round.remediedFaces == remediedFaces[remedy]);
      CHECK(facesMeasured[k] == facesAfter[remedy]);
      // Held: one solve at the parameters of the round repaired, no correction.
      CHECK(correctionsMeasured[k] == (held ? 0 : options.fit.correctionRounds));
    }
    CHECK(result.keptRound == c.kept);
    CHECK(result.mesh.numFaces() == facesMeasured[std::size_t(c.kept)]);
    CHECK(result.fit.rmsError == result.rounds[std::size_t(c.kept)].rmsError);
    CHECK(result.reachedTolerance == (c.folds[std::size_t(c.kept)] == 0));
    if (c.kept == 1) CHECK(result.mesh.faces[std::size_t(face)].width == Approx(0.5));
  }
}

TEST_CASE("tspline_adaptive_fit: cap regions at extraordinary vertices are split whole",
          "[spline]") {
  // A cube's T-mesh (8 corners of valence 3) fitted to a sphere; the measurement reports a stray
  // point on every face, so every face is split and takes a stray sample, the corners' cap regions
  // included, and every corner keeps its cap (no T-junction enters a cap region).
  const int k = 8;
  const test::CubeTMesh cube = test::cubeTMesh(k);
  const auto onSphere = [&](const spline::FacePoint& p) {
    const auto& face = cube.mesh.faces[std::size_t(p.face)];
    const Eigen::Vector3d a = cube.latticePoints.row(face.vertices[0]).transpose(),
                          b = cube.latticePoints.row(face.vertices[1]).transpose(),
                          d = cube.latticePoints.row(face.vertices[3]).transpose();
    return Eigen::Vector3d((a + p.position.x() * (b - a) + p.position.y() * (d - a)).normalized());
  };
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::FacePoint> parameters;
  Eigen::MatrixX3d targets(8 * cube.mesh.numFaces(), 3);
  for (Eigen::Index s = 0; s < targets.rows(); ++s) {
    parameters.push_back(
        {int(s % cube.mesh.numFaces()), Eigen::Vector2d(unit(random), unit(random))});
    targets.row(s) = onSphere(parameters.back()).transpose();
  }
  spline::TSplineAdaptiveFitOptions options;
  options.tolerance = 1e-1;
  options.maxRefinements = 1;
  options.maxControlPoints = 100000;
  options.fit.correctionRounds = 1;
  const int inputFaces = cube.mesh.numFaces();
  options.measure = [&](const spline::TMesh& mesh, const spline::SurfaceFitResult&) {
    spline::TSplineSurfaceCheck check;
    if (mesh.numFaces() > inputFaces) return check;
    check.accepted = false;
    check.strayTargets.resize(inputFaces, 3);
    for (int f = 0; f < inputFaces; ++f) {
      check.strays.push_back({f, Eigen::Vector2d(0.5, 0.5)});
      check.strayTargets.row(f) = 2.0 * onSphere(check.strays.back()).transpose();
    }
    return check;
  };
  const spline::TSplineAdaptiveFitResult result =
      spline::fitTSplineAdaptively(cube.mesh, parameters, targets, options);
  REQUIRE(result.rounds.size() == 2);
  for (int f = 0; f < inputFaces; ++f) CHECK(result.mesh.faces[std::size_t(f)].width < 1.0);
  CHECK(result.mesh.numFaces() == 4 * inputFaces);
  CHECK(spline::capRegions(result.mesh).size() == 8);
  CHECK(result.rounds.front().addedSamples == inputFaces);
}
