#include "mspline/spline/subd/subd_tessellate.h"

#include <string>

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;

TMeshTessellation tessellateSubd(const SubdSpace& space, const Eigen::MatrixXd& control,
                                 int resolution) {
  if (control.rows() != space.numBasis() || control.cols() != 3)
    throw InputError("subdivision surface tessellation: control points must be " +
                     std::to_string(space.numBasis()) + " x 3, got " +
                     std::to_string(control.rows()) + " x " + std::to_string(control.cols()));
  const auto surface = [&](int f, const Eigen::Vector2d& p, Eigen::Vector3d& x,
                           Eigen::Vector3d* normal) {
    Eigen::Vector3d ds, dt;
    if (!space.evaluate(control, f, p, x, normal ? &ds : nullptr, normal ? &dt : nullptr))
      return false;
    if (normal) *normal = unitNormal(ds, dt);
    return true;
  };
  return tessellateTMeshSurface(space.mesh(), surface, resolution,
                                "subdivision surface tessellation");
}

}  // namespace mspline::spline
