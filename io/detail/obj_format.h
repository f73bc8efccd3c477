#pragma once
// Internal to read_mesh/write_mesh: Wavefront OBJ: positions, texture coordinates
// and faces; every other statement is ignored.
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "mspline/io/write_mesh.h"
#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::io::detail {

/// Parses the file's contents into `soup` (polygons as stored); throws InputError naming
/// `source` (and the line, for text) when the content is malformed or truncated.
void readObj(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
             std::vector<std::string>& warnings);

/// Writes the soup, whose face indices are known to be in range; with `withUVs`, cornerUVs
/// become one `vt` per corner and faces `f v/vt`. Per-vertex attributes (sizes known to fit):
/// uvs one `vt` per vertex (withUVs is then false), normals one `vn` per vertex, faces referring
/// to them by the vertex's index.
void writeObj(std::ostream& out, const structure::PolygonSoup& soup, bool withUVs,
              const VertexAttributes& attributes = {});

/// Writes `v` lines for the points and `l` lines for the segments (indices known to be in range).
void writeObjLines(std::ostream& out, const std::vector<std::array<double, 3>>& points,
                   const std::vector<std::array<std::int64_t, 2>>& segments);

}  // namespace mspline::io::detail
