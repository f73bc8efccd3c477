#pragma once
// What fitting (surface_fit.h) needs of a spline space, whatever its kind: the functions the
// surface is a linear combination of, with derivatives, at a point of the parameter domain; a way
// to move a point across the domain's faces (parameter correction walks the surface); and a
// quadrature over the domain (the fairing energy). Implemented for T-splines (tspline_fit_space.h),
// triangular B-splines (tri_bspline_fit_space.h) and Catmull-Clark limit surfaces
// (subd_fit_space.h).
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/surface_point.h"

namespace mspline::spline {

using structure::FacePoint;
using structure::SurfacePoint;

/// One function of the space at a point, with derivatives along the axes of the point's face
/// frame (zero when not asked for).
struct FitBasisTerm {
  int index = -1;
  double value = 0.0;
  double ds = 0.0, dt = 0.0, dss = 0.0, dst = 0.0, dtt = 0.0;
};

class FitSpace {
 public:
  virtual ~FitSpace() = default;
  /// Number of functions (= control points).
  virtual int numBasis() const = 0;
  /// The functions that are non-zero at `p`, any rational normalization included (the surface is
  /// sum_k c_k value_k), with derivatives: 0 none, 1 first, 2 first and second. Leaves `out`
  /// empty where the surface is undefined (a cone point, a hole).
  virtual void basisAt(const FacePoint& p, std::vector<FitBasisTerm>& out,
                       int derivatives) const = 0;
  /// The point reached from `p` by the straight segment p.position + step of p.face's frame,
  /// continued across face sides in the neighbouring faces' frames (the direction turned with
  /// them). Stops where the segment leaves the domain (an open boundary) or would run into a
  /// cone; the result is then the last point reached.
  virtual FacePoint walk(const FacePoint& p, const Eigen::Vector2d& step) const = 0;
  /// A typical length of `face` in its frame: a Newton step of parameter correction moves at most
  /// this far (where the surface is nearly singular, as around a cone's hole, a short move in
  /// space can be a very long one in the parameters).
  virtual double faceSize(int face) const = 0;
  /// Quadrature nodes and weights for integrals over the whole domain, each node's weight the
  /// area element of its face's frame times the rule's weight (exact for polynomials of degree
  /// 3 in each variable on each face is plenty for the fairing energy).
  virtual void quadrature(std::vector<FacePoint>& nodes, std::vector<double>& weights) const = 0;
};

}  // namespace mspline::spline
