#pragma once
// A point on a triangulated surface given by a face and barycentric coordinates in it (any
// triangulation: a mesh, a coarse triangulation, a spline domain, a chart's star), and a point of
// a surface of faces given by a face and a position in that face's own frame (a T-mesh rectangle,
// a spline domain face's home chart): the one type of each kind every layer uses.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct SurfacePoint {
  /// Face index (-1: no face, e.g. a point outside a chart).
  int face = -1;
  /// Weights of the face's corners, summing to 1, in the order the triangulation lists them (for
  /// a TriMesh the vertex circulator: corner k is the k-th vertex of fv_range, as
  /// FlatLayout::cornerUV).
  Eigen::Vector3d barycentric = Eigen::Vector3d::Constant(1.0 / 3.0);
};

struct FacePoint {
  /// Face index.
  int face = -1;
  /// Position in the face's own frame.
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
};

/// Throws InputError "<what>: ..." unless the face exists in `mesh` and the coordinates are finite,
/// >= -1e-12 and sum to 1 within 1e-9.
void checkSurfacePoint(const TriMesh& mesh, const SurfacePoint& point, const std::string& what);

/// `count` points uniformly distributed in random faces (face chosen uniformly, point uniform in
/// it), reproducible from `seed`.
std::vector<SurfacePoint> randomSurfacePoints(const TriMesh& mesh, int count, unsigned seed);

/// The point's position in space (a valid point of `mesh`).
Eigen::Vector3d surfacePosition(const TriMesh& mesh, const SurfacePoint& point);

}  // namespace mspline::structure
