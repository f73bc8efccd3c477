#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "mspline/spline/fitting/surface_fit.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/spline/tribspline/tri_bspline_fit_space.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_fit_space.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "support/test_meshes.h"
#include "support/test_tmeshes.h"

using namespace mspline;

namespace {

// A torus of radii 3 and 1 over a periodic n x m grid of unit cells (the T-spline's parameters).
Eigen::Vector3d torusPoint(double s, double t, int n, int m) {
  const double a = 2.0 * kPi * s / n, b = 2.0 * kPi * t / m;
  return {(3.0 + std::cos(b)) * std::cos(a), (3.0 + std::cos(b)) * std::sin(a), std::sin(b)};
}

struct TorusCase {
  spline::TSplineSpace space;
  Eigen::VectorXd weights;
  std::vector<spline::FacePoint> parameters;
  Eigen::MatrixX3d targets;
};

// Samples of the torus at random grid points; `jitter` moves their parameters off the points'.
TorusCase torusCase(int n, int m, int perCell, double jitter, unsigned seed) {
  TorusCase c{
      spline::TSplineSpace(spline::gridTMesh(test::unitKnots(n), test::unitKnots(m), true, true)),
      Eigen::VectorXd(),
      {},
      Eigen::MatrixX3d()};
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), shift(-jitter, jitter);
  const int count = perCell * n * m;
  c.targets.resize(count, 3);
  for (int k = 0; k < count; ++k) {
    const int i = k % n, j = (k / n) % m;
    const Eigen::Vector2d inCell(unit(random), unit(random));
    c.targets.row(k) = torusPoint(i + inCell.x(), j + inCell.y(), n, m).transpose();
    const Eigen::Vector2d start =
        (inCell + Eigen::Vector2d(shift(random), shift(random))).cwiseMax(0.0).cwiseMin(1.0);
    c.parameters.push_back({j * n + i, start});
  }
  return c;
}

}  // namespace

TEST_CASE("surface_fit: a spline of the space is reproduced from its samples", "[spline]") {
  const spline::TSplineSpace space(
      spline::gridTMesh(test::unitKnots(8), test::unitKnots(6), true, false));
  const Eigen::VectorXd weights;
  const spline::TSplineFitSpace fitSpace(space, weights);
  const Eigen::MatrixXd control = test::randomPoints(space.numBasis(), 3u);
  std::mt19937 random(2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::FacePoint> parameters;
  Eigen::MatrixX3d targets(10 * space.numBasis(), 3);
  for (Eigen::Index k = 0; k < targets.rows(); ++k) {
    const int f = int(random() % std::size_t(space.mesh().numFaces()));
    parameters.push_back({f, Eigen::Vector2d(unit(random), unit(random))});
    targets.row(k) = spline::evaluateFitSurface(fitSpace, control, parameters.back()).transpose();
  }
  spline::SurfaceFitOptions options;
  options.smoothing = 0.0;
  options.correctionRounds = 1;
  const spline::SurfaceFitResult fit = spline::fitSurface(fitSpace, parameters, targets, options);
  // Up to the light pull towards the quasi-interpolant (1e-7 of the data term).
  CHECK((fit.controlPoints - control).cwiseAbs().maxCoeff() < 1e-4);
  CHECK(fit.maxError < 1e-5);
  CHECK(fit.rounds == 1);
}

TEST_CASE("surface_fit: the thin-plate energy is symmetric, zero on constants, exact", "[spline]") {
  const spline::TSplineSpace space(
      spline::gridTMesh(test::unitKnots(9), test::unitKnots(9), true, true));
  const Eigen::VectorXd weights;
  const spline::TSplineFitSpace fitSpace(space, weights);
  const Eigen::SparseMatrix<double> energy = spline::thinPlateEnergy(fitSpace);
  REQUIRE(energy.rows() == space.numBasis());
  // Symmetric, positive semidefinite, constants in its kernel.
  const Eigen::MatrixXd dense = Eigen::MatrixXd(energy);
  CHECK((dense - dense.transpose()).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((dense * Eigen::VectorXd::Ones(dense.cols())).cwiseAbs().maxCoeff() < 1e-10);
  // x^T K x equals the energy of the function sum x_k N_k by an independent rule (6 x 6 Gauss
  // points per face, values from evaluate's second derivatives).
  const Eigen::MatrixXd control = test::randomPoints(space.numBasis(), 5u).leftCols(1);
  const double quadratic = (control.transpose() * dense * control)(0, 0);
  const std::array<double, 6> x{0.0337652428984240, 0.1693953067668677, 0.3806904069584015,
                                0.6193095930415985, 0.8306046932331323, 0.9662347571015760};
  const std::array<double, 6> w{0.0856622461895852, 0.1803807865240693, 0.2339569672863455,
                                0.2339569672863455, 0.1803807865240693, 0.0856622461895852};
  double integral = 0.0;
  for (int f = 0; f < space.mesh().numFaces(); ++f)
    for (std::size_t i = 0; i < 6; ++i)
      for (std::size_t j = 0; j < 6; ++j) {
        const spline::TSplinePoint p =
            space.evaluate(control, {}, f, Eigen::Vector2d(x[i], x[j]), 2);
        integral +=
            w[i] * w[j] * (p.dss[0] * p.dss[0] + 2.0 * p.dst[0] * p.dst[0] + p.dtt[0] * p.dtt[0]);
      }
  CHECK(quadratic == Approx(integral).epsilon(1e-10));
}

TEST_CASE("surface_fit: projection finds the closest point, across faces", "[spline]") {
  TorusCase c = torusCase(12, 8, 4, 0.0, 3);
  const spline::TSplineFitSpace fitSpace(c.space, c.weights);
  spline::SurfaceFitOptions options;
  options.correctionRounds = 0;
  const spline::SurfaceFitResult fit =
      spline::fitSurface(fitSpace, c.parameters, c.targets, options);
  // Points just off the surface, projected from parameters a cell and a half away.
  std::mt19937 random(4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int crossed = 0;
  for (int k = 0; k < 200; ++k) {
    const spline::FacePoint on{int(random() % 96u), Eigen::Vector2d(unit(random), unit(random))};
    std::vector<spline::FitBasisTerm> terms;
    fitSpace.basisAt(on, terms, 1);
    Eigen::Vector3d point = Eigen::Vector3d::Zero(), ds = point, dt = point;
    for (const auto& term : terms) {
      point += term.value * fit.controlPoints.row(term.index).transpose();
      ds += term.ds * fit.controlPoints.row(term.index).transpose();
      dt += term.dt * fit.controlPoints.row(term.index).transpose();
    }
    const Eigen::Vector3d normal = ds.cross(dt).normalized();
    const Eigen::Vector3d target = point + 0.05 * normal;
    const spline::FacePoint start = fitSpace.walk(on, Eigen::Vector2d(1.5, -1.0));
    crossed += start.face != on.face;
    const spline::SurfaceProjection projection =
        spline::projectOntoSurface(fitSpace, fit.controlPoints, start, target, 30);
    CHECK(projection.distance == Approx(0.05).epsilon(1e-6));
    CHECK((spline::evaluateFitSurface(fitSpace, fit.controlPoints, projection.parameter) - point)
              .norm() < 1e-6);
  }
  CHECK(crossed == 200);
}

TEST_CASE("surface_fit: parameter correction lowers the error of jittered parameters", "[spline]") {
  TorusCase c = torusCase(16, 10, 6, 0.3, 5);
  const spline::TSplineFitSpace fitSpace(c.space, c.weights);
  spline::SurfaceFitOptions options;
  options.correctionRounds = 4;
  const spline::SurfaceFitResult fit =
      spline::fitSurface(fitSpace, c.parameters, c.targets, options);
  INFO("rms before " << fit.initialRmsError << " after " << fit.rmsError << " smoothing "
                     << fit.smoothing);
  CHECK(fit.rounds == 4);
  CHECK(fit.rmsError < 0.05 * fit.initialRmsError);
  CHECK(fit.smoothing > 0.0);
  CHECK(fit.samplesOutside == 0);
}

TEST_CASE("surface_fit: mismatched samples are input errors", "[spline]") {
  TorusCase c = torusCase(6, 6, 1, 0.0, 6);
  const spline::TSplineFitSpace fitSpace(c.space, c.weights);
  c.parameters.pop_back();
  CHECK_THROWS_AS(spline::fitSurface(fitSpace, c.parameters, c.targets), structure::InputError);
}

TEST_CASE("surface_fit: one solve at the samples' parameters recovers a triangular B-spline",
          "[spline]") {
  // As `spline` fits a model to its mesh: no fairing, no correction, errors at the parameters.
  const auto domain = test::flatTorusDomain(5, 0.1);
  const spline::TriBSplineSpace space(
      domain, spline::placeKnotClouds(domain, spline::buildHomeCharts(domain), 3));
  const spline::TriBSplineFitSpace fitSpace(space);
  std::mt19937 random(4);
  std::uniform_int_distribution<int> face(0, domain.faceCount() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::MatrixXd truth = test::randomPoints(space.numBasis(), 7u);
  std::vector<spline::FacePoint> parameters;
  Eigen::MatrixX3d targets(4000, 3);
  for (Eigen::Index s = 0; s < targets.rows(); ++s) {
    Eigen::Vector3d b(unit(random), unit(random), unit(random));
    parameters.push_back(spline::toFitParameter(space, {face(random), b / b.sum()}));
    targets.row(s) = spline::evaluateFitSurface(fitSpace, truth, parameters.back()).transpose();
  }
  spline::SurfaceFitOptions options;
  options.smoothing = 0.0;
  options.correctionRounds = 0;
  options.projectionSteps = 0;
  const spline::SurfaceFitResult fit = spline::fitSurface(fitSpace, parameters, targets, options);
  CHECK(fit.basisWithoutSamples == 0);
  CHECK(fit.samplesOutside == 0);
  CHECK(fit.rounds == 0);
  // The parameters stay, and the error is measured there.
  for (std::size_t k = 0; k < parameters.size(); k += 97) {
    CHECK(fit.parameters[k].face == parameters[k].face);
    CHECK(fit.parameters[k].position == parameters[k].position);
  }
  CHECK(fit.maxError < 1e-5);
  CHECK(fit.rmsError == Approx(fit.initialRmsError));
  CHECK((fit.controlPoints - truth).cwiseAbs().maxCoeff() < 1e-3);
}

TEST_CASE("surface_fit: functions without samples take the samples' mean", "[spline]") {
  // Samples only in the first two columns of cells of a 6 x 6 grid: the functions of the last
  // columns see none, and without fairing only the pull towards the quasi-interpolant holds them.
  const spline::TSplineSpace space(spline::gridTMesh(test::unitKnots(6), test::unitKnots(6)));
  const Eigen::VectorXd weights;
  const spline::TSplineFitSpace fitSpace(space, weights);
  std::mt19937 random(8);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::FacePoint> parameters;
  Eigen::MatrixX3d targets(300, 3);
  for (Eigen::Index k = 0; k < targets.rows(); ++k) {
    const int f = int(random() % 6u) * 6 + int(random() % 2u);
    parameters.push_back({f, Eigen::Vector2d(unit(random), unit(random))});
    targets.row(k) << 2.0 + unit(random), unit(random), -1.0;
  }
  spline::SurfaceFitOptions options;
  options.smoothing = 0.0;
  options.correctionRounds = 0;
  const spline::SurfaceFitResult fit = spline::fitSurface(fitSpace, parameters, targets, options);
  REQUIRE(fit.basisWithoutSamples > 0);
  std::vector<char> sampled(std::size_t(space.numBasis()), 0);
  std::vector<spline::FitBasisTerm> terms;
  for (const auto& p : parameters) {
    fitSpace.basisAt(p, terms, 0);
    for (const auto& term : terms) sampled[std::size_t(term.index)] |= term.value > 0.0;
  }
  int without = 0;
  const Eigen::RowVector3d mean = targets.colwise().mean();
  for (Eigen::Index k = 0; k < space.numBasis(); ++k) {
    if (sampled[std::size_t(k)]) continue;
    ++without;
    CHECK((fit.controlPoints.row(k) - mean).norm() < 1e-9);
  }
  CHECK(without == fit.basisWithoutSamples);
}

TEST_CASE("surface_fit: a few functions with a huge energy do not weaken the fairing elsewhere",
          "[spline]") {
  // One face's share of the energy a million times larger (as next to a cone's hole, where the
  // normalization's second derivatives blow up): lambda, relative to typical functions, stays.
  TorusCase c = torusCase(9, 9, 4, 0.0, 9);
  const spline::TSplineFitSpace fitSpace(c.space, c.weights);
  spline::SurfaceFitOptions options;
  options.smoothing = 1e-2;
  options.correctionRounds = 0;
  const spline::SurfaceFitResult plain =
      spline::fitSurface(fitSpace, c.parameters, c.targets, options);
  options.faceFairing = Eigen::VectorXd::Ones(c.space.mesh().numFaces());
  options.faceFairing[40] = 1e6;
  const spline::SurfaceFitResult stiff =
      spline::fitSurface(fitSpace, c.parameters, c.targets, options);
  CHECK(stiff.lambda == Approx(plain.lambda).epsilon(1e-12));
  // The stiff face's energy is that of the plain one times the factor.
  const Eigen::SparseMatrix<double> energy = spline::thinPlateEnergy(fitSpace);
  const Eigen::SparseMatrix<double> stiffEnergy =
      spline::thinPlateEnergy(fitSpace, options.faceFairing);
  CHECK(stiffEnergy.diagonal().sum() > 1e4 * energy.diagonal().sum());
  options.faceFairing.resize(3);
  CHECK_THROWS_AS(spline::fitSurface(fitSpace, c.parameters, c.targets, options),
                  structure::InputError);
}

TEST_CASE("surface_fit: the fairing quadrature covers every face, cones' faces included",
          "[spline]") {
  // A cube's T-mesh: its corners are extraordinary, each with a cap (8 cells a side keep them 5
  // cells apart), and the fairing must reach every face there too (where the surface would
  // otherwise fold freely).
  const test::CubeTMesh cube = test::cubeTMesh(8);
  const spline::TSplineSpace space(cube.mesh);
  const Eigen::VectorXd weights;
  const spline::TSplineFitSpace fitSpace(space, weights);
  std::vector<spline::FacePoint> nodes;
  std::vector<double> nodeWeights;
  fitSpace.quadrature(nodes, nodeWeights);
  std::vector<double> area(cube.mesh.faces.size(), 0.0);
  std::vector<int> defined(cube.mesh.faces.size(), 0);
  std::vector<spline::FitBasisTerm> terms;
  for (std::size_t q = 0; q < nodes.size(); ++q) {
    area[std::size_t(nodes[q].face)] += nodeWeights[q];
    fitSpace.basisAt(nodes[q], terms, 2);
    double energy = 0.0;
    for (const auto& term : terms)
      energy += term.dss * term.dss + 2.0 * term.dst * term.dst + term.dtt * term.dtt;
    defined[std::size_t(nodes[q].face)] += !terms.empty() && energy > 0.0;
  }
  for (std::size_t f = 0; f < area.size(); ++f) {
    const auto& face = cube.mesh.faces[f];
    CHECK(area[f] == Approx(face.width * face.height).epsilon(1e-12));
    CHECK(defined[f] == 16);
  }
}

TEST_CASE("surface_fit: a region with few samples gets no spike", "[spline]") {
  // A torus sampled with 6 points per cell but one in a block of 5 x 5 cells: with the automatic
  // fairing weight the surface spans the block close to the torus instead of swinging away
  // between the few samples there.
  TorusCase c = torusCase(16, 10, 6, 0.0, 11);
  std::vector<spline::FacePoint> parameters;
  std::vector<Eigen::Index> kept;
  const auto inBlock = [](int face) {
    const int i = face % 16, j = face / 16;
    return i >= 5 && i < 10 && j >= 2 && j < 7;
  };
  for (std::size_t k = 0; k < c.parameters.size(); ++k)
    if (!inBlock(c.parameters[k].face) || k < 16 * 10) {
      parameters.push_back(c.parameters[k]);
      kept.push_back(Eigen::Index(k));
    }
  const Eigen::MatrixX3d targets = c.targets(kept, Eigen::all);
  const spline::TSplineFitSpace fitSpace(c.space, c.weights);
  const spline::SurfaceFitResult fit = spline::fitSurface(fitSpace, parameters, targets);
  double worst = 0.0;
  for (int j = 2; j < 7; ++j)
    for (int i = 5; i < 10; ++i)
      for (double x : {0.1, 0.5, 0.9})
        for (double y : {0.1, 0.5, 0.9}) {
          const Eigen::Vector3d point = spline::evaluateFitSurface(
              fitSpace, fit.controlPoints, {j * 16 + i, Eigen::Vector2d(x, y)});
          // Distance to the torus of radii 3 and 1.
          const double ring = std::hypot(point.x(), point.y()) - 3.0;
          worst = std::max(worst, std::abs(std::hypot(ring, point.z()) - 1.0));
        }
  INFO("samples' max error " << fit.maxError << ", surface over the block " << worst);
  CHECK(worst < 0.02);
}
