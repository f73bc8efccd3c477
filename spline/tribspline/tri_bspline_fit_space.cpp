#include "mspline/spline/tribspline/tri_bspline_fit_space.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

namespace {

// A walk turns around at most this many sides (a segment many times around a small domain, or
// rounding going round in circles) before it stops where it is.
constexpr int kMaxCrossings = 10000;
// A segment passing a cone closer than this (relative to the face's perimeter) runs into it.
constexpr double kConeHit = 1e-9;
// Where it does, the walk stops this much (relative to the perimeter) before the closest approach.
constexpr double kConeMargin = 1e-6;

Eigen::Vector2d turn(double angle, const Eigen::Vector2d& x) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * x.x() - s * x.y(), s * x.x() + c * x.y()};
}

// The frame position of barycentric coordinates `lambda` in a face with `corners`, rounding's
// small negative coordinates (a point on a side) clamped first.
Eigen::Vector2d framePoint(const std::array<Eigen::Vector2d, 3>& corners, Eigen::Vector3d lambda) {
  lambda = lambda.cwiseMax(0.0);
  lambda /= lambda.sum();
  return lambda[0] * corners[0] + lambda[1] * corners[1] + lambda[2] * corners[2];
}

}  // namespace

FacePoint toFitParameter(const TriBSplineSpace& space, const SurfacePoint& point) {
  return {point.face, space.framePosition(point)};
}

SurfacePoint toDomainPoint(const TriBSplineSpace& space, const FacePoint& p) {
  if (p.face < 0 || p.face >= space.domain().faceCount())
    throw structure::InputError("fit parameter: domain face " + std::to_string(p.face) +
                                " does not exist");
  return {p.face, frameBarycentric(space.domain(), p.face, p.position)};
}

TriBSplineFitSpace::TriBSplineFitSpace(const TriBSplineSpace& space) : space_(space) {}

void TriBSplineFitSpace::basisAt(const FacePoint& p, std::vector<FitBasisTerm>& out,
                                 int derivatives) const {
  thread_local BasisValues values;
  out.clear();
  space_.basisAt(toDomainPoint(space_, p), values, derivatives);
  for (std::size_t k = 0; k < values.index.size(); ++k) {
    FitBasisTerm term;
    term.index = values.index[k];
    term.value = values.value[k];
    if (derivatives >= 1) {
      term.ds = values.gradient[k].x();
      term.dt = values.gradient[k].y();
    }
    if (derivatives >= 2) {
      term.dss = values.hessian[k](0, 0);
      term.dst = values.hessian[k](0, 1);
      term.dtt = values.hessian[k](1, 1);
    }
    out.push_back(term);
  }
}

FacePoint TriBSplineFitSpace::walk(const FacePoint& p, const Eigen::Vector2d& step) const {
  Eigen::Vector2d turnedStep;
  return walk(p, step, turnedStep);
}

FacePoint TriBSplineFitSpace::walk(const FacePoint& p, const Eigen::Vector2d& step,
                                   Eigen::Vector2d& turnedStep) const {
  const SplineDomain& domain = space_.domain();
  FacePoint at = p;
  toDomainPoint(space_, at);  // checks the face
  // What is left of the step, and the whole step, in the frame of at.face.
  Eigen::Vector2d rest = step;
  turnedStep = step;
  // The side the walk came in through: a straight segment cannot leave a triangle through it.
  int entry = -1;
  for (int crossing = 0; crossing <= kMaxCrossings && rest.squaredNorm() > 0.0; ++crossing) {
    const std::size_t f = std::size_t(at.face);
    const auto corners = canonicalCorners(domain, at.face);
    const auto& l = domain.sideLengths[f];
    const double perimeter = l[0] + l[1] + l[2];
    const Eigen::Vector3d from = frameBarycentric(domain, at.face, at.position);
    const Eigen::Vector3d to = frameBarycentric(domain, at.face, at.position + rest);
    // The first side the segment leaves through (lambda_j vanishes on side j + 1) and when.
    double leave = 1.0;
    int exit = -1;
    for (int j = 0; j < 3; ++j) {
      const int side = (j + 1) % 3;
      if (side == entry || !(to[j] < 0.0)) continue;
      const double t = from[j] <= 0.0 ? 0.0 : from[j] / (from[j] - to[j]);
      if (t < leave || exit < 0) {
        leave = std::min(t, 1.0);
        exit = side;
      }
    }
    // A cone next to the part of the segment inside this face stops the walk short of it.
    for (int k = 0; k < 3; ++k) {
      if (!domain.cone[std::size_t(domain.faces[f][std::size_t(k)])]) continue;
      const Eigen::Vector2d toCone = corners[std::size_t(k)] - at.position;
      const double closest = std::clamp(toCone.dot(rest) / rest.squaredNorm(), 0.0, leave);
      if ((at.position + closest * rest - corners[std::size_t(k)]).norm() > kConeHit * perimeter)
        continue;
      const double stop = std::max(0.0, closest - kConeMargin * perimeter / rest.norm());
      at.position =
          framePoint(corners, frameBarycentric(domain, at.face, at.position + stop * rest));
      return at;
    }
    if (exit < 0) {
      at.position = framePoint(corners, to);
      return at;
    }
    // Across side `exit` (corner exit to exit + 1), which runs the other way in the neighbour:
    // the point keeps its place along the side and the direction turns with the side.
    const int g = domain.neighbour[f][std::size_t(exit)];
    const int gs = domain.neighbourSide[f][std::size_t(exit)];
    const Eigen::Vector3d there = frameBarycentric(domain, at.face, at.position + leave * rest);
    const double a = std::max(0.0, there[exit]), b = std::max(0.0, there[(exit + 1) % 3]);
    const double along = a + b > 0.0 ? b / (a + b) : 0.5;
    const auto next = canonicalCorners(domain, g);
    const Eigen::Vector2d& nextStart = next[std::size_t((gs + 1) % 3)];
    const Eigen::Vector2d& nextEnd = next[std::size_t(gs)];
    const Eigen::Vector2d sideHere =
        corners[std::size_t((exit + 1) % 3)] - corners[std::size_t(exit)];
    const Eigen::Vector2d sideThere = nextEnd - nextStart;
    const double angle =
        std::atan2(sideThere.y(), sideThere.x()) - std::atan2(sideHere.y(), sideHere.x());
    rest = turn(angle, (1.0 - leave) * rest);
    turnedStep = turn(angle, turnedStep);
    at = {g, (1.0 - along) * nextStart + along * nextEnd};
    entry = gs;
  }
  return at;
}

double TriBSplineFitSpace::faceSize(int face) const {
  const auto& sides = space_.domain().sideLengths.at(std::size_t(face));
  return std::max({sides[0], sides[1], sides[2]});
}

namespace {

// Quadrature nodes where sum N_k is below this (close to a cone) are left out.
constexpr double kMinDenominator = 0.5;

// The barycentric corners of the four triangles a face's side midpoints cut it into.
const std::array<std::array<Eigen::Vector3d, 3>, 4> kMidpointTriangles{{
    {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0.5, 0.5, 0), Eigen::Vector3d(0.5, 0, 0.5)},
    {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0.5, 0.5), Eigen::Vector3d(0.5, 0.5, 0)},
    {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.5, 0, 0.5), Eigen::Vector3d(0, 0.5, 0.5)},
    {Eigen::Vector3d(0.5, 0.5, 0), Eigen::Vector3d(0, 0.5, 0.5), Eigen::Vector3d(0.5, 0, 0.5)},
}};

}  // namespace

void TriBSplineFitSpace::quadrature(std::vector<FacePoint>& nodes,
                                    std::vector<double>& weights) const {
  // Dunavant's 7-point rule (exact to degree 5): the centroid and two orbits of three points.
  const double r = std::sqrt(15.0);
  const double a1 = (6.0 - r) / 21.0, a2 = (6.0 + r) / 21.0;
  const double w1 = (155.0 - r) / 1200.0, w2 = (155.0 + r) / 1200.0;
  const std::array<Eigen::Vector3d, 7> points{
      Eigen::Vector3d::Constant(1.0 / 3.0),    Eigen::Vector3d(a1, a1, 1.0 - 2.0 * a1),
      Eigen::Vector3d(a1, 1.0 - 2.0 * a1, a1), Eigen::Vector3d(1.0 - 2.0 * a1, a1, a1),
      Eigen::Vector3d(a2, a2, 1.0 - 2.0 * a2), Eigen::Vector3d(a2, 1.0 - 2.0 * a2, a2),
      Eigen::Vector3d(1.0 - 2.0 * a2, a2, a2)};
  const std::array<double, 7> rule{9.0 / 40.0, w1, w1, w1, w2, w2, w2};
  nodes.clear();
  weights.clear();
  const SplineDomain& domain = space_.domain();
  BasisValues values;
  for (int f = 0; f < domain.faceCount(); ++f) {
    const auto corners = canonicalCorners(domain, f);
    // Corner 0 at the origin, corner 1 on the x axis.
    const double area = 0.5 * corners[1].x() * corners[2].y();
    // The rule on each of the face's 4 midpoint triangles: the basis is only piecewise
    // polynomial (the knot lines cross the face), and 7 nodes cannot see all of a face's 10+
    // functions' second derivatives, which would leave functions without data (over filled
    // holes) undetermined.
    for (const auto& sub : kMidpointTriangles)
      for (std::size_t k = 0; k < points.size(); ++k) {
        const Eigen::Vector3d b =
            points[k][0] * sub[0] + points[k][1] * sub[1] + points[k][2] * sub[2];
        const SurfacePoint point{f, b};
        double denominator = 0.0;
        space_.basisAt(point, values, 0, &denominator);
        // Near a cone the normalization divides by a vanishing sum: second derivatives there
        // are huge and would make the fairing ill-conditioned, so the energy is taken where the
        // basis is close to a partition of unity.
        if (values.index.empty() || denominator < kMinDenominator) continue;
        nodes.push_back(toFitParameter(space_, point));
        weights.push_back(0.25 * rule[k] * area);
      }
  }
}

}  // namespace mspline::spline
