#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/structure/core/constants.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "mspline/spline/tribspline/simplex_spline.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"

namespace mspline::spline {

namespace {

using structure::InputError;
using structure::RigidMotion;

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
    // lambda_j(x) = (cross(u, v) + cross(x, u - v)) / det, u and v the other two corners.
    const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
      return u.x() * v.y() - u.y() * v.x();
    };
    const double det = cross(corners[1], corners[2]);
    std::array<double, 9> frame{};
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector2d& u = corners[std::size_t((j + 1) % 3)];
      const Eigen::Vector2d& v = corners[std::size_t((j + 2) % 3)];
      frame[std::size_t(3 * j)] = cross(u, v) / det;
      frame[std::size_t(3 * j + 1)] = (u - v).y() / det;
      frame[std::size_t(3 * j + 2)] = -(u - v).x() / det;
    }
    barycentric_.push_back(frame);
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
    // The knots as the face's space has them (knot 0 exactly the corner).
    const KnotClouds& faceKnots = faceSpaces_[std::size_t(k)].knots();
    for (std::size_t j = 0; j < chart.faces.size(); ++j) {
      const int g = chart.faces[j];
      Contributor contributor{k, chart.placement[j], rotation(chart.placement[j].angle), {}, {}};
      // The coordinates are affine: their largest values over a convex hull are over its points.
      const auto bounds = [&](const std::vector<Eigen::Vector2d>& points) {
        std::array<double, 3> upper;
        upper.fill(-std::numeric_limits<double>::infinity());
        for (const Eigen::Vector2d& point : points) {
          const std::array<double, 3> lambda = barycentricAt(
              g, contributor.rotation.transpose() * (point - contributor.motion.translation));
          for (std::size_t c = 0; c < 3; ++c) upper[c] = std::max(upper[c], lambda[c]);
        }
        for (double& bound : upper) bound += 1e-9;
        return upper;
      };
      contributor.reach[0] =
          bounds({corners_[std::size_t(k)].begin(), corners_[std::size_t(k)].end()});
      for (std::size_t side = 0; side < 3; ++side) {
        std::vector<Eigen::Vector2d> clouds = faceKnots[side];
        clouds.insert(clouds.end(), faceKnots[(side + 1) % 3].begin(),
                      faceKnots[(side + 1) % 3].end());
        contributor.reach[side + 1] = bounds(clouds);
      }
      for (std::size_t c = 0; c < 3; ++c)
        contributor.anyReach[c] = std::max({contributor.reach[0][c], contributor.reach[1][c],
                                            contributor.reach[2][c], contributor.reach[3][c]});
      contributors_[std::size_t(g)].push_back(contributor);
    }
  }
  for (int g = 0; g < domain_.faceCount(); ++g) {
    // Clearly inside (DmsSpace's margin), then each region that might still meet the inner
    // triangle is cut off along the coordinate where that costs least.
    std::array<double, 3> from{1e-9, 1e-9, 1e-9};
    for (const Contributor& contributor : contributors_[std::size_t(g)]) {
      // The home face comes first in its chart, with the identity: its own triangle is G.
      const bool self = contributor.face == g && contributor.motion.angle == 0.0 &&
                        contributor.motion.translation.isZero(0.0);
      for (std::size_t r = self ? 1 : 0; r < 4; ++r) {
        const auto& upper = contributor.reach[r];
        if (upper[0] <= from[0] || upper[1] <= from[1] || upper[2] <= from[2]) continue;
        const std::size_t j =
            std::size_t(std::min_element(upper.begin(), upper.end()) - upper.begin());
        from[j] = upper[j];
      }
    }
    polynomialFrom_.push_back(from);
  }
}

bool TriBSplineSpace::Contributor::mayReach(const double* lambda) const {
  if (lambda[0] > anyReach[0] || lambda[1] > anyReach[1] || lambda[2] > anyReach[2]) return false;
  for (const auto& upper : reach)
    if (lambda[0] <= upper[0] && lambda[1] <= upper[1] && lambda[2] <= upper[2]) return true;
  return false;
}

std::array<double, 3> TriBSplineSpace::barycentricAt(int face, const Eigen::Vector2d& x) const {
  const auto& frame = barycentric_[std::size_t(face)];
  return {frame[0] + frame[1] * x.x() + frame[2] * x.y(),
          frame[3] + frame[4] * x.x() + frame[5] * x.y(),
          frame[6] + frame[7] * x.x() + frame[8] * x.y()};
}

Eigen::Vector2d TriBSplineSpace::framePosition(const SurfacePoint& point) const {
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
void TriBSplineSpace::visitContributors(int face, const Eigen::Vector2d& x,
                                        const std::array<double, 3>& lambda, int derivatives,
                                        TriangleBasis& basis, Visitor&& visit) const {
  for (const Contributor& contributor : contributors_[std::size_t(face)]) {
    if (!contributor.mayReach(lambda.data())) continue;
    const Eigen::Vector2d y = contributor.rotation * x + contributor.motion.translation;
    if (faceSpaces_[std::size_t(contributor.face)].triangleBasisAt(0, y, basis, derivatives))
      visit(contributor, basis);
  }
}

void TriBSplineSpace::basisAt(const SurfacePoint& point, BasisValues& out, int derivatives,
                              double* denominator) const {
  out.index.clear();
  out.value.clear();
  out.gradient.clear();
  out.hessian.clear();
  double sum = 0.0;
  Eigen::Vector2d sumGradient = Eigen::Vector2d::Zero();
  Eigen::Matrix2d sumHessian = Eigen::Matrix2d::Zero();
  thread_local TriangleBasis local;
  const Eigen::Vector2d x = framePosition(point);
  visitContributors(
      point.face, x, barycentricAt(point.face, x), derivatives, local,
      [&](const Contributor& contributor, const TriangleBasis& basis) {
        // Back to the frame of the point's face: y = R x + t.
        const Eigen::Matrix2d& r = contributor.rotation;
        for (int k = 0; k < perFace_; ++k) {
          const Eigen::Vector2d gradient =
              derivatives >= 1 ? Eigen::Vector2d(basis.gradient[std::size_t(2 * k)],
                                                 basis.gradient[std::size_t(2 * k + 1)])
                               : Eigen::Vector2d::Zero();
          Eigen::Matrix2d hessian = Eigen::Matrix2d::Zero();
          if (derivatives >= 2)
            hessian << basis.hessian[std::size_t(3 * k)], basis.hessian[std::size_t(3 * k + 1)],
                basis.hessian[std::size_t(3 * k + 1)], basis.hessian[std::size_t(3 * k + 2)];
          const double value = basis.value[std::size_t(k)];
          if (value == 0.0 && gradient.isZero(0.0) && hessian.isZero(0.0)) continue;
          out.index.push_back(contributor.face * perFace_ + k);
          out.value.push_back(value);
          sum += value;
          if (derivatives >= 1) {
            out.gradient.push_back(r.transpose() * gradient);
            sumGradient += out.gradient.back();
          }
          if (derivatives >= 2) {
            out.hessian.push_back(r.transpose() * hessian * r);
            sumHessian += out.hessian.back();
          }
        }
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

SplinePoint TriBSplineSpace::evaluate(const Eigen::MatrixXd& control, const SurfacePoint& point,
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
                                             const std::vector<SurfacePoint>& points,
                                             int derivatives) const {
  SplineSamples samples;
  evaluateBatch(control, points, derivatives, samples);
  return samples;
}

void TriBSplineSpace::evaluateBatch(const Eigen::MatrixXd& control,
                                    const std::vector<SurfacePoint>& points, int derivatives,
                                    SplineSamples& samples) const {
  if (control.rows() != numBasis())
    throw InputError("triangular B-spline: " + std::to_string(control.rows()) +
                     " control points for " + std::to_string(numBasis()) + " basis functions");
  if (derivatives < 0 || derivatives > 2)
    throw InputError("triangular B-spline: derivatives must be 0, 1 or 2, got " +
                     std::to_string(derivatives));
  // Points grouped by face (a counting sort): consecutive points then share their contributors'
  // tables in cache, which in random order cost more than the arithmetic (and more than the
  // scattered writes of the results; sorting only windows of the points is slower).
  std::vector<int> start(std::size_t(domain_.faceCount()) + 1, 0);
  for (const SurfacePoint& point : points) {
    if (point.face < 0 || point.face >= domain_.faceCount())
      throw InputError("triangular B-spline: domain face " + std::to_string(point.face) +
                       " does not exist");
    ++start[std::size_t(point.face) + 1];
  }
  for (std::size_t f = 0; f + 1 < start.size(); ++f) start[f + 1] += start[f];
  std::vector<int> order(points.size());
  for (std::size_t k = 0; k < points.size(); ++k)
    order[std::size_t(start[std::size_t(points[k].face)]++)] = int(k);

  const Eigen::Index count = Eigen::Index(points.size());
  const Eigen::Index dims = control.cols();
  const auto size = [count](Eigen::MatrixXd& matrix, bool wanted, Eigen::Index columns) {
    if (wanted)
      matrix.resize(count, columns);
    else
      matrix.resize(0, 0);
  };
  size(samples.position, true, dims);
  size(samples.du, derivatives >= 1, dims);
  size(samples.dv, derivatives >= 1, dims);
  size(samples.normal, derivatives >= 1 && dims == 3, 3);
  size(samples.duu, derivatives >= 2, dims);
  size(samples.duv, derivatives >= 2, dims);
  size(samples.dvv, derivatives >= 2, dims);
  // [1, control point] row by row: a function's weights for D and for S are adjacent.
  RowMatrix rows(control.rows(), dims + 1);
  rows.col(0).setOnes();
  rows.rightCols(dims) = control;
  if (derivatives == 0)
    dims == 3 ? evaluateOrdered<1, 4>(points, order, rows, samples)
              : evaluateOrdered<1, 0>(points, order, rows, samples);
  else if (derivatives == 1)
    dims == 3 ? evaluateOrdered<3, 4>(points, order, rows, samples)
              : evaluateOrdered<3, 0>(points, order, rows, samples);
  else
    dims == 3 ? evaluateOrdered<6, 4>(points, order, rows, samples)
              : evaluateOrdered<6, 0>(points, order, rows, samples);
}

namespace {

// sum[p * width + c] += weight(p, k) * rows[k * width + c] over functions (or monomials)
// k < count, parts p < Parts and columns c < width; Width is width when fixed, else 0.
template <int Parts, int Width, class Weight>
void addWeighted(int count, const double* rows, int width, const Weight& weight, double* sum) {
  if constexpr (Width > 0) {
    // Fixed sizes and a variable per part: the sums stay in registers.
    using Row = Eigen::Array<double, Width, 1>;
    Row part[6] = {Row::Zero(), Row::Zero(), Row::Zero(), Row::Zero(), Row::Zero(), Row::Zero()};
    for (int k = 0; k < count; ++k, rows += Width) {
      const Row row = Eigen::Map<const Row>(rows);
      part[0] += weight(0, k) * row;
      if constexpr (Parts >= 3) {
        part[1] += weight(1, k) * row;
        part[2] += weight(2, k) * row;
      }
      if constexpr (Parts >= 6) {
        part[3] += weight(3, k) * row;
        part[4] += weight(4, k) * row;
        part[5] += weight(5, k) * row;
      }
    }
    for (int p = 0; p < Parts; ++p) Eigen::Map<Row>(sum + p * Width) += part[p];
  } else {
    for (int k = 0; k < count; ++k, rows += width)
      for (int p = 0; p < Parts; ++p) {
        const double w = weight(p, k);
        for (int c = 0; c < width; ++c) sum[p * width + c] += w * rows[c];
      }
  }
}

}  // namespace

template <int Parts, int Width>
void TriBSplineSpace::evaluateOrdered(const std::vector<SurfacePoint>& points,
                                      const std::vector<int>& order, const RowMatrix& rows,
                                      SplineSamples& samples) const {
  constexpr int derivatives = Parts == 1 ? 0 : Parts == 3 ? 1 : 2;
  const int width = Width > 0 ? Width : int(rows.cols());
  const int dims = width - 1;
  // Per point: part p (value, d/dx, d/dy, d2/dx2, d2/dxdy, d2/dy2) of the raw sums D = sum_k N_k
  // and S = sum_k c_k N_k in the point's frame at p * width; then the rational normalization,
  // once per point rather than per function: R = S / D, dR = (dS - R dD) / D,
  // d2R = (d2S - R d2D - dR dD^T - dD dR^T) / D.
  const int stride = Parts * width;
  // In chunks: gather the chunk's points, evaluate them into a contiguous buffer, scatter the
  // results; the gathers and scatters, free of dependencies, overlap their cache misses.
  constexpr std::size_t kChunk = 1024;
  std::vector<Eigen::Vector2d> chunkPoints(std::min(points.size(), kChunk));
  std::vector<double> results(chunkPoints.size() * std::size_t(stride));
  std::vector<double> frameSum(static_cast<std::size_t>(stride));
  thread_local TriangleBasis basis;
  // Where only a face's own functions reach (polynomialFrom_), D and S are polynomials: row m
  // (a monomial x^a y^b in BivariatePolynomial's order) of `polynomial` holds their coefficients.
  const int monomials = BivariatePolynomial::monomialCount(degree_);
  RowMatrix polynomial;
  int polynomialFace = -1;
  std::vector<double> monomial(std::size_t(Parts * monomials));
  const auto monomialWeight = [&monomial, monomials](int p, int m) {
    return monomial[std::size_t(p * monomials + m)];
  };
  std::array<double, 11> px{}, py{};
  Eigen::MatrixXd* outputs[6] = {&samples.position, &samples.du,  &samples.dv,
                                 &samples.duu,      &samples.duv, &samples.dvv};
  for (std::size_t begin = 0; begin < points.size(); begin += kChunk) {
    const std::size_t end = std::min(points.size(), begin + kChunk);
    for (std::size_t i = begin; i < end; ++i) {
      const SurfacePoint& point = points[std::size_t(order[i])];
      const auto& corners = corners_[std::size_t(point.face)];
      chunkPoints[i - begin] = point.barycentric[0] * corners[0] +
                               point.barycentric[1] * corners[1] +
                               point.barycentric[2] * corners[2];
    }
    for (std::size_t i = begin; i < end; ++i) {
      const int face = points[std::size_t(order[i])].face;
      double* sum = results.data() + (i - begin) * std::size_t(stride);
      std::fill(sum, sum + stride, 0.0);
      const Eigen::Vector2d& x = chunkPoints[i - begin];
      const std::array<double, 3> lambda = barycentricAt(face, x);
      const auto& from = polynomialFrom_[std::size_t(face)];
      if (lambda[0] > from[0] && lambda[1] > from[1] && lambda[2] > from[2]) {
        if (face != polynomialFace) {
          polynomial = faceSpaces_[std::size_t(face)].trianglePolynomials(0).coefficients *
                       rows.middleRows(Eigen::Index(face) * perFace_, perFace_);
          polynomialFace = face;
        }
        // x from the face's first corner, the origin of its frame.
        px[0] = py[0] = 1.0;
        for (int e = 1; e <= degree_; ++e) {
          px[std::size_t(e)] = px[std::size_t(e - 1)] * x.x();
          py[std::size_t(e)] = py[std::size_t(e - 1)] * x.y();
        }
        const auto power = [](const std::array<double, 11>& p, int e) {
          return e >= 0 ? p[std::size_t(e)] : 0.0;
        };
        for (int total = 0, m = 0; total <= degree_; ++total)
          for (int b = 0; b <= total; ++b, ++m) {
            const int a = total - b;
            double* w = monomial.data() + m;
            w[0] = px[std::size_t(a)] * py[std::size_t(b)];
            if (Parts >= 3) {
              w[monomials] = a * power(px, a - 1) * py[std::size_t(b)];
              w[2 * monomials] = b * px[std::size_t(a)] * power(py, b - 1);
            }
            if (Parts >= 6) {
              w[3 * monomials] = a * (a - 1) * power(px, a - 2) * py[std::size_t(b)];
              w[4 * monomials] = a * b * power(px, a - 1) * power(py, b - 1);
              w[5 * monomials] = b * (b - 1) * px[std::size_t(a)] * power(py, b - 2);
            }
          }
        addWeighted<Parts, Width>(monomials, polynomial.data(), width, monomialWeight, sum);
      } else {
        visitContributors(
            face, x, lambda, derivatives, basis,
            [&](const Contributor& contributor, const TriangleBasis& values) {
              const double* weights =
                  rows.data() + std::size_t(contributor.face) * std::size_t(perFace_ * width);
              const double* value = values.value.data();
              const double* gradient = values.gradient.data();
              const double* hessian = values.hessian.data();
              const auto basisWeight = [=](int p, int k) {
                if (p == 0) return value[k];
                if (p <= 2) return gradient[2 * k + p - 1];
                return hessian[3 * k + p - 3];
              };
              if (Parts == 1) {
                addWeighted<Parts, Width>(perFace_, weights, width, basisWeight, sum);
                return;
              }
              // The sums in the contributor's frame, then turned into the point's: y = R x + t
              // (values need no turning).
              std::fill(frameSum.begin(), frameSum.end(), 0.0);
              addWeighted<Parts, Width>(perFace_, weights, width, basisWeight, frameSum.data());
              const Eigen::Matrix2d& r = contributor.rotation;
              for (int c = 0; c < width; ++c) {
                const double* own = frameSum.data() + c;
                const Eigen::Vector2d g =
                    r.transpose() * Eigen::Vector2d(own[width], own[2 * width]);
                sum[c] += own[0];
                sum[width + c] += g.x();
                sum[2 * width + c] += g.y();
                if (Parts >= 6) {
                  const Eigen::Matrix2d h = r.transpose() *
                                            (Eigen::Matrix2d() << own[3 * width], own[4 * width],
                                             own[4 * width], own[5 * width])
                                                .finished() *
                                            r;
                  sum[3 * width + c] += h(0, 0);
                  sum[4 * width + c] += h(0, 1);
                  sum[5 * width + c] += h(1, 1);
                }
              }
            });
      }
      const double denominator = sum[0];
      if (!(denominator > 0.0))
        throw InputError(
            "triangular B-spline: the spline is undefined at a cone point (domain face " +
            std::to_string(face) + ")");
      const double inverse = 1.0 / denominator;
      for (int d = 1; d <= dims; ++d) {
        double* part = sum + d;
        const double value = part[0] * inverse;
        part[0] = value;
        if (Parts >= 3) {
          const double du = (part[width] - value * sum[width]) * inverse;
          const double dv = (part[2 * width] - value * sum[2 * width]) * inverse;
          if (Parts >= 6) {
            part[3 * width] =
                (part[3 * width] - value * sum[3 * width] - 2.0 * du * sum[width]) * inverse;
            part[4 * width] =
                (part[4 * width] - value * sum[4 * width] - du * sum[2 * width] - dv * sum[width]) *
                inverse;
            part[5 * width] =
                (part[5 * width] - value * sum[5 * width] - 2.0 * dv * sum[2 * width]) * inverse;
          }
          part[width] = du;
          part[2 * width] = dv;
        }
      }
    }
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Index k = order[i];
      const double* sum = results.data() + (i - begin) * std::size_t(stride);
      for (int p = 0; p < Parts; ++p)
        for (int d = 0; d < dims; ++d) (*outputs[p])(k, d) = sum[p * width + 1 + d];
      if (Parts >= 3 && dims == 3) {
        const double* du = sum + width + 1;
        const double* dv = sum + 2 * width + 1;
        const Eigen::Vector3d normal =
            Eigen::Vector3d(du[0], du[1], du[2]).cross(Eigen::Vector3d(dv[0], dv[1], dv[2]));
        const double length = normal.norm();
        samples.normal.row(k) = length > 0.0 ? Eigen::RowVector3d(normal.transpose() / length)
                                             : Eigen::RowVector3d::Zero();
      }
    }
  }
}

Eigen::VectorXd TriBSplineSpace::evaluateInChart(const Eigen::MatrixXd& control,
                                                 const SurfacePoint& point, int holder,
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
