#include "mspline/io/read_mesh.h"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "mspline/io/detail/obj_format.h"
#include "mspline/io/detail/off_format.h"
#include "mspline/io/detail/ply_format.h"
#include "mspline/io/detail/stl_format.h"
#include "mspline/io/detail/whole_file.h"
#include "mspline/structure/core/errors.h"

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
  MeshFormat format = meshFormatFromPath(path);
  std::string data = readWholeFile(path);
  if (data.empty()) throw structure::InputError(path + ": the file is empty");
  MeshReadResult result;
  result.soup.sourceName = path;
  switch (format) {
    case MeshFormat::Obj:
      detail::readObj(data, path, result.soup, result.warnings);
      break;
    case MeshFormat::Off:
      detail::readOff(data, path, result.soup, result.warnings);
      break;
    case MeshFormat::Ply:
      detail::readPly(data, path, result.soup, result.warnings);
      break;
    case MeshFormat::Stl:
      detail::readStl(data, path, result.soup, result.warnings);
      break;
  }
  std::size_t triangulated = structure::triangulatePolygons(result.soup);
  if (triangulated > 0)
    result.warnings.push_back(std::to_string(triangulated) +
                              (triangulated == 1 ? " polygon was" : " polygons were") +
                              " triangulated");
  return result;
}

}  // namespace mspline::io
