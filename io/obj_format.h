#pragma once
// Internal to read_mesh/write_mesh: Wavefront OBJ: positions, texture coordinates
// and faces; every other statement is ignored.
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "structure/polygon_soup.h"

namespace mspline::io::detail {

/// Parses the file's contents into `soup` (polygons as stored); throws InputError naming
/// `source` (and the line, for text) when the content is malformed or truncated.
void readObj(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
             std::vector<std::string>& warnings);

/// Writes the soup, whose face indices are known to be in range; with `withUVs`, cornerUVs
/// become one `vt` per corner and faces `f v/vt`.
void writeObj(std::ostream& out, const structure::PolygonSoup& soup, bool withUVs);

}  // namespace mspline::io::detail
