#pragma once
// Checks a polygon soup for every defect that stops it from being a clean manifold triangle mesh.
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::structure {

/// One kind of defect found in the input, with the offending elements.
struct MeshProblem {
  /// Stable identifier, snake_case: face_index_out_of_range, too_few_face_vertices,
  /// non_finite_coordinate, non_manifold_edge, non_manifold_vertex, degenerate_face,
  /// duplicate_face, inconsistent_orientation, unreferenced_vertex, multiple_components,
  /// empty_mesh.
  std::string kind;
  /// How many elements have this defect: faces, vertices, edges (non_manifold_edge and
  /// inconsistent_orientation), components (multiple_components), or 1 for empty_mesh.
  std::size_t count = 0;
  /// Indices of the first offending elements, at most ValidationOptions::maxListed, ascending
  /// unless said otherwise: vertices for non_finite_coordinate, non_manifold_vertex and
  /// unreferenced_vertex; faces for the face kinds; for non_manifold_edge and
  /// inconsistent_orientation the faces at the first offending edges (edges taken in order of
  /// their first face); for multiple_components the first face of each component, largest
  /// component first; none for empty_mesh.
  std::vector<std::int64_t> elements;
  /// One line naming the source, the defect, the count and the first element indices.
  std::string message;
};

struct ValidationOptions {
  /// A face is degenerate when twice its area is at most this times its longest edge squared,
  /// i.e. when the sine of its largest angle is (almost) zero.
  double degenerateTolerance = 1e-12;
  /// How many element indices a problem lists.
  std::size_t maxListed = 10;
};

struct ValidationReport {
  /// Every defect found, one entry per kind, in this order: empty_mesh, face_index_out_of_range,
  /// too_few_face_vertices, non_finite_coordinate, non_manifold_edge, non_manifold_vertex,
  /// degenerate_face, duplicate_face, inconsistent_orientation, unreferenced_vertex,
  /// multiple_components. Empty for a clean mesh.
  std::vector<MeshProblem> problems;
  /// Counts on the soup as given (edges are distinct unordered vertex pairs of usable faces, see
  /// SoupConnectivity).
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t edges = 0;
  /// Connected components of faces sharing vertices (unreferenced vertices not counted).
  std::size_t components = 0;
  /// Whether the faces can be oriented consistently (meaningful when edges are manifold).
  bool orientable = true;

  bool ok() const { return problems.empty(); }
  /// The first problem's message followed by "; also: " and the other kinds, for a one-line
  /// error; "no problems" for a clean mesh.
  std::string summary() const;
};

/// Whether a problem kind keeps the faces from forming an oriented manifold mesh: empty_mesh,
/// face_index_out_of_range, too_few_face_vertices, non_manifold_edge, non_manifold_vertex,
/// duplicate_face, inconsistent_orientation.
bool preventsManifoldMesh(const std::string& kind);

/// Whether a problem kind makes the Euler characteristic, genus and boundary loops meaningless:
/// the kinds above, and unreferenced_vertex (isolated points would count as vertices and
/// components of their own: each adds 1 to V - E + F and half a handle to the genus).
bool hidesTopology(const std::string& kind);

/// Runs every check; never throws on bad content (that is what the report is for).
/// Faces with an index out of range or fewer than 3 vertices take part in no other check; faces
/// with a repeated vertex index or duplicating an earlier face are reported as such and are left
/// out of the edge, fan and orientation checks, which therefore describe the mesh that remains
/// once they are removed. A soup without faces is reported as empty_mesh only, not as having
/// unreferenced vertices.
ValidationReport validate(const PolygonSoup& soup, const ValidationOptions& options = {});

/// The connectivity validate() derives from a soup, shared with repair() so that repairs act on
/// exactly what validation reports. Corners are the (face, position) pairs numbered in face order.
/// A face is valid when its indices are in range and it has at least 3 vertices; it is usable when
/// it is valid, repeats no vertex index and does not duplicate an earlier face. Only usable faces
/// have edges, fans and orientation.
struct SoupConnectivity {
  static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  /// Per face: valid / usable as defined above.
  std::vector<std::uint8_t> valid;
  std::vector<std::uint8_t> usable;
  /// Per face: the earliest valid face with the same vertex set (any order), or `none`.
  std::vector<std::uint32_t> duplicateOf;
  /// First corner of each face; faces + 1 entries.
  std::vector<std::size_t> cornerOffset;
  /// Per corner: the smallest corner of its fan. Corners of one vertex are in the same fan when
  /// their faces are connected around the vertex through edges at it (all faces at a non-manifold
  /// edge count as connected). Corners of faces that are not usable are their own fan.
  std::vector<std::uint32_t> cornerFan;
  /// Per vertex: how many fans of usable faces meet there (2 or more: a non-manifold vertex).
  std::vector<std::uint32_t> fanCount;
  /// Number of distinct undirected edges of usable faces.
  std::size_t edges = 0;
  /// An edge used by 3 or more usable faces.
  struct NonManifoldEdge {
    std::uint32_t v0 = 0, v1 = 0;      ///< its vertices, v0 < v1
    std::vector<std::uint32_t> faces;  ///< the faces using it, ascending
  };
  /// Non-manifold edges in order of their first face.
  std::vector<NonManifoldEdge> nonManifoldEdges;
  /// Manifold edges traversed in the same direction by both faces, as (smaller face, larger face),
  /// ascending.
  std::vector<std::array<std::uint32_t, 2>> inconsistentEdges;
  /// Per face: its orientation patch, the smallest face reachable through manifold edges (each
  /// face not usable is a patch of its own).
  std::vector<std::uint32_t> facePatch;
  /// Per face: whether it must be flipped to agree with its patch's first face (for a
  /// non-orientable patch some assignment that leaves at least one edge inconsistent).
  std::vector<std::uint8_t> faceFlip;
  /// Per face: whether its patch can be oriented consistently.
  std::vector<std::uint8_t> patchOrientable;
  /// Per face: the smallest valid face of its component (valid faces connected through shared
  /// vertices), or `none` for faces that are not valid.
  std::vector<std::uint32_t> faceComponent;
};

/// Computes the connectivity above in time linear in the soup size (plus small per-vertex sorts).
SoupConnectivity analyzeConnectivity(const PolygonSoup& soup);

/// Whether a face with in-range indices repeats a vertex index, has fewer than 3 vertices, or
/// has twice its area (the length of its Newell normal) at most `tolerance` times its longest
/// edge squared. Non-finite coordinates never make a face degenerate.
bool isDegenerateFace(const PolygonSoup& soup, std::size_t face, double tolerance);

}  // namespace mspline::structure
