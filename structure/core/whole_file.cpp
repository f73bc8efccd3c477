#include "mspline/structure/core/whole_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

namespace {

[[noreturn]] void failSystem(const std::string& path, const char* action, int error) {
  throw IoError("cannot " + std::string(action) + " '" + path + "': " + std::strerror(error));
}

}  // namespace

std::string readWholeFile(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) failSystem(path, "open", errno);
  if (S_ISDIR(info.st_mode)) failSystem(path, "read", EISDIR);
  if (!S_ISREG(info.st_mode))
    throw InputError(path + ": not a regular file (pipes and devices are not read)");
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

}  // namespace mspline::structure
