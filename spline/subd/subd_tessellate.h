#pragma once
// The Catmull-Clark limit surface of a T-mesh's net as a triangle mesh, sampled like a T-spline
// (spline/tspline/tspline_tessellate.h).
#include <Eigen/Core>

#include "mspline/spline/subd/subd_fit_space.h"
#include "mspline/spline/tspline/tspline_tessellate.h"

namespace mspline::spline {

/// Samples the Catmull-Clark limit surface of `control` (numBasis x 3, the net point of each
/// T-mesh vertex) as tessellateTSpline does; holes only where the space has no surface (faces
/// at an open boundary under BoundaryRule::None). Throws InputError for a resolution below 1,
/// wrong sizes, or a face without surface.
TMeshTessellation tessellateSubd(const SubdSpace& space, const Eigen::MatrixXd& control,
                                 int resolution);

}  // namespace mspline::spline
