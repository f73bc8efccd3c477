#pragma once
// How far the normals of a T-spline surface spread right around its cones. The caps (tspline_cap.h)
// give every cone a unique normal, so the spread at a distance is the surface's own turning there:
// it vanishes like the distance. Measured 1e-3 cells away it passes 1e-3 rad where a cap cell
// turns the normal by more than about half a radian; cones sit where curvature concentrates (ear
// rims, horn tips, box corners), and on fitted scans most of them do.
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tspline.h"

namespace mspline::spline {

struct ConeNormalSpread {
  /// The cone (T-mesh vertex), its valence and the side of its cap's cells (knot intervals).
  int vertex = -1;
  int valence = 0;
  double cellSize = 0.0;
  /// The largest angle between the normals `offset` cells from the cone in at least 8 directions,
  /// spread evenly over each face around it (4 per face at valence 2, 3 at valence 3, 2 above);
  /// radians, pi where a normal is undefined.
  double spread = 0.0;
};

/// Per cone with cap faces, in increasing vertex order (none unless the control points are in
/// 3-space). `offset` is a fraction of the cap's cell.
std::vector<ConeNormalSpread> coneNormalSpreads(const TSplineSpace& space,
                                                const Eigen::MatrixXd& control,
                                                const Eigen::VectorXd& weights,
                                                double offset = 1e-3);

}  // namespace mspline::spline
