#pragma once
// Internal to read_mesh/write_mesh: STL, ASCII and binary. STL stores every triangle
// with its own three corners.
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::io::detail {

/// Parses the file's contents into `soup` (polygons as stored); throws InputError naming
/// `source` (and the line, for text) when the content is malformed or truncated.
void readStl(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
             std::vector<std::string>& warnings);

/// Writes binary STL. Throws InputError when a face is not a triangle. STL stores 32-bit
/// floats, so positions are rounded and do not read back bit-exactly.
void writeStl(std::ostream& out, const structure::PolygonSoup& soup);

}  // namespace mspline::io::detail
