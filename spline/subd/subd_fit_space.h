#pragma once
// The Catmull-Clark limit surface of a T-mesh's control net as a linear space: the baseline the
// T-spline fits are compared with. On a T-mesh without T-junctions every face is a quad and every
// vertex a net point (tspline_osd.h's catmullClarkNetFaces); OpenSubdiv refines the net around
// extraordinary vertices and caps what is left with Gregory patches, and every patch point is a
// fixed combination of net points (its refinement or end-cap stencil). The limit surface is
// therefore sum_v c_v B_v with one function B_v per T-mesh vertex, evaluated here in double
// precision: the patch basis of OpenSubdiv's Far layer times the stencils, the same surface as
// CatmullClarkLimit of the same net and options.
//
// Parameters: point (x, y) of T-mesh face f is (u, v) = (x / width, y / height) of patch face f,
// as in tspline_osd.h; derivatives are along the face frame's axes (d/dx = d/du / width). On a
// uniform grid (unit knot intervals) B_v is the T-spline's uniform bicubic B-spline of vertex v.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/fitting/fit_space.h"
#include "mspline/spline/subd/catmull_clark_limit.h"
#include "mspline/spline/tspline/tmesh.h"

namespace mspline::spline {

/// The limit surface functions of a T-mesh without T-junctions. Immutable; evaluation may run on
/// several threads at once.
class SubdSpace {
 public:
  /// Builds OpenSubdiv's adaptive refinement, patch table and stencils of the net (options as
  /// CatmullClarkLimit's: by default the surface reaches an open boundary and its corners).
  /// Throws InputError when the T-mesh has T-junctions or CatmullClarkLimit would reject the
  /// net or the options.
  explicit SubdSpace(TMesh mesh, const CatmullClarkOptions& options = {});
  ~SubdSpace();
  SubdSpace(SubdSpace&&) noexcept;
  SubdSpace& operator=(SubdSpace&&) noexcept;

  const TMesh& mesh() const;
  /// One function per T-mesh vertex.
  int numBasis() const;
  /// The functions that are non-zero at p of `face` (its frame; p is clamped into the face's
  /// rectangle), each index once, with derivatives: 0 none, 1 first, 2 first and second. Empty
  /// where the face has no limit surface (next to the boundary under BoundaryRule::None).
  /// Throws InputError for a face out of range or a non-finite p.
  void basisAt(int face, const Eigen::Vector2d& p, std::vector<FitBasisTerm>& out,
               int derivatives = 0) const;
  /// The surface of `control` (numBasis x 3) at p of `face`, with its first derivatives along the
  /// frame's axes when ds and dt are given; false (and nothing written) where the face has no
  /// limit surface. Throws InputError as basisAt, and for control of the wrong size.
  bool evaluate(const Eigen::MatrixXd& control, int face, const Eigen::Vector2d& p,
                Eigen::Vector3d& position, Eigen::Vector3d* ds = nullptr,
                Eigen::Vector3d* dt = nullptr) const;

 private:
  struct Tables;
  std::unique_ptr<Tables> tables_;
};

/// A SubdSpace as a FitSpace: its functions (a partition of unity, so no normalization), walks
/// on its T-mesh (tmesh_walk.h) and a 4 x 4 Gauss-Legendre rule per face.
class SubdFitSpace : public FitSpace {
 public:
  /// Keeps a reference: `space` must outlive this object.
  explicit SubdFitSpace(const SubdSpace& space) : space_(space) {}
  int numBasis() const override { return space_.numBasis(); }
  void basisAt(const FacePoint& p, std::vector<FitBasisTerm>& out, int derivatives) const override;
  FacePoint walk(const FacePoint& p, const Eigen::Vector2d& step) const override;
  double faceSize(int face) const override;
  void quadrature(std::vector<FacePoint>& nodes, std::vector<double>& weights) const override;
  const SubdSpace& space() const { return space_; }

 private:
  const SubdSpace& space_;
};

}  // namespace mspline::spline
