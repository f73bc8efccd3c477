#include "mspline/spline/tspline/tspline_bezier.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/LU>

#include "mspline/spline/core/cubic_bspline.h"
#include "mspline/spline/tspline/tspline_cap.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;

namespace {

// Bernstein coefficients from values at these parameters: inside the interval, so that the
// half-open supports of the B-splines never pick the neighbouring polynomial piece.
constexpr std::array<double, 4> kSampleParameters = {0.125, 0.375, 0.625, 0.875};

const Eigen::Matrix4d& valuesToBernstein() {
  static const Eigen::Matrix4d inverse = [] {
    Eigen::Matrix4d collocation;
    for (int r = 0; r < 4; ++r) {
      double b[4];
      cubicBernstein(kSampleParameters[r], b);
      for (int c = 0; c < 4; ++c) collocation(r, c) = b[c];
    }
    return Eigen::Matrix4d(collocation.inverse());
  }();
  return inverse;
}

std::vector<double> splitLines(double length, std::vector<double> lines, double tolerance) {
  lines.push_back(0.0);
  lines.push_back(length);
  std::sort(lines.begin(), lines.end());
  std::vector<double> kept;
  for (double x : lines) {
    if (x < -tolerance || x > length + tolerance) continue;
    x = std::clamp(x, 0.0, length);
    if (kept.empty() || x > kept.back() + tolerance) kept.push_back(x);
  }
  kept.back() = length;  // a line within tolerance of the far side is the side
  return kept;
}

// Bernstein coefficients of a cubic B-spline on [lo, hi], where it is one polynomial.
std::array<double, 4> bernsteinOf(const std::array<double, 5>& knots, double lo, double hi) {
  Eigen::Vector4d values;
  for (int r = 0; r < 4; ++r)
    values[r] = cubicBSpline(knots.data(), lo + kSampleParameters[r] * (hi - lo));
  const Eigen::Vector4d c = valuesToBernstein() * values;
  return {c[0], c[1], c[2], c[3]};
}

}  // namespace

TSplineBezier::TSplineBezier(const TSplineSpace& space, const Eigen::MatrixXd& control,
                             const Eigen::VectorXd& weights) {
  if (control.rows() != space.numBasis() || control.cols() != 3)
    throw InputError("Bezier extraction: control points must be " +
                     std::to_string(space.numBasis()) + " x 3");
  if (weights.size() != 0 && weights.size() != space.numBasis())
    throw InputError("Bezier extraction: weights do not match the blending functions");
  const TMesh& mesh = space.mesh();
  first_.assign(1, 0);
  splitsX_.resize(mesh.faces.size());
  splitsY_.resize(mesh.faces.size());
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const TMeshFace& face = mesh.faces[f];
    const double tolerance = 1e-9 * std::max(face.width, face.height);
    if (const TSplineCapFace* cap = space.capFace(f)) {
      BezierElement element;
      element.face = f;
      element.hi = {face.width, face.height};
      element.points.setZero();
      for (std::size_t m = 0; m < cap->anchors.size(); ++m) {
        const int anchor = cap->anchors[m];
        const double w = weights.size() ? weights[anchor] : 1.0;
        Eigen::RowVector4d homogeneous;
        homogeneous << w * control.row(anchor), w;
        element.points += cap->bezier.col(Eigen::Index(m)) * homogeneous;
      }
      splitsX_[f] = {0.0, face.width};
      splitsY_[f] = {0.0, face.height};
      elements_.push_back(element);
      first_.push_back(static_cast<int>(elements_.size()));
      continue;
    }
    std::vector<std::pair<int, FaceKnots2d>> factors;
    std::vector<double> xLines, yLines;
    for (const TSplinePiece& piece : space.pieces(f)) {
      const FaceKnots2d knots = knotsInFace(space.anchors()[piece.anchor], piece.toChart);
      factors.emplace_back(piece.anchor, knots);
      xLines.insert(xLines.end(), knots.xKnots.begin(), knots.xKnots.end());
      yLines.insert(yLines.end(), knots.yKnots.begin(), knots.yKnots.end());
    }
    splitsX_[f] = splitLines(face.width, xLines, tolerance);
    splitsY_[f] = splitLines(face.height, yLines, tolerance);
    const auto& xs = splitsX_[f];
    const auto& ys = splitsY_[f];
    for (std::size_t j = 0; j + 1 < ys.size(); ++j)
      for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
        BezierElement element;
        element.face = f;
        element.lo = {xs[i], ys[j]};
        element.hi = {xs[i + 1], ys[j + 1]};
        element.points.setZero();
        for (const auto& [anchor, knots] : factors) {
          const auto cx = bernsteinOf(knots.xKnots, xs[i], xs[i + 1]);
          const auto cy = bernsteinOf(knots.yKnots, ys[j], ys[j + 1]);
          if (std::all_of(cx.begin(), cx.end(), [](double c) { return c == 0.0; }) ||
              std::all_of(cy.begin(), cy.end(), [](double c) { return c == 0.0; }))
            continue;
          const double w = weights.size() ? weights[anchor] : 1.0;
          Eigen::RowVector4d homogeneous;
          homogeneous << w * control.row(anchor), w;
          for (int b = 0; b < 4; ++b)
            for (int a = 0; a < 4; ++a)
              element.points.row(4 * b + a) += cx[a] * cy[b] * homogeneous;
        }
        elements_.push_back(element);
      }
    first_.push_back(static_cast<int>(elements_.size()));
  }
}

void TSplineBezier::evaluate(int face, const Eigen::Vector2d& p, Eigen::Vector3d& position,
                             Eigen::Vector3d* ds, Eigen::Vector3d* dt, double* denominator) const {
  const auto& xs = splitsX_[face];
  const auto& ys = splitsY_[face];
  const std::size_t nx = xs.size() - 1, ny = ys.size() - 1;
  const std::size_t i = std::min<std::size_t>(
      nx - 1,
      std::max<std::ptrdiff_t>(0, std::upper_bound(xs.begin(), xs.end(), p.x()) - xs.begin() - 1));
  const std::size_t j = std::min<std::size_t>(
      ny - 1,
      std::max<std::ptrdiff_t>(0, std::upper_bound(ys.begin(), ys.end(), p.y()) - ys.begin() - 1));
  const BezierElement& e = elements_[static_cast<std::size_t>(first_[face]) + j * nx + i];
  const double width = e.hi.x() - e.lo.x(), height = e.hi.y() - e.lo.y();
  double bu[4], bv[4], du[4], dv[4];
  cubicBernstein((p.x() - e.lo.x()) / width, bu, du);
  cubicBernstein((p.y() - e.lo.y()) / height, bv, dv);
  Eigen::RowVector4d h = Eigen::RowVector4d::Zero(), hu = h, hv = h;
  for (int b = 0; b < 4; ++b) {
    Eigen::RowVector4d row = Eigen::RowVector4d::Zero(), rowU = row;
    for (int a = 0; a < 4; ++a) {
      row += bu[a] * e.points.row(4 * b + a);
      rowU += du[a] * e.points.row(4 * b + a);
    }
    h += bv[b] * row;
    hu += bv[b] * rowU;
    hv += dv[b] * row;
  }
  if (denominator) *denominator = h[3];
  if (!(h[3] > 0.0)) {
    position.setConstant(std::numeric_limits<double>::quiet_NaN());
    if (ds) *ds = position;
    if (dt) *dt = position;
    return;
  }
  position = h.head<3>().transpose() / h[3];
  if (ds) *ds = (hu.head<3>().transpose() - hu[3] * position) / (h[3] * width);
  if (dt) *dt = (hv.head<3>().transpose() - hv[3] * position) / (h[3] * height);
}

void TSplineBezier::evaluate(const std::vector<FacePoint>& points, Eigen::MatrixX3d& position,
                             Eigen::MatrixX3d& ds, Eigen::MatrixX3d& dt) const {
  const Eigen::Index n = static_cast<Eigen::Index>(points.size());
  position.resize(n, 3);
  ds.resize(n, 3);
  dt.resize(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const FacePoint& point = points[static_cast<std::size_t>(k)];
    if (point.face < 0 || point.face >= static_cast<int>(splitsX_.size()))
      throw InputError("Bezier evaluation: face " + std::to_string(point.face) + " out of range");
    Eigen::Vector3d x, u, v;
    evaluate(point.face, point.position, x, &u, &v);
    position.row(k) = x.transpose();
    ds.row(k) = u.transpose();
    dt.row(k) = v.transpose();
  }
}

}  // namespace mspline::spline
