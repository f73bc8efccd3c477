#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/ricci/circle_packing_energy.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::CirclePackingMetric;
using structure::Cone;
using structure::TriMesh;

namespace {

enum class Scheme { Thurston, Inversive };

const char* schemeName(Scheme scheme) {
  return scheme == Scheme::Thurston ? "Thurston" : "inversive distance";
}

CirclePackingMetric makeMetric(const TriMesh& mesh, Scheme scheme) {
  return scheme == Scheme::Thurston ? structure::thurstonPackingMetric(mesh)
                                    : structure::inversiveDistanceMetric(mesh);
}

// Random scale factors in [-amplitude, amplitude].
Eigen::VectorXd randomU(const TriMesh& mesh, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-amplitude, amplitude);
  Eigen::VectorXd u(static_cast<Eigen::Index>(mesh.n_vertices()));
  for (Eigen::Index i = 0; i < u.size(); ++i) u[i] = uniform(rng);
  return u;
}

// Random vertices to differentiate along (all of them on small meshes).
std::vector<int> sampleVertices(const TriMesh& mesh, int count, unsigned seed) {
  std::vector<int> vertices;
  const int n = static_cast<int>(mesh.n_vertices());
  if (n <= count) {
    for (int v = 0; v < n; ++v) vertices.push_back(v);
    return vertices;
  }
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int i = 0; i < count; ++i) vertices.push_back(pick(rng));
  return vertices;
}

double maxRelativeLengthError(const TriMesh& mesh, const CirclePackingMetric& metric) {
  const Eigen::VectorXd input = structure::edgeLengths(mesh);
  const Eigen::VectorXd packed = structure::circlePackingEdgeLengths(
      mesh, metric, Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices())));
  return ((packed - input).cwiseAbs().cwiseQuotient(input)).maxCoeff();
}

// Columns of the Hessian against central differences of the gradient.
void checkHessianByFiniteDifferences(const std::string& name, const TriMesh& mesh, Scheme scheme,
                                     unsigned seed) {
  const CirclePackingMetric metric = makeMetric(mesh, scheme);
  const Eigen::VectorXd u = randomU(mesh, 0.3, seed);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(u.size());
  REQUIRE(structure::degenerateFaces(mesh, structure::circlePackingEdgeLengths(mesh, metric, u))
              .empty());
  const Eigen::SparseMatrix<double> hessian = structure::circlePackingHessian(mesh, metric, u);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(hessian);
  const double scale = dense.cwiseAbs().maxCoeff();
  REQUIRE(scale > 0.0);
  const double h = 1e-5;
  double worst = 0.0;
  for (int j : sampleVertices(mesh, 40, seed + 1)) {
    Eigen::VectorXd plus = u, minus = u;
    plus[j] += h;
    minus[j] -= h;
    const Eigen::VectorXd difference =
        (structure::circlePackingGradient(mesh, metric, plus, zero) -
         structure::circlePackingGradient(mesh, metric, minus, zero)) /
        (2.0 * h);
    worst = std::max(worst, (difference - dense.col(j)).cwiseAbs().maxCoeff() / scale);
  }
  WARN(name << ", " << schemeName(scheme) << ": Hessian vs finite differences, max relative error "
            << worst);
  CHECK(worst <= 1e-6);
  CHECK((dense - dense.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * scale);
  CHECK(dense.rowwise().sum().cwiseAbs().maxCoeff() <= 1e-12 * scale);
}

struct NewtonRun {
  Eigen::VectorXd u;
  int iterations = 0;
  double maxCurvatureError = 0.0;
};

// The project's Newton solver on a circle-packing scheme, vertex 0 pinned for the gauge (closed
// meshes, nothing fixed). Requires convergence to max |K - K_target| <= 1e-10.
NewtonRun newtonSolve(const std::string& name, const TriMesh& mesh,
                      const CirclePackingMetric& metric, const Eigen::VectorXd& target) {
  const auto start = std::chrono::steady_clock::now();
  structure::CurvatureTarget curvatureTarget;
  curvatureTarget.curvature = target;
  curvatureTarget.fixed.assign(mesh.n_vertices(), 0);
  structure::RicciNewtonOptions options;
  options.tolerance = 1e-10 / (2.0 * kPi);  // the solver's tolerance is relative to 2 pi
  const structure::RicciResult result = structure::solveRicciFlow(
      mesh, structure::circlePackingScheme(mesh, metric, name), curvatureTarget, options);
  INFO(result.message);
  REQUIRE(result.converged);
  NewtonRun run;
  run.u = result.u;
  run.iterations = result.iterations;
  run.maxCurvatureError = result.maxCurvatureError;
  const double initialError = result.log.front().maxCurvatureError;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WARN(name << ": " << run.iterations << " Newton steps, curvature error " << initialError << " -> "
            << run.maxCurvatureError << ", " << seconds << " s");
  REQUIRE(run.maxCurvatureError <= 1e-10);
  // Independent check of the curvatures from the final lengths.
  const Eigen::VectorXd lengths = structure::circlePackingEdgeLengths(mesh, metric, run.u);
  CHECK(structure::degenerateFaces(mesh, lengths).empty());
  CHECK((structure::vertexCurvatures(mesh, lengths) - target).cwiseAbs().maxCoeff() <= 1e-9);
  return run;
}

}  // namespace

TEST_CASE("circle_packing_energy: initial metrics from the input", "[structure]") {
  for (const auto& [name, mesh] :
       {std::pair<std::string, TriMesh>{"knot1.off", test::realMesh("knot1.off")},
        {"torus", test::torus(32, 16)},
        {"icosphere(2)", test::icosphere(2)},
        {"pair of pants", test::pairOfPants(8)}}) {
    const Eigen::VectorXd input = structure::edgeLengths(mesh);
    const Eigen::VectorXd zero =
        Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));

    // Inversive distance reproduces the input at u = 0.
    const CirclePackingMetric inversive = structure::inversiveDistanceMetric(mesh);
    CHECK((inversive.radius.array() > 0.0).all());
    CHECK((inversive.eta.array() >= -1.0).all());
    CHECK(maxRelativeLengthError(mesh, inversive) <= 1e-14);

    // Thurston: the same radii, eta clamped to [0, 1]; exact wherever no clamping happened, and
    // too long (eta = 0) or too short (eta = 1) where it did.
    const CirclePackingMetric thurston = structure::thurstonPackingMetric(mesh);
    CHECK(thurston.radius == inversive.radius);
    CHECK((thurston.eta.array() >= 0.0).all());
    CHECK((thurston.eta.array() <= 1.0).all());
    const Eigen::VectorXd packed = structure::circlePackingEdgeLengths(mesh, thurston, zero);
    int clamped = 0;
    for (Eigen::Index e = 0; e < input.size(); ++e) {
      const double relative = (packed[e] - input[e]) / input[e];
      if (inversive.eta[e] < 0.0) {
        CHECK(relative > 0.0);
        ++clamped;
      } else if (inversive.eta[e] > 1.0) {
        CHECK(relative < 0.0);
        ++clamped;
      } else {
        CHECK(std::abs(relative) <= 1e-14);
      }
    }
    const auto [minEta, maxEta] = std::pair(inversive.eta.minCoeff(), inversive.eta.maxCoeff());
    WARN(name << ": inversive distances in [" << minEta << ", " << maxEta
              << "]; Thurston initial metric: " << clamped << " of " << input.size()
              << " edges clamped, max relative edge-length error "
              << maxRelativeLengthError(mesh, thurston));
  }
}

TEST_CASE("circle_packing_energy: Hessian matches finite differences of the gradient",
          "[structure]") {
  const TriMesh knot = test::realMesh("knot1.off");
  const TriMesh pants = test::pairOfPants(8);
  for (Scheme scheme : {Scheme::Thurston, Scheme::Inversive}) {
    checkHessianByFiniteDifferences("knot1.off", knot, scheme, 11);
    checkHessianByFiniteDifferences("pair of pants", pants, scheme, 12);
  }
}

TEST_CASE("circle_packing_energy: Thurston's Hessian is positive semidefinite", "[structure]") {
  const TriMesh mesh = test::icosphere(1);
  const CirclePackingMetric metric = structure::thurstonPackingMetric(mesh);
  for (unsigned seed : {1u, 2u, 3u}) {
    // Large u: the semidefiniteness is global for intersection angles in [0, pi/2].
    const Eigen::VectorXd u = randomU(mesh, 2.0, seed);
    const Eigen::MatrixXd dense = Eigen::MatrixXd(structure::circlePackingHessian(mesh, metric, u));
    const double scale = dense.cwiseAbs().maxCoeff();
    CHECK(dense.rowwise().sum().cwiseAbs().maxCoeff() <= 1e-12 * scale);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (dense + dense.transpose()));
    REQUIRE(eigen.info() == Eigen::Success);
    CHECK(eigen.eigenvalues()[0] >= -1e-10);
    // The kernel is the constants only (the mesh is connected).
    CHECK(eigen.eigenvalues()[1] > 1e-8 * scale);
  }
}

TEST_CASE("circle_packing_energy: the energy's gradient is K - K_target", "[structure]") {
  const TriMesh knot = test::realMesh("knot1.off");
  const TriMesh sphere = test::icosphere(2);
  for (Scheme scheme : {Scheme::Thurston, Scheme::Inversive}) {
    for (const TriMesh* mesh : {&knot, &sphere}) {
      const CirclePackingMetric metric = makeMetric(*mesh, scheme);
      const Eigen::VectorXd u = randomU(*mesh, 0.3, 21);
      Eigen::VectorXd target = randomU(*mesh, 0.1, 22);
      CHECK(structure::circlePackingEnergy(*mesh, metric, 0.0 * u, target) == 0.0);
      const Eigen::VectorXd gradient = structure::circlePackingGradient(*mesh, metric, u, target);
      const double h = 1e-4;
      double worst = 0.0;
      for (int j : sampleVertices(*mesh, 10, 23)) {
        Eigen::VectorXd plus = u, minus = u;
        plus[j] += h;
        minus[j] -= h;
        const double difference = (structure::circlePackingEnergy(*mesh, metric, plus, target) -
                                   structure::circlePackingEnergy(*mesh, metric, minus, target)) /
                                  (2.0 * h);
        worst = std::max(worst,
                         std::abs(difference - gradient[j]) / std::max(1.0, std::abs(gradient[j])));
      }
      WARN(schemeName(scheme) << ", " << mesh->n_vertices()
                              << " vertices: energy gradient vs finite differences, max error "
                              << worst);
      CHECK(worst <= 1e-6);
    }
  }
}

TEST_CASE("circle_packing_energy: Newton reaches flat tori and cone metrics", "[structure]") {
  const TriMesh torus = test::torus(32, 16);
  const TriMesh sphere = test::icosphere(2);
  const Eigen::VectorXd torusTarget = structure::flatTarget(torus, {}).curvature;
  const Eigen::VectorXd sphereTarget =
      structure::flatTarget(sphere, test::cubeCornerCones(sphere)).curvature;
  for (Scheme scheme : {Scheme::Thurston, Scheme::Inversive}) {
    const std::string name = schemeName(scheme);
    const NewtonRun flat =
        newtonSolve(name + ", flat torus", torus, makeMetric(torus, scheme), torusTarget);
    CHECK(flat.iterations <= 20);
    const NewtonRun cones = newtonSolve(name + ", icosphere(2) with 8 cones", sphere,
                                        makeMetric(sphere, scheme), sphereTarget);
    CHECK(cones.iterations <= 20);
  }
}

TEST_CASE("circle_packing_energy: Newton flattens knot1.off without cones", "[structure]") {
  const TriMesh mesh = test::realMesh("knot1.off");
  const Eigen::VectorXd target = structure::flatTarget(mesh, {}).curvature;
  for (Scheme scheme : {Scheme::Thurston, Scheme::Inversive}) {
    const NewtonRun run = newtonSolve(std::string(schemeName(scheme)) + ", knot1.off", mesh,
                                      makeMetric(mesh, scheme), target);
    CHECK(run.iterations <= 20);
  }
}
