// Benchmark: cubic T-spline evaluation by Bezier extraction (spline/tspline/tspline_bezier.h)
// against OpenSubdiv's Catmull-Clark limit (spline/subd/catmull_clark_limit.h, Far, double
// precision) on the same control net, by spline/subd/tspline_osd.h: (a) a periodic N x M grid of
// unit cells with control points on a torus (radii 1 and 0.4), every face regular; (b) a planar N x
// M grid with random heights, compared on its inner faces (OpenSubdiv under BoundaryRule::None has
// no surface at the boundary). 1e6 random points (sample k in face k mod F at uniform (u, v)),
// position + first derivatives, serial, best of two batches. Setup: TSplineSpace construction +
// Bezier extraction against CatmullClarkLimit construction (the T-mesh is built before either). The
// deviations check that both evaluate the same surface (relative to the control points' bounding
// box).
//
// Usage: tspline_bench [N [M]]   (cells; default 200 100, each at least 4)
//        tspline_bench MODEL.msp (c) a T-spline model of a real mesh, with extraordinary points
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mspline/io/spline_model_file.h"
#include "mspline/spline/subd/tspline_osd.h"
#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/structure/core/constants.h"

using namespace mspline;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kSamples = 1000000;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::vector<double> knotLines(int count) {
  std::vector<double> knots;
  for (int i = 0; i < count; ++i) knots.push_back(i);
  return knots;
}

void printComparison(const char* name, int vertices, int faces, double spaceSeconds,
                     const spline::OsdComparison& c) {
  const double msplineSetup = spaceSeconds + c.msplineSetupSeconds;
  std::printf("\n%s: %d vertices, %d faces (%d regular, %d irregular, %d without surface)\n", name,
              vertices, faces, c.regularFaces, c.irregularFaces, c.facesWithoutSurface);
  std::printf(
      "  %d of %d random points compared; max deviation on regular faces %.3g (position), %.3g "
      "(first derivatives); on irregular faces %.3g, %.3g\n",
      c.samples, kSamples, c.regularMaxDeviation, c.regularMaxDerivativeDeviation,
      c.irregularMaxDeviation, c.irregularMaxDerivativeDeviation);
  std::printf("  %-34s %12s %10s\n", "evaluator", "Mpoints/s", "setup s");
  std::printf("  %-34s %12.3f %10.3f  (TSplineSpace %.3f s + Bezier extraction %.3f s)\n",
              "mspline T-spline (TSplineBezier)", c.msplinePointsPerSecond / 1e6, msplineSetup,
              spaceSeconds, c.msplineSetupSeconds);
  std::printf("  %-34s %12.3f %10.3f\n", "OpenSubdiv Far (double)", c.osdPointsPerSecond / 1e6,
              c.osdSetupSeconds);
  std::printf("  mspline / OpenSubdiv: %.2fx the speed (target >= 1), %.2fx the setup time\n",
              c.msplinePointsPerSecond / c.osdPointsPerSecond, msplineSetup / c.osdSetupSeconds);
}

// Times the T-spline setup, compares and prints one case. `pointOf(i, j)` is the control point of
// grid vertex (i, j); vertex ids are gridTMesh's, j * columns + i.
template <class PointOf>
void runCase(const char* name, spline::TMesh mesh, int columns, PointOf pointOf) {
  const int vertices = mesh.numVertices, faces = mesh.numFaces();
  auto start = Clock::now();
  const spline::TSplineSpace space(std::move(mesh));
  const double spaceSeconds = since(start);
  Eigen::MatrixXd control(space.numBasis(), 3);
  for (int a = 0; a < space.numBasis(); ++a) {
    const int v = space.anchors()[a].vertex;
    control.row(a) = pointOf(v % columns, v / columns);
  }
  spline::OsdCompareOptions options;
  options.samples = kSamples;
  printComparison(name, vertices, faces, spaceSeconds,
                  spline::compareWithOpenSubdiv(space, control, {}, options));
}

// A T-spline model (mspline spline --kind tspline): its own T-mesh and control points, with
// extraordinary points at the cones.
void runModel(const std::string& path) {
  const spline::SplineModel model = io::readSplineModel(path);
  if (model.kind != spline::SplineKind::TSpline)
    throw std::runtime_error(path + " is not a T-spline model");
  auto start = Clock::now();
  const spline::TSplineSpace space(model.tmesh);
  const double spaceSeconds = since(start);
  spline::OsdCompareOptions options;
  options.samples = kSamples;
  printComparison(
      ("(c) " + path).c_str(), model.tmesh.numVertices, model.tmesh.numFaces(), spaceSeconds,
      spline::compareWithOpenSubdiv(space, model.controlPoints, model.weights, options));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]).size() > 4 &&
      std::string(argv[1]).substr(std::string(argv[1]).size() - 4) == ".msp") {
    try {
      std::printf("tspline_bench: position + first derivatives at %d random points, serial\n",
                  kSamples);
      runModel(argv[1]);
      return 0;
    } catch (const std::exception& error) {
      std::fprintf(stderr, "tspline_bench: %s\n", error.what());
      return 1;
    }
  }
  const int n = argc > 1 ? std::atoi(argv[1]) : 200;
  const int m = argc > 2 ? std::atoi(argv[2]) : (argc > 1 ? n : 100);
  if (argc > 3 || n < 4 || m < 4) {
    std::fprintf(stderr,
                 "usage: tspline_bench [N [M]]   (grid cells, each at least 4)\n"
                 "       tspline_bench MODEL.msp (a T-spline model)\n");
    return 1;
  }
  try {
    std::printf("tspline_bench: position + first derivatives at %d random points, serial\n",
                kSamples);
    runCase("(a) periodic torus grid",
            spline::gridTMesh(knotLines(n + 1), knotLines(m + 1), true, true), n,
            [&](int i, int j) {
              const double a = 2 * kPi * i / n, b = 2 * kPi * j / m, r = 1.0 + 0.4 * std::cos(b);
              return Eigen::RowVector3d(r * std::cos(a), r * std::sin(a), 0.4 * std::sin(b));
            });
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> height(-0.5, 0.5);
    Eigen::VectorXd heights((n + 1) * (m + 1));
    for (Eigen::Index k = 0; k < heights.size(); ++k) heights[k] = height(rng);
    runCase("(b) planar grid, random heights",
            spline::gridTMesh(knotLines(n + 1), knotLines(m + 1)), n + 1,
            [&](int i, int j) { return Eigen::RowVector3d(i, j, heights[j * (n + 1) + i]); });
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "tspline_bench: %s\n", error.what());
    return 1;
  }
}
