#pragma once
// Reads OBJ, OFF, PLY (ASCII and binary) and STL (ASCII and binary) into a polygon soup.
#include <string>
#include <string_view>
#include <vector>

#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::io {

enum class MeshFormat { Obj, Off, Ply, Stl };

/// The format named by the file's extension (case-insensitive); throws InputError otherwise.
MeshFormat meshFormatFromPath(const std::string& path);

struct MeshReadResult {
  /// Positions and faces exactly as stored (polygons are already triangulated, see warnings).
  structure::PolygonSoup soup;
  /// Things the user should know that are not errors, e.g. "12 polygons were triangulated".
  std::vector<std::string> warnings;
};

/// Parses the file. Throws IoError when it cannot be opened or read, InputError when it is
/// empty, of unknown format, malformed or truncated, or holds a vertex with a coordinate that is
/// not finite (NaN or infinity); every message names the file and, for text formats, the line,
/// or the vertex.
MeshReadResult readMesh(const std::string& path);

/// Parses a file's bytes as readMesh does (the fuzz targets' entry); `sourceName` stands for the
/// file in messages.
MeshReadResult parseMesh(std::string_view data, MeshFormat format, const std::string& sourceName);

}  // namespace mspline::io
