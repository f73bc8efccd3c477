#pragma once
// Writes triangle meshes as OBJ, OFF, PLY or STL, atomically.
#include <string>

#include "structure/polygon_soup.h"
#include "structure/tri_mesh.h"

namespace mspline::io {

struct MeshWriteOptions {
  /// PLY only: binary little-endian (compact, exact) instead of ASCII.
  bool binary = true;
  /// OBJ only: write soup.cornerUVs as per-corner `vt` (ignored when the soup has none).
  bool writeUVs = true;
};

/// Writes the soup in the format named by the extension, through a temporary file that is
/// renamed into place, so a failure never leaves a partial file. Doubles are written with
/// round-trip precision. Throws InputError (unknown extension) or IoError.
void writeMesh(const std::string& path, const structure::PolygonSoup& soup,
               const MeshWriteOptions& options = {});

void writeMesh(const std::string& path, const structure::TriMesh& mesh,
               const MeshWriteOptions& options = {});

}  // namespace mspline::io
