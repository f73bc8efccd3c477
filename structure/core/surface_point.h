#pragma once
// A point anywhere on a triangle mesh: a face and barycentric coordinates in it.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct SurfacePoint {
  /// Face index.
  int face = -1;
  /// Weights of the face's corners, in the order of its vertex circulator (corner k is the k-th
  /// vertex of fv_range, as FlatLayout::cornerUV); >= 0, summing to 1.
  Eigen::Vector3d barycentric = Eigen::Vector3d::Constant(1.0 / 3.0);
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
