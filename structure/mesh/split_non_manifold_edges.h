#pragma once
// Splits the edges shared by 3 or more faces, so that no face is removed: each consistently
// oriented pair of faces around such an edge keeps a copy of it of its own, and every other face is
// detached there (a boundary, unless its fans around both ends join it to another detached face
// anyway). Removing the fewest faces instead would also leave a valid mesh, but it punches holes
// where the scan has surface and picks the faces to lose arbitrarily; splitting keeps every face
// and separates solids that merely touch along an edge, as splitting a bow-tie vertex does.
#include <cstddef>

#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::structure {

struct SplitNonManifoldEdgesOptions {
  /// Keep pairs of faces glued at a non-manifold edge (true), or give every face its own copy of
  /// such an edge, all of them detached (false). Pairs are taken around the edge in angular
  /// order: a face traversing the edge backwards is glued to the next face counterclockwise (about
  /// the edge's direction from its smaller to its larger vertex) when that face traverses it
  /// forwards, so each pair is consistently oriented and encloses the space behind both faces'
  /// normals: two closed solids sharing an edge become two closed solids.
  bool pairFaces = true;
};

struct SplitNonManifoldEdgesResult {
  /// The soup with the edges split: faces keep their order and corners, only the vertex indices at
  /// non-manifold edges change; copied vertices are appended after the existing ones.
  PolygonSoup soup;
  /// Non-manifold edges found (edges of usable faces, as validate() defines them, used by 3 or
  /// more faces); none remains afterwards.
  std::size_t edgesSplit = 0;
  /// Pairs of faces that still share a copy of a split edge.
  std::size_t pairsKept = 0;
  /// (Face, edge) incidences left out of a pair at a split edge: the face's copy of the edge is a
  /// boundary unless its fans around both ends hold another such face (then the two share it).
  std::size_t facesDetached = 0;
  /// Split edges whose pairs could not be separated by their vertex fans (the pairs met again
  /// around both ends), so every face there was detached instead; also counted in facesDetached.
  std::size_t edgesFullyDetached = 0;
  /// Vertices appended: at each end of a split edge, one per fan of faces beyond the first (faces
  /// connected around the vertex through manifold edges and kept pairs), which also splits any
  /// bow-tie at those vertices.
  std::size_t verticesAdded = 0;
};

/// Splits every non-manifold edge as described above. Faces that are not usable (index out of
/// range, fewer than 3 vertices, a repeated vertex, a duplicate) are left as they are, so remove
/// those first (repair() does): on a soup of usable faces validate() afterwards reports no
/// non_manifold_edge and no non_manifold_vertex at the split edges' vertices and their copies.
/// Linear in the soup's size plus a sort of the faces around each split edge.
SplitNonManifoldEdgesResult splitNonManifoldEdges(PolygonSoup soup,
                                                  const SplitNonManifoldEdgesOptions& options = {});

}  // namespace mspline::structure
