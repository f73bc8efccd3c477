#pragma once
// A manifold triangular B-spline (tri_bspline.h) as a FitSpace: its rationally normalized basis
// with derivatives in the frame of the point's face, walks along straight segments of the flat
// domain (across sides by the rigid transitions between the faces' frames, stopping at cones) and
// Dunavant's 7-point rule on each of a face's 4 midpoint triangles (nodes next to cones, where
// the normalization's denominator is below 1/2, left out).
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/fitting/fit_space.h"
#include "mspline/spline/tribspline/spline_domain.h"
#include "mspline/spline/tribspline/tri_bspline.h"

namespace mspline::spline {

/// The fit parameter of a domain point: its face and its position in that face's frame
/// (TriBSplineSpace::framePosition). InputError for a face out of range.
FacePoint toFitParameter(const TriBSplineSpace& space, const SurfacePoint& point);
/// The domain point of a fit parameter (barycentric coordinates from the frame position).
/// InputError for a face out of range.
SurfacePoint toDomainPoint(const TriBSplineSpace& space, const FacePoint& p);

class TriBSplineFitSpace : public FitSpace {
 public:
  /// Keeps a reference: `space` must outlive this object.
  explicit TriBSplineFitSpace(const TriBSplineSpace& space);
  int numBasis() const override { return space_.numBasis(); }
  void basisAt(const FacePoint& p, std::vector<FitBasisTerm>& out, int derivatives) const override;
  FacePoint walk(const FacePoint& p, const Eigen::Vector2d& step) const override;
  /// walk, and `turnedStep` receives `step` turned into the frame of the face reached (walking
  /// back by -turnedStep from there returns to `p`, unless a cone stopped the walk).
  FacePoint walk(const FacePoint& p, const Eigen::Vector2d& step,
                 Eigen::Vector2d& turnedStep) const;
  double faceSize(int face) const override;
  void quadrature(std::vector<FacePoint>& nodes, std::vector<double>& weights) const override;

 private:
  const TriBSplineSpace& space_;
};

}  // namespace mspline::spline
