#include "mspline/spline/tspline/tspline_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "mspline/structure/core/constants.h"

namespace mspline::spline {

namespace {

// Normals at a small distance around every cone (TSplineCheck::maxConeNormalSpread).
void checkCones(const TSplineSpace& space, const Eigen::MatrixXd& control,
                const Eigen::VectorXd& weights, TSplineCheck& check) {
  constexpr double kOffset = 1e-3;
  const TMesh& mesh = space.mesh();
  std::vector<std::vector<Eigen::Vector3d>> normals(std::size_t(mesh.numVertices));
  for (const TSplineCapFace& cap : space.capFaces()) {
    const TMeshFace& face = mesh.faces[std::size_t(cap.face)];
    const auto at = std::find(face.vertices.begin(), face.vertices.end(), cap.cone);
    const Eigen::Vector2d corner = face.positions[std::size_t(at - face.vertices.begin())];
    const double sx = corner.x() < 0.5 * face.width ? 1.0 : -1.0;
    const double sy = corner.y() < 0.5 * face.height ? 1.0 : -1.0;
    for (const double fraction : {0.125, 0.5, 0.875}) {
      const double angle = fraction * kPi / 2.0;
      const Eigen::Vector2d p =
          corner + kOffset * Eigen::Vector2d(sx * std::cos(angle), sy * std::sin(angle));
      const Eigen::VectorXd normal = space.evaluate(control, weights, cap.face, p, 1).normal;
      normals[std::size_t(cap.cone)].push_back(normal);
    }
  }
  for (int v = 0; v < mesh.numVertices; ++v) {
    const auto& around = normals[std::size_t(v)];
    if (around.empty()) continue;
    ++check.cones;
    double spread = 0.0;
    for (const auto& a : around)
      for (const auto& b : around)
        spread = a.allFinite() && b.allFinite()
                     ? std::max(spread, std::atan2(a.cross(b).norm(), a.dot(b)))
                     : kPi;
    if (spread > 1e-3) ++check.conesSpreadOver1e3;
    if (spread > check.maxConeNormalSpread || check.worstCone < 0) {
      check.maxConeNormalSpread = spread;
      check.worstCone = v;
    }
  }
}

}  // namespace

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
  if (control.cols() == 3) checkCones(space, control, weights, check);
  return check;
}

}  // namespace mspline::spline
