#pragma once
// Faces and positions exactly as a file stores them, before any manifold structure is imposed.
// Readers produce a soup so that validation can see (and name) every defect of the input.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct PolygonSoup {
  /// Vertex positions, in file order.
  std::vector<std::array<double, 3>> positions;
  /// Faces as vertex indices (0-based, file order); polygons have 3 or more entries.
  std::vector<std::vector<std::int64_t>> faces;
  /// Optional per-corner texture coordinates, parallel to `faces` (empty when the file has none).
  std::vector<std::vector<std::array<double, 2>>> cornerUVs;
  /// Where the soup came from, used in every message about it.
  std::string sourceName = "<memory>";
};

/// Splits every face with more than 3 vertices into a fan of triangles around its first
/// vertex, splitting cornerUVs alike; returns how many faces were split.
std::size_t triangulatePolygons(PolygonSoup& soup);

/// The faces of a soup of triangles as index triples, the form TriangleMeshDistance, renderShaded
/// and the viewer take. Throws InputError naming the source when a face is not a triangle.
std::vector<std::array<int, 3>> triangleIndices(const PolygonSoup& soup);

/// Points as the rows of a matrix.
Eigen::MatrixX3d pointMatrix(const std::vector<std::array<double, 3>>& points);

/// Builds a TriMesh from a soup whose faces are triangles and which passed validation.
/// Throws TopologyError naming the source and the face if OpenMesh cannot add a face.
TriMesh toTriMesh(const PolygonSoup& soup);

/// The mesh as a soup (positions and triangles in OpenMesh index order).
PolygonSoup toSoup(const TriMesh& mesh, const std::string& sourceName = "<memory>");

}  // namespace mspline::structure
