#pragma once
// Writes triangle meshes as OBJ, OFF, PLY or STL, atomically.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::io {

struct MeshWriteOptions {
  /// PLY only: binary little-endian (compact, exact) instead of ASCII.
  bool binary = true;
  /// OBJ only: write soup.cornerUVs as per-corner `vt` (ignored when the soup has none).
  bool writeUVs = true;
};

/// Optional per-vertex data written with a soup: each member empty or one entry per soup vertex.
/// Formats without a place for an attribute ignore it (OFF all of them, STL all of them: its facet
/// normals always come from the triangles).
struct VertexAttributes {
  /// Normals: OBJ `vn` (one per vertex, faces `f v/t/n` or `f v//n`), PLY `nx ny nz` (double).
  std::vector<std::array<double, 3>> normals;
  /// Texture coordinates, OBJ only: one `vt` per vertex; they replace the soup's cornerUVs.
  std::vector<std::array<double, 2>> uvs;
  /// Colors, PLY only: `red green blue` (uchar).
  std::vector<std::array<std::uint8_t, 3>> colors;
};

/// Writes the soup in the format named by the extension, through a temporary file that is
/// renamed into place, so a failure never leaves a partial file. Doubles are written with
/// round-trip precision. Throws InputError (unknown extension) or IoError.
void writeMesh(const std::string& path, const structure::PolygonSoup& soup,
               const MeshWriteOptions& options = {});

/// The same with per-vertex attributes; InputError when an attribute that is not empty does not
/// have one entry per vertex.
void writeMesh(const std::string& path, const structure::PolygonSoup& soup,
               const VertexAttributes& attributes, const MeshWriteOptions& options = {});

/// Writes points and line segments between them as OBJ (a `v` per point, an `l a b` per segment)
/// through a temporary file renamed into place. Throws InputError for a path that is not .obj or a
/// segment index out of range, IoError when writing fails.
void writeObjLines(const std::string& path, const std::vector<std::array<double, 3>>& points,
                   const std::vector<std::array<std::int64_t, 2>>& segments);

void writeMesh(const std::string& path, const structure::TriMesh& mesh,
               const MeshWriteOptions& options = {});

}  // namespace mspline::io
