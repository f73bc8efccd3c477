#pragma once
// A T-spline (tspline.h) as a FitSpace: its rational blending functions w_i N_i / sum_j w_j N_j
// with derivatives, walks on its T-mesh (tmesh_walk.h) and a 4 x 4 Gauss rule per face.
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/fitting/fit_space.h"
#include "mspline/spline/tspline/tspline.h"

namespace mspline::spline {

/// What every spline on a T-mesh uses as FitSpace::faceSize and FitSpace::quadrature: the longer
/// side of the face, and a 4 x 4 Gauss-Legendre rule per face.
double tmeshFaceSize(const TMesh& mesh, int face);
void tmeshQuadrature(const TMesh& mesh, std::vector<FacePoint>& nodes,
                     std::vector<double>& weights);

class TSplineFitSpace : public FitSpace {
 public:
  /// `weights`: one per blending function, or empty for all 1. Keeps references: `space` and
  /// `weights` must outlive this object.
  TSplineFitSpace(const TSplineSpace& space, const Eigen::VectorXd& weights);
  int numBasis() const override { return space_.numBasis(); }
  void basisAt(const FacePoint& p, std::vector<FitBasisTerm>& out, int derivatives) const override;
  FacePoint walk(const FacePoint& p, const Eigen::Vector2d& step) const override;
  double faceSize(int face) const override;
  void quadrature(std::vector<FacePoint>& nodes, std::vector<double>& weights) const override;

 private:
  const TSplineSpace& space_;
  const Eigen::VectorXd& weights_;
};

}  // namespace mspline::spline
