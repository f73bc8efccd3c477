#include "io/read_mesh.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "io/obj_format.h"
#include "io/off_format.h"
#include "io/ply_format.h"
#include "io/stl_format.h"
#include "structure/errors.h"

namespace mspline::io {

namespace {

[[noreturn]] void failSystem(const std::string& path, const char* action, int error) {
  throw structure::IoError("cannot " + std::string(action) + " '" + path +
                           "': " + std::strerror(error));
}

// The whole file in memory: one read is far faster than streaming, and lets the text parsers
// work on a contiguous buffer. Only regular files: a FIFO would block on open and a device such
// as /dev/zero never ends.
std::string readWholeFile(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) failSystem(path, "open", errno);
  if (S_ISDIR(info.st_mode)) failSystem(path, "read", EISDIR);
  if (!S_ISREG(info.st_mode))
    throw structure::InputError(path + ": not a regular file (pipes and devices are not read)");
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) failSystem(path, "open", errno);
  struct FileCloser {
    int fd;
    ~FileCloser() { ::close(fd); }
  } closer{fd};
  // The +1 sees the end of the file in the first read; the loop still copes with a file that
  // grows while it is read.
  std::string data(static_cast<std::size_t>(info.st_size) + 1, '\0');
  std::size_t used = 0;
  for (;;) {
    if (used == data.size()) data.resize(2 * data.size());
    ssize_t got = ::read(fd, data.data() + used, data.size() - used);
    if (got < 0) {
      if (errno == EINTR) continue;
      failSystem(path, "read", errno);
    }
    if (got == 0) break;
    used += static_cast<std::size_t>(got);
  }
  data.resize(used);
  return data;
}

}  // namespace

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
