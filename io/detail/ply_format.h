#pragma once
// Internal to read_mesh/write_mesh: PLY (Stanford polygon format), ASCII and binary
// in either byte order.
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "mspline/io/write_mesh.h"
#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::io::detail {

/// Parses the file's contents into `soup` (polygons as stored); throws InputError naming
/// `source` (and the line, for text) when the content is malformed or truncated.
void readPly(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
             std::vector<std::string>& warnings);

/// Writes the soup, whose face indices are known to be in range: binary little-endian or
/// ASCII, positions as doubles; per-vertex normals (double nx ny nz) and colors (uchar red green
/// blue) when the attributes have them (sizes known to fit).
void writePly(std::ostream& out, const structure::PolygonSoup& soup, bool binary,
              const VertexAttributes& attributes = {});

}  // namespace mspline::io::detail
