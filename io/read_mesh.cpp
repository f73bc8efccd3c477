#include "mspline/io/read_mesh.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "mspline/io/detail/obj_format.h"
#include "mspline/io/detail/off_format.h"
#include "mspline/io/detail/ply_format.h"
#include "mspline/io/detail/stl_format.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/whole_file.h"

namespace mspline::io {

MeshFormat meshFormatFromPath(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".off") return MeshFormat::Off;
  if (extension == ".ply") return MeshFormat::Ply;
  if (extension == ".stl") return MeshFormat::Stl;
  throw structure::InputError(
      path + ": unknown mesh format" +
      (extension.empty() ? std::string(" (no extension)") : " '" + extension + "'") +
      "; expected .obj, .off, .ply or .stl");
}

MeshReadResult readMesh(const std::string& path) {
  const MeshFormat format = meshFormatFromPath(path);
  return parseMesh(structure::readWholeFile(path), format, path);
}

MeshReadResult parseMesh(std::string_view data, MeshFormat format, const std::string& sourceName) {
  if (data.empty()) throw structure::InputError(sourceName + ": the file is empty");
  MeshReadResult result;
  result.soup.sourceName = sourceName;
  switch (format) {
    case MeshFormat::Obj:
      detail::readObj(data, sourceName, result.soup, result.warnings);
      break;
    case MeshFormat::Off:
      detail::readOff(data, sourceName, result.soup, result.warnings);
      break;
    case MeshFormat::Ply:
      detail::readPly(data, sourceName, result.soup, result.warnings);
      break;
    case MeshFormat::Stl:
      detail::readStl(data, sourceName, result.soup, result.warnings);
      break;
  }
  // Every later step measures and compares positions: a NaN would pass through as a distance of 0.
  for (std::size_t v = 0; v < result.soup.positions.size(); ++v)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(result.soup.positions[v][std::size_t(k)]))
        throw structure::InputError(sourceName + ": vertex " + std::to_string(v) +
                                    " (counted from 0) has a coordinate that is not finite (" +
                                    "xyz"[k] + " = " +
                                    std::to_string(result.soup.positions[v][std::size_t(k)]) + ")");
  std::size_t triangulated = structure::triangulatePolygons(result.soup);
  if (triangulated > 0)
    result.warnings.push_back(std::to_string(triangulated) +
                              (triangulated == 1 ? " polygon was" : " polygons were") +
                              " triangulated");
  return result;
}

}  // namespace mspline::io
