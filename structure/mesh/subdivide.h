#pragma once
// 1-to-4 midpoint subdivision: every triangle splits into four, new vertices at edge midpoints.
// The surface (as a point set) is unchanged; only the sampling gets finer.
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

/// Returns the subdivided mesh: the old vertices keep their indices 0..V-1, then one new vertex per
/// edge in edge-index order (vertex V + e sits on edge e). Faces are 4x as many: faces 4f to
/// 4f + 3 are face f's (its corners, then its centre).
TriMesh subdivideMidpoint(const TriMesh& mesh);

/// Applies subdivideMidpoint until the mesh has at least `minFaces` faces.
TriMesh subdivideToAtLeast(const TriMesh& mesh, std::size_t minFaces);

}  // namespace mspline::structure
