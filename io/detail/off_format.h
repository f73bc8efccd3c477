#pragma once
// Internal to read_mesh/write_mesh: OFF (Geomview's Object File Format) with the
// COFF/NOFF/STOFF/4OFF variants CGAL's data uses.
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::io::detail {

/// Parses the file's contents into `soup` (polygons as stored); throws InputError naming
/// `source` (and the line, for text) when the content is malformed or truncated.
void readOff(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
             std::vector<std::string>& warnings);

/// Writes the soup, whose face indices are known to be in range.
void writeOff(std::ostream& out, const structure::PolygonSoup& soup);

}  // namespace mspline::io::detail
