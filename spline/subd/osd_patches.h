#pragma once
// OpenSubdiv's Far layer as CatmullClarkLimit and SubdSpace use it, in one place so that the two
// are one surface: a Catmull-Clark net refined adaptively around extraordinary vertices into a
// double-precision patch table whose irregular rest is capped by Gregory basis patches, and the
// weights of a patch's points at a parameter point with exact derivatives.
#include <memory>
#include <vector>

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/topologyRefiner.h>

#include "mspline/spline/subd/catmull_clark_limit.h"

namespace mspline::spline {

/// The largest patch OpenSubdiv builds for Catmull-Clark: a Gregory basis end cap.
constexpr int kMaxOsdPatchVertices = 20;

/// OpenSubdiv's tables of a net.
struct OsdPatches {
  /// Patch faces of base face f are firstPatchFace[f] .. firstPatchFace[f + 1] - 1: one for a
  /// quad, n for a face with n != 4 vertices.
  std::vector<int> firstPatchFace;
  /// Refined vertices of every level, the net's points first.
  std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> refiner;
  /// The patches, on the refined vertices and then the local points of the end caps (their
  /// stencils over the refined vertices in double precision).
  std::unique_ptr<OpenSubdiv::Far::PatchTable> patchTable;
  /// Finds the patch at (u, v) of a patch face.
  std::unique_ptr<OpenSubdiv::Far::PatchMap> patchMap;
};

/// Throws InputError, naming `source`, for an isolation level outside 1..10.
void checkIsolationLevel(const CatmullClarkOptions& options, const char* source);

/// Builds the tables of the net with `numVertices` points and polygons `faces` (already checked:
/// indices in range, manifold, consistently oriented), with options.boundary and
/// options.isolationLevel (checked by checkIsolationLevel). Patch faces are as in
/// CatmullClarkLimit. Throws InputError naming `source` when OpenSubdiv rejects the topology.
OsdPatches buildOsdPatches(int numVertices, const std::vector<std::vector<int>>& faces,
                           const CatmullClarkOptions& options, const char* source);

/// The weights of the patch's points at (u, v) of its patch face: w[0] the position, w[1], w[2]
/// the derivatives per unit of the patch face's u and v, w[3..5] (with `second`) the uu, uv and
/// vv ones. On Gregory end caps the rational weights are differentiated exactly (OpenSubdiv's
/// EvaluateBasis is about 1% off), and on non-quads' sub-faces OpenSubdiv 3.5's derivative scale
/// (twice too large) is corrected. Returns the patch's points.
OpenSubdiv::Far::ConstIndexArray osdPatchWeights(
    const OpenSubdiv::Far::PatchTable& table,
    const OpenSubdiv::Far::PatchTable::PatchHandle& handle, double u, double v,
    double (*w)[kMaxOsdPatchVertices], bool second);

}  // namespace mspline::spline
