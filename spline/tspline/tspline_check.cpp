#include "mspline/spline/tspline/tspline_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "mspline/spline/tspline/tspline_cone_normals.h"

namespace mspline::spline {

TSplineCheck checkTSpline(const TSplineSpace& space, const Eigen::MatrixXd& control,
                          const Eigen::VectorXd& weights, const TSplineCheckOptions& options) {
  const TMesh& mesh = space.mesh();
  const TSplineBezier bezier(space, control, weights);
  TSplineCheck check;
  check.samples = options.samples;
  check.diagonal = (control.colwise().maxCoeff() - control.colwise().minCoeff()).norm();
  const double scale = check.diagonal > 0.0 ? 1.0 / check.diagonal : 1.0;
  check.minDenominator = std::numeric_limits<double>::infinity();
  std::vector<double> areas;
  for (const auto& f : mesh.faces) areas.push_back(f.width * f.height);
  std::mt19937_64 random(options.seed);
  std::discrete_distribution<int> pickFace(areas.begin(), areas.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Vertices within two edges of a vertex without function, and the faces touching them.
  std::vector<std::vector<int>> neighbours(std::size_t(mesh.numVertices));
  for (const auto& face : mesh.faces)
    for (std::size_t k = 0; k < face.vertices.size(); ++k) {
      const int a = face.vertices[k], b = face.vertices[(k + 1) % face.vertices.size()];
      neighbours[std::size_t(a)].push_back(b);
      neighbours[std::size_t(b)].push_back(a);
    }
  std::vector<int> near;
  std::vector<char> isNear(std::size_t(mesh.numVertices), 0);
  for (const auto& missing : space.missingAnchors()) {
    isNear[std::size_t(missing.vertex)] = 1;
    near.push_back(missing.vertex);
  }
  for (int ring = 0; ring < 2; ++ring) {
    const std::vector<int> front = near;
    for (int v : front)
      for (int w : neighbours[std::size_t(v)])
        if (!isNear[std::size_t(w)]) {
          isNear[std::size_t(w)] = 1;
          near.push_back(w);
        }
  }
  std::vector<char> faceAway(mesh.faces.size(), 1);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (int v : mesh.faces[f].vertices)
      if (isNear[std::size_t(v)]) faceAway[f] = 0;
  std::vector<TSplineBasisValue> basis;
  for (int s = 0; s < options.samples; ++s) {
    const int f = pickFace(random);
    const TMeshFace& face = mesh.faces[f];
    const Eigen::Vector2d p(unit(random) * face.width, unit(random) * face.height);
    space.basisAt(f, p, basis);
    double sum = 0.0;
    for (const auto& b : basis) sum += b.value;
    if (basis.empty()) {
      ++check.holeSamples;
      continue;
    }
    check.partitionOfUnityError = std::max(check.partitionOfUnityError, std::abs(sum - 1.0));
    if (faceAway[std::size_t(f)]) {
      check.partitionOfUnityErrorAway =
          std::max(check.partitionOfUnityErrorAway, std::abs(sum - 1.0));
      ++check.awaySamples;
    }
    if (std::abs(sum - 1.0) > 1e-12) ++check.normalizedSamples;
    const TSplinePoint direct = space.evaluate(control, weights, f, p);
    check.minDenominator = std::min(check.minDenominator, direct.denominator);
    const TSplinePoint moved = space.evaluateMovingKnots(control, weights, f, p);
    check.knotRouteDiscrepancy =
        std::max(check.knotRouteDiscrepancy, (moved.position - direct.position).norm() * scale);
    Eigen::Vector3d x, du, dv;
    bezier.evaluate(f, p, x, &du, &dv);
    check.bezierDiscrepancy =
        std::max(check.bezierDiscrepancy, (x - direct.position).norm() * scale);
    check.bezierDerivativeDiscrepancy =
        std::max({check.bezierDerivativeDiscrepancy, (du - direct.ds).norm() * scale,
                  (dv - direct.dt).norm() * scale});

    // A point on a random shared edge of the face, seen from both sides.
    const int k = std::uniform_int_distribution<int>(0, int(face.vertices.size()) - 1)(random);
    if (face.twinFace[k] < 0) continue;
    const Eigen::Vector2d a = face.positions[k],
                          b = face.positions[(k + 1) % face.positions.size()];
    const Eigen::Vector2d q = a + unit(random) * (b - a);
    const Eigen::Vector2d other = mesh.acrossEdge(f, k).apply(q);
    const TSplinePoint here = space.evaluate(control, weights, f, q, 0);
    const TSplinePoint there = space.evaluate(control, weights, face.twinFace[k], other, 0);
    if (!(here.denominator > 0.0) || !(there.denominator > 0.0)) continue;
    check.chartDiscrepancy =
        std::max(check.chartDiscrepancy, (here.position - there.position).norm() * scale);
    ++check.edgeSamples;
  }
  if (!std::isfinite(check.minDenominator)) check.minDenominator = 0.0;
  if (control.cols() == 3)
    for (const ConeNormalSpread& cone : coneNormalSpreads(space, control, weights)) {
      ++check.cones;
      if (cone.spread > 1e-3) ++check.conesSpreadOver1e3;
      if (cone.spread > check.maxConeNormalSpread || check.worstCone < 0) {
        check.maxConeNormalSpread = cone.spread;
        check.worstCone = cone.vertex;
      }
    }
  return check;
}

}  // namespace mspline::spline
