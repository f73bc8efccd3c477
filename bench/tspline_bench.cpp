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
// (c) A T-spline model of a real mesh, with extraordinary points at the cones (their polynomial
// caps, tspline_cap.h), against OpenSubdiv on its own net; only a T-mesh without T-junctions has
// one (bunny00's T-splines have T-junctions where cells split around close cones). (d) A fitted
// T-spline, T-junctions and all, against the `subd` fit of the same scan: OpenSubdiv on that
// model's net, the same layout's net before its cells are split, with about as many control
// points. The two are different surfaces, so only speed is compared: 1e6 random points of each
// (sample k in face k mod F of its own model at uniform (u, v)), best of five batches each.
//
// Usage: tspline_bench [N [M]]              (a), (b): cells; default 200 100, each at least 4
//        tspline_bench MODEL.msp            (c): `mspline spline MESH --kind tspline -o MODEL.msp`
//        tspline_bench TSPLINE.msp SUBD.msp (d): `mspline fit SCAN --kind tspline -o TSPLINE.msp`
//                                           and `mspline fit SCAN --kind subd -o SUBD.msp`
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
#include "mspline/spline/subd/catmull_clark_limit.h"
#include "mspline/spline/subd/tspline_osd.h"
#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_bezier.h"
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

spline::SplineModel readModel(const std::string& path, spline::SplineKind kind) {
  spline::SplineModel model = io::readSplineModel(path);
  if (model.kind != kind)
    throw std::runtime_error(path + " is not a " +
                             (kind == spline::SplineKind::TSpline ? "T-spline" : "subdivision") +
                             " model");
  return model;
}

// A T-spline model (mspline spline --kind tspline): its own T-mesh and control points, with
// extraordinary points at the cones.
void runModel(const std::string& path) {
  const spline::SplineModel model = readModel(path, spline::SplineKind::TSpline);
  auto start = Clock::now();
  const spline::TSplineSpace space(model.tmesh);
  const double spaceSeconds = since(start);
  spline::OsdCompareOptions options;
  options.samples = kSamples;
  printComparison(
      ("(c) " + path).c_str(), model.tmesh.numVertices, model.tmesh.numFaces(), spaceSeconds,
      spline::compareWithOpenSubdiv(space, model.controlPoints, model.weights, options));
}

// Best of kBatches timed batches of each, in turn, so that a burst of load on the shared machine
// does not fall on one side only.
constexpr int kBatches = 5;

// (d): the fitted T-spline at `tsplinePath` by Bezier extraction against OpenSubdiv's limit of the
// subdivision model at `subdPath`, each at kSamples random points of its own faces.
void runFittedPair(const std::string& tsplinePath, const std::string& subdPath) {
  const spline::SplineModel tspline = readModel(tsplinePath, spline::SplineKind::TSpline);
  const spline::SplineModel subd = readModel(subdPath, spline::SplineKind::Subdivision);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  auto start = Clock::now();
  const spline::TSplineSpace space(tspline.tmesh);
  const double spaceSeconds = since(start);
  start = Clock::now();
  const spline::TSplineBezier bezier(space, tspline.controlPoints, tspline.weights);
  const double bezierSeconds = since(start);
  const spline::TMesh& tmesh = tspline.tmesh;
  std::vector<spline::FacePoint> points(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    const int f = k % tmesh.numFaces();
    const double x = unit(rng) * tmesh.faces[f].width, y = unit(rng) * tmesh.faces[f].height;
    points[k] = {f, Eigen::Vector2d(x, y)};
  }

  start = Clock::now();
  const spline::CatmullClarkLimit limit(subd.controlPoints,
                                        spline::catmullClarkNetFaces(subd.tmesh, subdPath));
  const double osdSetupSeconds = since(start);
  std::vector<spline::FaceParameter> parameters(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    const double u = unit(rng), v = unit(rng);
    parameters[k] = {k % limit.numPatchFaces(), u, v};
  }
  Eigen::MatrixX3d position, ds, dt;
  spline::LimitPoints reference;
  std::size_t onSurface = 0;
  double msplineSeconds = INFINITY, osdSeconds = INFINITY;
  for (int batch = 0; batch < kBatches; ++batch) {
    start = Clock::now();
    bezier.evaluate(points, position, ds, dt);
    msplineSeconds = std::min(msplineSeconds, since(start));
    start = Clock::now();
    onSurface = limit.evaluate(parameters, reference);
    osdSeconds = std::min(osdSeconds, since(start));
  }
  const bool msplineFinite = position.allFinite() && ds.allFinite() && dt.allFinite();
  const double msplineRate = kSamples / msplineSeconds, osdRate = kSamples / osdSeconds;

  std::printf(
      "\n(d) fitted T-spline %s: %d faces, %d control points, %d T-junctions, %d "
      "extraordinary points%s\n",
      tsplinePath.c_str(), tmesh.numFaces(), space.numBasis(), tmesh.numTJunctions(),
      tmesh.numExtraordinary(), msplineFinite ? "" : " (NOT FINITE at some points)");
  std::printf(
      "    subdivision model %s: %d faces, %d control points, %d extraordinary points, "
      "%zu of %d points on the surface\n",
      subdPath.c_str(), subd.tmesh.numFaces(), limit.numControlPoints(),
      subd.tmesh.numExtraordinary(), onSurface, kSamples);
  std::printf("  %-34s %12s %10s\n", "evaluator", "Mpoints/s", "setup s");
  std::printf("  %-34s %12.3f %10.3f  (TSplineSpace %.3f s + Bezier extraction %.3f s)\n",
              "mspline T-spline (TSplineBezier)", msplineRate / 1e6, spaceSeconds + bezierSeconds,
              spaceSeconds, bezierSeconds);
  std::printf("  %-34s %12.3f %10.3f\n", "OpenSubdiv Far (double)", osdRate / 1e6, osdSetupSeconds);
  std::printf("  mspline / OpenSubdiv: %.2fx the speed (target >= 1), %.2fx the setup time\n",
              msplineRate / osdRate, (spaceSeconds + bezierSeconds) / osdSetupSeconds);
}

bool isModelPath(const std::string& arg) {
  return arg.size() > 4 && arg.substr(arg.size() - 4) == ".msp";
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  const bool models =
      !args.empty() && args.size() <= 2 && std::all_of(args.begin(), args.end(), isModelPath);
  const int n = !models && argc > 1 ? std::atoi(argv[1]) : 200;
  const int m = !models && argc > 2 ? std::atoi(argv[2]) : (argc > 1 ? n : 100);
  if (!models && (argc > 3 || n < 4 || m < 4)) {
    std::fprintf(stderr,
                 "usage: tspline_bench [N [M]]              (grid cells, each at least 4)\n"
                 "       tspline_bench MODEL.msp            (a T-spline model without "
                 "T-junctions)\n"
                 "       tspline_bench TSPLINE.msp SUBD.msp (a fitted T-spline and the subd fit "
                 "of the same scan)\n");
    return 1;
  }
  try {
    std::printf("tspline_bench: position + first derivatives at %d random points, serial\n",
                kSamples);
    if (args.size() == 1 && models) {
      runModel(args[0]);
      return 0;
    }
    if (models) {
      runFittedPair(args[0], args[1]);
      return 0;
    }
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
