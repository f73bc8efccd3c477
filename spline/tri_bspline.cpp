#include "spline/tri_bspline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "spline/simplex_spline.h"
#include "structure/errors.h"
#include "structure/vertex_scaling_energy.h"

#ifndef CONE_SCALE
#define CONE_SCALE 0.01
#endif
namespace mspline::spline {

namespace {

using structure::InputError;
using structure::RigidMotion;

constexpr double kPi = 3.14159265358979323846;

// Cone clouds lie this much closer to their vertex than shared clouds: the basis functions of the
// faces at a cone vanish at the cone (no knots surround it), and inside the faces only within
// about this distance of it.
constexpr double kConeCloudScale = 0.02;

/// Angle of face f at corner k (between its sides k and k + 2).
double cornerAngle(const SplineDomain& domain, int f, int k) {
  const auto& l = domain.sideLengths[std::size_t(f)];
  const double a = l[std::size_t(k)], b = l[std::size_t((k + 2) % 3)],
               opposite = l[std::size_t((k + 1) % 3)];
  return std::acos(std::clamp((a * a + b * b - opposite * opposite) / (2.0 * a * b), -1.0, 1.0));
}

double inradius(const std::array<double, 3>& l) {
  return 0.5 * structure::fourTimesArea(l[0], l[1], l[2]) / (l[0] + l[1] + l[2]);
}

Eigen::Matrix2d rotation(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return (Eigen::Matrix2d() << c, -s, s, c).finished();
}

}  // namespace

std::vector<FaceKnots> placeKnotClouds(const SplineDomain& domain,
                                       const std::vector<HomeChart>& charts, int degree,
                                       const KnotCloudOptions& options) {
  if (degree < 1 || degree > 10)
    throw InputError("knot clouds: degree " + std::to_string(degree) + " is outside 1..10");
  if (!(options.radiusFraction > 0.0 && options.radiusFraction <= 0.5))
    throw InputError("knot clouds: radius fraction " + std::to_string(options.radiusFraction) +
                     " is outside (0, 0.5]");
  const int faces = domain.faceCount();
  std::vector<double> radius(std::size_t(domain.vertexCount()),
                             std::numeric_limits<double>::infinity());
  // The first face and corner of every vertex: where its cloud is drawn.
  std::vector<std::array<int, 2>> home(std::size_t(domain.vertexCount()), {-1, -1});
  for (int f = 0; f < faces; ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = domain.faces[std::size_t(f)][std::size_t(c)];
      radius[std::size_t(v)] =
          std::min(radius[std::size_t(v)],
                   options.radiusFraction * inradius(domain.sideLengths[std::size_t(f)]));
      if (home[std::size_t(v)][0] < 0) home[std::size_t(v)] = {f, c};
    }
  std::mt19937_64 random(options.seed);
  const auto uniform = [&random] { return double(random() >> 11) * 0x1.0p-53; };
  // Offsets of the shared clouds in the frame of the vertex's first face.
  std::vector<std::vector<Eigen::Vector2d>> offsets(std::size_t(domain.vertexCount()));
  for (int v = 0; v < domain.vertexCount(); ++v) {
    if (domain.cone[std::size_t(v)] || home[std::size_t(v)][0] < 0) continue;
    for (int b = 1; b <= degree; ++b) {
      const double r = radius[std::size_t(v)] * (0.3 + 0.7 * std::sqrt(uniform()));
      const double angle = 2.0 * kPi * uniform();
      offsets[std::size_t(v)].push_back(r * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    }
  }
  std::vector<FaceKnots> knots(static_cast<std::size_t>(faces));
  for (int f = 0; f < faces; ++f) {
    const auto corners = canonicalCorners(domain, f);
    for (int c = 0; c < 3; ++c) {
      const int v = domain.faces[std::size_t(f)][std::size_t(c)];
      auto& cloud = knots[std::size_t(f)][std::size_t(c)];
      cloud.assign(std::size_t(degree + 1), corners[std::size_t(c)]);
      if (domain.cone[std::size_t(v)]) {
        // A cloud of this face's own, close to the cone and strictly inside its corner.
        const Eigen::Vector2d toNext = corners[std::size_t((c + 1) % 3)] - corners[std::size_t(c)];
        const double start = std::atan2(toNext.y(), toNext.x());
        const double opening = cornerAngle(domain, f, c);
        for (int b = 1; b <= degree; ++b) {
          const double r = radius[std::size_t(v)] * kConeCloudScale * (1.0 + uniform());
          const double angle = start + (0.2 + 0.6 * uniform()) * opening;
          cloud[std::size_t(b)] += r * Eigen::Vector2d(std::cos(angle), std::sin(angle));
        }
        continue;
      }
      // The shared cloud, carried from its first face into this one's frame: by the copy of that
      // face that the fan around v places (its corner at v lands on this corner).
      const auto [source, sourceCorner] = home[std::size_t(v)];
      const auto& l = domain.sideLengths[std::size_t(f)];
      const RigidMotion* placement = nullptr;
      for (int at : charts[std::size_t(f)].findAll(source)) {
        const RigidMotion& candidate = charts[std::size_t(f)].placement[std::size_t(at)];
        const Eigen::Vector2d centre =
            candidate(canonicalCorners(domain, source)[std::size_t(sourceCorner)]);
        if ((centre - corners[std::size_t(c)]).norm() <= 1e-9 * (l[0] + l[1] + l[2]))
          placement = &candidate;
      }
      if (!placement)
        throw structure::InternalError("knot clouds: the chart of domain face " +
                                       std::to_string(f) + " misses the fan around its vertex " +
                                       std::to_string(v));
      for (int b = 1; b <= degree; ++b)
        cloud[std::size_t(b)] =
            corners[std::size_t(c)] +
            rotation(placement->angle) * offsets[std::size_t(v)][std::size_t(b - 1)];
    }
  }
  return knots;
}

TriBSplineSpace::TriBSplineSpace(SplineDomain domain, std::vector<FaceKnots> knots)
    : domain_(std::move(domain)), knots_(std::move(knots)) {
  charts_ = buildHomeCharts(domain_);
  if (int(knots_.size()) != domain_.faceCount())
    throw InputError("triangular B-spline: " + std::to_string(knots_.size()) + " knot sets for " +
                     std::to_string(domain_.faceCount()) + " faces");
  degree_ = domain_.faceCount() > 0 ? int(knots_[0][0].size()) - 1 : 0;
  perFace_ = (degree_ + 1) * (degree_ + 2) / 2;
  faceSpaces_.reserve(knots_.size());
  for (int f = 0; f < domain_.faceCount(); ++f) {
    const auto corners = canonicalCorners(domain_, f);
    corners_.push_back(corners);
    const auto& l = domain_.sideLengths[std::size_t(f)];
    KnotClouds clouds(3);
    for (int c = 0; c < 3; ++c) {
      const auto& cloud = knots_[std::size_t(f)][std::size_t(c)];
      if (int(cloud.size()) != degree_ + 1)
        throw InputError("triangular B-spline: domain face " + std::to_string(f) + " corner " +
                         std::to_string(c) + " has " + std::to_string(cloud.size()) +
                         " knots, expected " + std::to_string(degree_ + 1));
      if (!((cloud[0] - corners[std::size_t(c)]).norm() <= 1e-9 * (l[0] + l[1] + l[2])))
        throw InputError("triangular B-spline: the first knot of corner " + std::to_string(c) +
                         " of domain face " + std::to_string(f) + " is not the corner");
      clouds[std::size_t(c)] = cloud;
      clouds[std::size_t(c)][0] = corners[std::size_t(c)];
    }
    Eigen::AlignedBox2d box;
    for (const auto& cloud : clouds)
      for (const auto& knot : cloud) box.extend(knot);
    supportBoxes_.push_back(box);
    try {
      faceSpaces_.emplace_back(std::vector<Eigen::Vector2d>(corners.begin(), corners.end()),
                               std::vector<std::array<int, 3>>{{0, 1, 2}}, std::move(clouds));
    } catch (const InputError& error) {
      throw InputError("triangular B-spline: domain face " + std::to_string(f) + ": " +
                       error.what());
    }
  }
  contributors_.resize(std::size_t(domain_.faceCount()));
  for (int k = 0; k < domain_.faceCount(); ++k) {
    const HomeChart& chart = charts_[std::size_t(k)];
    for (std::size_t j = 0; j < chart.faces.size(); ++j)
      contributors_[std::size_t(chart.faces[j])].push_back(
          {k, chart.placement[j], rotation(chart.placement[j].angle)});
  }
}

Eigen::Vector2d TriBSplineSpace::framePosition(const DomainPoint& point) const {
  if (point.face < 0 || point.face >= domain_.faceCount())
    throw InputError("triangular B-spline: domain face " + std::to_string(point.face) +
                     " does not exist");
  const auto& corners = corners_[std::size_t(point.face)];
  return point.barycentric[0] * corners[0] + point.barycentric[1] * corners[1] +
         point.barycentric[2] * corners[2];
}

std::vector<int> TriBSplineSpace::chartsHolding(int face) const {
  std::vector<int> faces;
  for (const auto& contributor : contributors_.at(std::size_t(face)))
    faces.push_back(contributor.face);
  return faces;
}

template <class Visitor>
void TriBSplineSpace::visitRaw(const DomainPoint& point, int derivatives, Visitor&& visit) const {
  const Eigen::Vector2d x = framePosition(point);
  thread_local BasisValues local;
  for (const Contributor& contributor : contributors_[std::size_t(point.face)]) {
    const Eigen::Vector2d y = contributor.rotation * x + contributor.motion.translation;
    if (!supportBoxes_[std::size_t(contributor.face)].contains(y)) continue;
    const DmsSpace& space = faceSpaces_[std::size_t(contributor.face)];
    space.basisAt(0, y, local, derivatives);
    const Eigen::Matrix2d& r = contributor.rotation;
    for (std::size_t k = 0; k < local.index.size(); ++k) {
      const int index = contributor.face * perFace_ + local.index[k];
      // Back to the frame of the point's face: y = R x + t.
      const Eigen::Vector2d gradient = derivatives >= 1
                                           ? Eigen::Vector2d(r.transpose() * local.gradient[k])
                                           : Eigen::Vector2d::Zero();
      const Eigen::Matrix2d hessian = derivatives >= 2
                                          ? Eigen::Matrix2d(r.transpose() * local.hessian[k] * r)
                                          : Eigen::Matrix2d::Zero();
      visit(index, local.value[k], gradient, hessian);
    }
  }
}

void TriBSplineSpace::basisAt(const DomainPoint& point, BasisValues& out, int derivatives,
                              double* denominator) const {
  out.index.clear();
  out.value.clear();
  out.gradient.clear();
  out.hessian.clear();
  double sum = 0.0;
  Eigen::Vector2d sumGradient = Eigen::Vector2d::Zero();
  Eigen::Matrix2d sumHessian = Eigen::Matrix2d::Zero();
  visitRaw(point, derivatives,
           [&](int index, double value, const Eigen::Vector2d& gradient,
               const Eigen::Matrix2d& hessian) {
             out.index.push_back(index);
             out.value.push_back(value);
             if (derivatives >= 1) out.gradient.push_back(gradient);
             if (derivatives >= 2) out.hessian.push_back(hessian);
             sum += value;
             sumGradient += gradient;
             sumHessian += hessian;
           });
  if (denominator) *denominator = sum;
  if (!(sum > 0.0)) {
    // A cone point: every function vanishes there, and the spline is undefined.
    out.index.clear();
    out.value.clear();
    out.gradient.clear();
    out.hessian.clear();
    return;
  }
  // Rational normalization R = N / D: dR = (dN - R dD) / D and the second derivatives likewise.
  for (std::size_t k = 0; k < out.value.size(); ++k) {
    const double value = out.value[k] / sum;
    if (derivatives >= 1) {
      const Eigen::Vector2d gradient = (out.gradient[k] - value * sumGradient) / sum;
      if (derivatives >= 2)
        out.hessian[k] = (out.hessian[k] - value * sumHessian - gradient * sumGradient.transpose() -
                          sumGradient * gradient.transpose()) /
                         sum;
      out.gradient[k] = gradient;
    }
    out.value[k] = value;
  }
}

SplinePoint TriBSplineSpace::evaluate(const Eigen::MatrixXd& control, const DomainPoint& point,
                                      int derivatives) const {
  if (control.rows() != numBasis())
    throw InputError("triangular B-spline: " + std::to_string(control.rows()) +
                     " control points for " + std::to_string(numBasis()) + " basis functions");
  BasisValues basis;
  basisAt(point, basis, derivatives);
  if (basis.index.empty())
    throw InputError("triangular B-spline: the spline is undefined at a cone point (domain face " +
                     std::to_string(point.face) + ")");
  const Eigen::Index dims = control.cols();
  SplinePoint result;
  result.position = Eigen::VectorXd::Zero(dims);
  if (derivatives >= 1) result.du = result.dv = Eigen::VectorXd::Zero(dims);
  if (derivatives >= 2) result.duu = result.duv = result.dvv = Eigen::VectorXd::Zero(dims);
  for (std::size_t k = 0; k < basis.index.size(); ++k) {
    const auto row = control.row(basis.index[k]).transpose();
    result.position += basis.value[k] * row;
    if (derivatives >= 1) {
      result.du += basis.gradient[k].x() * row;
      result.dv += basis.gradient[k].y() * row;
    }
    if (derivatives >= 2) {
      result.duu += basis.hessian[k](0, 0) * row;
      result.duv += basis.hessian[k](0, 1) * row;
      result.dvv += basis.hessian[k](1, 1) * row;
    }
  }
  if (derivatives >= 1 && dims == 3) {
    const Eigen::Vector3d normal = Eigen::Vector3d(result.du).cross(Eigen::Vector3d(result.dv));
    if (normal.norm() > 0.0) result.normal = normal.normalized();
  }
  return result;
}

SplineSamples TriBSplineSpace::evaluateBatch(const Eigen::MatrixXd& control,
                                             const std::vector<DomainPoint>& points,
                                             int derivatives) const {
  const Eigen::Index count = Eigen::Index(points.size()), dims = control.cols();
  SplineSamples samples;
  samples.position.resize(count, dims);
  if (derivatives >= 1) {
    samples.du.resize(count, dims);
    samples.dv.resize(count, dims);
    if (dims == 3) samples.normal.resize(count, 3);
  }
  if (derivatives >= 2) {
    samples.duu.resize(count, dims);
    samples.duv.resize(count, dims);
    samples.dvv.resize(count, dims);
  }
  samples.position.setZero();
  if (derivatives >= 1) samples.du.setZero(), samples.dv.setZero();
  if (derivatives >= 2) samples.duu.setZero(), samples.duv.setZero(), samples.dvv.setZero();
  thread_local BasisValues basis;
  for (Eigen::Index k = 0; k < count; ++k) {
    basisAt(points[std::size_t(k)], basis, derivatives);
    if (basis.index.empty())
      throw InputError(
          "triangular B-spline: the spline is undefined at a cone point (domain face " +
          std::to_string(points[std::size_t(k)].face) + ")");
    for (std::size_t j = 0; j < basis.index.size(); ++j) {
      const auto row = control.row(basis.index[j]);
      samples.position.row(k) += basis.value[j] * row;
      if (derivatives >= 1) {
        samples.du.row(k) += basis.gradient[j].x() * row;
        samples.dv.row(k) += basis.gradient[j].y() * row;
      }
      if (derivatives >= 2) {
        samples.duu.row(k) += basis.hessian[j](0, 0) * row;
        samples.duv.row(k) += basis.hessian[j](0, 1) * row;
        samples.dvv.row(k) += basis.hessian[j](1, 1) * row;
      }
    }
    if (derivatives >= 1 && dims == 3) {
      const Eigen::Vector3d normal = Eigen::Vector3d(samples.du.row(k).transpose())
                                         .cross(Eigen::Vector3d(samples.dv.row(k).transpose()));
      samples.normal.row(k).setZero();
      if (normal.norm() > 0.0) samples.normal.row(k) = normal.normalized().transpose();
    }
  }
  return samples;
}

Eigen::VectorXd TriBSplineSpace::evaluateInChart(const Eigen::MatrixXd& control,
                                                 const DomainPoint& point, int holder,
                                                 ChartRoute route) const {
  const Eigen::Vector2d x = framePosition(point);
  const auto& holders = contributors_[std::size_t(point.face)];
  if (holder < 0 || holder >= int(holders.size()))
    throw InputError("triangular B-spline: domain face " + std::to_string(point.face) +
                     " has no chart " + std::to_string(holder));
  const HomeChart& home = charts_[std::size_t(holders[std::size_t(holder)].face)];
  const Eigen::Vector2d inChart = holders[std::size_t(holder)].motion(x);
  const double scale = (canonicalCorners(domain_, point.face)[1]).norm();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(control.cols());
  double denominator = 0.0;
  BasisValues local;
  for (const Contributor& contributor : holders) {
    const DmsSpace& space = faceSpaces_[std::size_t(contributor.face)];
    // The copy of the function's face in the chart that sits where this contributor sees the
    // point (the chart may hold several).
    const Eigen::Vector2d direct = contributor.motion(x);
    const RigidMotion* placement = nullptr;
    for (int at : home.findAll(contributor.face)) {
      const RigidMotion& candidate = home.placement[std::size_t(at)];
      if ((candidate.inverse()(inChart) - direct).norm() <= 1e-6 * scale) placement = &candidate;
    }
    if (placement && route == ChartRoute::MoveKnots) {
      for (int k = 0; k < perFace_; ++k) {
        std::vector<Eigen::Vector2d> knots = space.knotSet(k);
        for (auto& knot : knots) knot = (*placement)(knot);
        const double value = space.normalization(k) * simplexSpline(inChart, knots);
        sum += value * control.row(contributor.face * perFace_ + k).transpose();
        denominator += value;
      }
      continue;
    }
    space.basisAt(0, placement ? placement->inverse()(inChart) : direct, local);
    for (std::size_t j = 0; j < local.index.size(); ++j) {
      sum += local.value[j] * control.row(contributor.face * perFace_ + local.index[j]).transpose();
      denominator += local.value[j];
    }
  }
  return sum / denominator;
}

}  // namespace mspline::spline
