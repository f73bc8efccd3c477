#pragma once
// Which parts of a tessellated spline surface lie over the scan and which over the patches that
// closed its holes (structure/mesh/cap_holes.h): export trims the latter away, and fit measures the
// surface against the scan only where there is scan.
#include <vector>

#include "mspline/spline/core/spline_model.h"
#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::spline {

/// The spline of `model` at each surface vertex's parameters (its T-mesh point or domain point);
/// NaN rows where the spline is undefined (a cone point).
Eigen::MatrixX3d surfaceVertexSpline(const SplineModel& model);

/// surfaceVertexSpline with the undefined rows replaced by the vertices' own positions.
Eigen::MatrixX3d surfaceVertexImages(const SplineModel& model);

/// Per face of `tessellation` (triangles of the evaluated surface of `model`): 1 when the face of
/// the model's surface mesh carried onto the spline (its vertices moved to surfaceVertexImages)
/// that is closest to the face's centroid is not filled. Classifying on the spline itself, not
/// on the mesh, keeps a fill that bulges differently from the mesh's patch on the right side.
/// Where the scan and a fill are equally near (within 1e-3 of the diagonal: a fill lying on the
/// scan), the one whose nearest triangle faces the same way as the face decides. All 1 when the
/// model has no filled faces.
std::vector<char> facesOverScan(const structure::PolygonSoup& tessellation,
                                const SplineModel& model);

/// Clears `keep` for faces that would make a vertex non-manifold once the others are dropped: at
/// every vertex whose kept faces form several fans (joined only at the vertex), all but the
/// largest fan go. Trimming along a jagged line can leave such bow-ties.
void dropBowTies(const structure::PolygonSoup& soup, std::vector<char>& keep);

/// Per face of `tessellation` (triangles of the evaluated surface of `model`) 1 when it stays
/// once the fills are trimmed: facesOverScan less the bow-ties that dropping the others would
/// leave (dropBowTies).
std::vector<char> facesToKeep(const structure::PolygonSoup& tessellation, const SplineModel& model);

/// Keeps the faces of `soup` marked in `keep` and the vertices they use (renumbered in order, with
/// their per-corner UVs); returns per old vertex its new index or -1.
std::vector<int> keepFaces(structure::PolygonSoup& soup, const std::vector<char>& keep);

}  // namespace mspline::spline
