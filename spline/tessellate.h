#pragma once
// The spline surface as a triangle mesh: every domain face sampled on a regular barycentric grid,
// the samples on shared sides and vertices computed once and shared, so the mesh is watertight.
#include <vector>

#include <Eigen/Core>

#include "spline/tri_bspline.h"
#include "structure/polygon_soup.h"

namespace mspline::spline {

struct Tessellation {
  /// The surface's triangles (resolution^2 per domain face), counter-clockwise like the domain.
  structure::PolygonSoup mesh;
  /// Smallest denominator (sum of the raw basis functions) met at a sample.
  double minDenominator = 0.0;
  /// Cone vertices, where the spline is undefined: their samples are the mean of the spline at
  /// the points `coneOffset` (barycentric) into each face around them.
  int coneVertices = 0;
  double coneOffset = 0.0;
};

/// Samples the spline with control points `control` (3 columns) `resolution` times along every
/// side of every domain face (resolution >= 1; InputError otherwise).
Tessellation tessellate(const TriBSplineSpace& space, const Eigen::MatrixXd& control,
                        int resolution);

}  // namespace mspline::spline
