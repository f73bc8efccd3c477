#include "mspline/io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "mspline/structure/core/errors.h"

namespace mspline::io {

namespace {

namespace fs = std::filesystem;

// Unique within the process by the counter and across processes by the pid.
std::string temporaryPathFor(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  return path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
}

[[noreturn]] void failWriting(const std::string& path, const std::string& reason) {
  throw structure::IoError("cannot write '" + path + "': " + reason);
}

}  // namespace

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string temporary = temporaryPathFor(path);
  try {
    std::ofstream out;
    errno = 0;
    out.open(temporary, std::ios::binary | std::ios::trunc);
    if (!out) failWriting(path, errno ? std::strerror(errno) : "cannot create a temporary file");
    write(out);
    out.flush();
    if (!out) failWriting(path, errno ? std::strerror(errno) : "the write failed");
    out.close();
    if (!out) failWriting(path, errno ? std::strerror(errno) : "closing the file failed");
    std::error_code error;
    fs::rename(temporary, path, error);
    if (error) failWriting(path, error.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
}

}  // namespace mspline::io
