#include "mspline/io/write_mesh.h"

#include "mspline/io/atomic_file.h"
#include "mspline/io/detail/obj_format.h"
#include "mspline/io/detail/off_format.h"
#include "mspline/io/detail/ply_format.h"
#include "mspline/io/detail/stl_format.h"
#include "mspline/io/read_mesh.h"
#include "mspline/structure/core/errors.h"

namespace mspline::io {

namespace {

// Out-of-range indices would be written as-is and read back as different faces (in OBJ a
// negative index is even relative), so they are refused.
void checkIndices(const std::string& path, const structure::PolygonSoup& soup) {
  auto vertexCount = static_cast<std::int64_t>(soup.positions.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    for (std::int64_t index : soup.faces[f]) {
      if (index < 0 || index >= vertexCount)
        throw structure::InputError("cannot write '" + path + "': face " + std::to_string(f) +
                                    " refers to vertex " + std::to_string(index) + ", but " +
                                    soup.sourceName + " has " + std::to_string(vertexCount) +
                                    " vertices");
    }
  }
}

void checkCornerUVs(const std::string& path, const structure::PolygonSoup& soup) {
  bool parallel = soup.cornerUVs.size() == soup.faces.size();
  for (std::size_t f = 0; parallel && f < soup.faces.size(); ++f)
    parallel = soup.cornerUVs[f].size() == soup.faces[f].size();
  if (!parallel)
    throw structure::InputError("cannot write '" + path + "': the texture coordinates of " +
                                soup.sourceName + " do not match its faces corner for corner");
}

void checkAttributes(const std::string& path, const structure::PolygonSoup& soup,
                     const VertexAttributes& attributes) {
  const auto check = [&](std::size_t size, const char* what) {
    if (size != 0 && size != soup.positions.size())
      throw structure::InputError("cannot write '" + path + "': " + std::to_string(size) + " " +
                                  what + " for the " + std::to_string(soup.positions.size()) +
                                  " vertices of " + soup.sourceName);
  };
  check(attributes.normals.size(), "normals");
  check(attributes.uvs.size(), "texture coordinates");
  check(attributes.colors.size(), "colors");
}

void writeFormat(std::ostream& out, MeshFormat format, const structure::PolygonSoup& soup,
                 const VertexAttributes& attributes, bool withUVs, bool binary) {
  switch (format) {
    case MeshFormat::Obj:
      detail::writeObj(out, soup, withUVs, attributes);
      break;
    case MeshFormat::Off:
      detail::writeOff(out, soup);
      break;
    case MeshFormat::Ply:
      detail::writePly(out, soup, binary, attributes);
      break;
    case MeshFormat::Stl:
      detail::writeStl(out, soup);
      break;
  }
}

}  // namespace

void writeMesh(const std::string& path, const structure::PolygonSoup& soup,
               const MeshWriteOptions& options) {
  writeMesh(path, soup, VertexAttributes{}, options);
}

void writeMesh(const std::string& path, const structure::PolygonSoup& soup,
               const VertexAttributes& attributes, const MeshWriteOptions& options) {
  MeshFormat format = meshFormatFromPath(path);
  checkIndices(path, soup);
  checkAttributes(path, soup, attributes);
  bool withUVs = format == MeshFormat::Obj && options.writeUVs && !soup.cornerUVs.empty() &&
                 attributes.uvs.empty();
  if (withUVs) checkCornerUVs(path, soup);
  writeFileAtomically(path, [&](std::ostream& out) {
    try {
      writeFormat(out, format, soup, attributes, withUVs, options.binary);
    } catch (const structure::InputError& error) {
      throw structure::InputError("cannot write '" + path + "': " + error.what());
    }
  });
}

void writeObjLines(const std::string& path, const std::vector<std::array<double, 3>>& points,
                   const std::vector<std::array<std::int64_t, 2>>& segments) {
  if (meshFormatFromPath(path) != MeshFormat::Obj)
    throw structure::InputError("cannot write '" + path + "': lines are written as .obj only");
  for (std::size_t s = 0; s < segments.size(); ++s)
    for (std::int64_t index : segments[s])
      if (index < 0 || index >= std::int64_t(points.size()))
        throw structure::InputError("cannot write '" + path + "': segment " + std::to_string(s) +
                                    " refers to point " + std::to_string(index) + " of " +
                                    std::to_string(points.size()));
  writeFileAtomically(path,
                      [&](std::ostream& out) { detail::writeObjLines(out, points, segments); });
}

void writeMesh(const std::string& path, const structure::TriMesh& mesh,
               const MeshWriteOptions& options) {
  writeMesh(path, structure::toSoup(mesh, path), options);
}

}  // namespace mspline::io
