#pragma once
// Bezier extraction of a T-spline (Scott et al. 2011): every face is cut along the knot lines of
// the blending functions over it into elements on which each function is one bicubic polynomial;
// on each element the rational surface is one rational bicubic Bezier patch with 16 homogeneous
// control points. Evaluating a patch costs the same everywhere, whatever the T-mesh looks like,
// and the patches are what CAD formats take. A cap face (around an extraordinary vertex) is one
// element, its patch.
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tspline.h"

namespace mspline::spline {

/// One element: a rectangle of its face's frame and its rational Bezier patch.
struct BezierElement {
  int face = -1;
  Eigen::Vector2d lo = Eigen::Vector2d::Zero();
  Eigen::Vector2d hi = Eigen::Vector2d::Zero();
  /// Homogeneous control points (w x, w y, w z, w), row 4 j + i for Bernstein B_i(u) B_j(v),
  /// u = (x - lo.x) / (hi.x - lo.x) and v likewise.
  Eigen::Matrix<double, 16, 4> points;
};

/// The Bezier elements of a surface in 3-space; evaluation is read-only and thread-safe.
class TSplineBezier {
 public:
  /// Extracts the elements of the surface with `control` (numBasis x 3) and `weights` (numBasis,
  /// or empty for all 1). Throws InputError for wrong sizes.
  TSplineBezier(const TSplineSpace& space, const Eigen::MatrixXd& control,
                const Eigen::VectorXd& weights = {});

  int numElements() const { return static_cast<int>(elements_.size()); }
  const std::vector<BezierElement>& elements() const { return elements_; }
  /// Elements of face f: elementsOfFace()[f] .. elementsOfFace()[f + 1] - 1, a grid of
  /// splitsX[f].size() - 1 by splitsY[f].size() - 1, x fastest.
  const std::vector<int>& firstElement() const { return first_; }

  /// Position and, when asked for, first derivatives along the face frame's axes and the
  /// denominator sum_i w_i N_i at p (in face f's frame, inside its rectangle). In a hole
  /// (denominator 0) the position and derivatives are NaN.
  void evaluate(int face, const Eigen::Vector2d& p, Eigen::Vector3d& position,
                Eigen::Vector3d* ds = nullptr, Eigen::Vector3d* dt = nullptr,
                double* denominator = nullptr) const;
  /// The same for many points, one row each.
  void evaluate(const std::vector<FacePoint>& points, Eigen::MatrixX3d& position,
                Eigen::MatrixX3d& ds, Eigen::MatrixX3d& dt) const;

 private:
  std::vector<BezierElement> elements_;
  std::vector<int> first_;
  std::vector<std::vector<double>> splitsX_, splitsY_;
};

}  // namespace mspline::spline
