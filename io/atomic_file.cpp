#include "mspline/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <streambuf>

#include "mspline/structure/core/errors.h"

namespace mspline::io {

namespace fs = std::filesystem;

/// A finished file without its final name: open and unnamed (`temporary` empty) or, where the
/// file system has no unnamed files, under a temporary name.
struct StagedFile {
  int descriptor = -1;
  std::string temporary;
  std::string target;
};

namespace {

[[noreturn]] void failWriting(const std::string& path, const std::string& reason) {
  throw structure::IoError("cannot write '" + path + "': " + reason);
}

[[noreturn]] void failWithErrno(const std::string& path) {
  failWriting(path, std::strerror(errno));
}

// Writes through a file descriptor; the standard streams cannot adopt one.
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int descriptor) : descriptor_(descriptor) {
    setp(buffer_, buffer_ + sizeof buffer_);
  }
  /// errno of the first failed write, 0 if none.
  int error() const { return error_; }

 protected:
  int overflow(int c) override {
    if (sync() != 0) return traits_type::eof();
    if (c != traits_type::eof()) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override {
    const char* data = pbase();
    while (data < pptr()) {
      const ssize_t written = ::write(descriptor_, data, std::size_t(pptr() - data));
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        error_ = written < 0 ? errno : EIO;
        return -1;
      }
      data += written;
    }
    setp(buffer_, buffer_ + sizeof buffer_);
    return 0;
  }

 private:
  int descriptor_;
  int error_ = 0;
  char buffer_[1 << 16];
};

constexpr const char* kTemporaryMark = ".mspline-";
constexpr const char* kTemporarySuffix = ".tmp";

// `.NAME.mspline-PID-N.tmp` beside the target: unique by the pid and a counter, and recognisable
// by the next run, which removes those whose process is gone.
std::string temporaryPathFor(const fs::path& target) {
  static std::atomic<unsigned long> counter{0};
  const std::string name = "." + target.filename().string() + kTemporaryMark +
                           std::to_string(::getpid()) + "-" + std::to_string(counter++) +
                           kTemporarySuffix;
  return (target.parent_path() / name).string();
}

void removeTemporariesOfGoneProcesses(const fs::path& target) {
  const std::string prefix = "." + target.filename().string() + kTemporaryMark;
  std::error_code error;
  fs::directory_iterator entry(target.parent_path().empty() ? "." : target.parent_path(), error);
  for (; !error && entry != fs::directory_iterator(); entry.increment(error)) {
    const std::string name = entry->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = name.substr(prefix.size());
    const std::size_t dash = rest.find('-');
    if (dash == std::string::npos || dash == 0 || dash > 9 ||
        rest.find_first_not_of("0123456789") != dash)
      continue;
    const pid_t pid = pid_t(std::stol(rest.substr(0, dash)));
    if (pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH) ::unlink(entry->path().c_str());
  }
}

// Symbolic links are followed so that the link stays and its final target is replaced.
fs::path resolveLinks(const std::string& path) {
  fs::path resolved = path;
  for (int hop = 0; hop < 40; ++hop) {
    std::error_code error;
    if (!fs::is_symlink(fs::symlink_status(resolved, error))) return resolved;
    const fs::path link = fs::read_symlink(resolved, error);
    if (error) failWriting(path, error.message());
    resolved = link.is_absolute() ? link : resolved.parent_path() / link;
  }
  failWriting(path, std::strerror(ELOOP));
}

struct OpenedFile {
  int descriptor = -1;
  std::string temporary;  // empty for an unnamed file
};

OpenedFile openUnnamedBeside(const fs::path& target, const std::string& path) {
  const fs::path directory = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  int descriptor = ::open(directory.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
  if (descriptor >= 0) return {descriptor, {}};
  // Some file systems have no unnamed files: a named temporary, removed on failure here or by
  // the next run after a kill.
  if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) failWithErrno(path);
  const std::string temporary = temporaryPathFor(target);
  descriptor = ::open(temporary.c_str(), O_CREAT | O_EXCL | O_WRONLY | O_CLOEXEC, 0666);
  if (descriptor < 0) failWithErrno(path);
  return {descriptor, temporary};
}

void discard(StagedFile& file) {
  if (file.descriptor >= 0) ::close(file.descriptor);
  file.descriptor = -1;
  if (!file.temporary.empty()) ::unlink(file.temporary.c_str());
  file.temporary.clear();
}

void giveTargetName(StagedFile& file) {
  if (file.temporary.empty()) {
    // The unnamed file gets a temporary name first: linkat cannot replace an existing file.
    const std::string temporary = temporaryPathFor(file.target);
    const std::string self = "/proc/self/fd/" + std::to_string(file.descriptor);
    if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, temporary.c_str(), AT_SYMLINK_FOLLOW) != 0)
      failWithErrno(file.target);
    file.temporary = temporary;
  }
  if (::rename(file.temporary.c_str(), file.target.c_str()) != 0) failWithErrno(file.target);
  file.temporary.clear();
  ::close(file.descriptor);
  file.descriptor = -1;
}

// A device or a pipe cannot be replaced: it is written as it is.
void writeInPlace(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const int descriptor = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (descriptor < 0) failWithErrno(path);
  DescriptorBuffer buffer(descriptor);
  std::ostream out(&buffer);
  try {
    write(out);
  } catch (...) {
    ::close(descriptor);
    throw;
  }
  out.flush();
  ::close(descriptor);
  if (!out) failWriting(path, std::strerror(buffer.error() ? buffer.error() : EIO));
}

thread_local OutputBatch* innermostBatch = nullptr;

}  // namespace

OutputBatch::OutputBatch() : outer_(innermostBatch) {
  innermostBatch = this;
}

OutputBatch::~OutputBatch() {
  innermostBatch = outer_;
  for (StagedFile& file : staged_) discard(file);
}

OutputBatch* OutputBatch::current() {
  return innermostBatch;
}

void OutputBatch::stage(StagedFile file) {
  staged_.push_back(std::move(file));
}

std::string OutputBatch::readablePath(const std::string& target) const {
  const std::string resolved = resolveLinks(target).string();
  for (auto file = staged_.rbegin(); file != staged_.rend(); ++file)
    if (file->target == resolved)
      return file->temporary.empty() ? "/proc/self/fd/" + std::to_string(file->descriptor)
                                     : file->temporary;
  return outer_ ? outer_->readablePath(target) : target;
}

void OutputBatch::commit() {
  if (outer_) {
    for (StagedFile& file : staged_) outer_->stage(file);
    staged_.clear();
    return;
  }
  for (StagedFile& file : staged_) giveTargetName(file);
  staged_.clear();
}

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const fs::path target = resolveLinks(path);
  struct stat existing {};
  const bool exists = ::stat(target.c_str(), &existing) == 0;
  if (exists && !S_ISREG(existing.st_mode) && !S_ISDIR(existing.st_mode))
    return writeInPlace(path, write);
  removeTemporariesOfGoneProcesses(target);

  const OpenedFile opened = openUnnamedBeside(target, path);
  StagedFile file{opened.descriptor, opened.temporary, target.string()};
  try {
    if (exists && S_ISREG(existing.st_mode)) {
      // Keep the owner where allowed, and the permissions (after the owner: chown clears setuid).
      [[maybe_unused]] const int ignored =
          ::fchown(file.descriptor, existing.st_uid, existing.st_gid);
      if (::fchmod(file.descriptor, existing.st_mode & 07777) != 0) failWithErrno(path);
    }
    DescriptorBuffer buffer(file.descriptor);
    std::ostream out(&buffer);
    write(out);
    out.flush();
    if (!out) failWriting(path, std::strerror(buffer.error() ? buffer.error() : EIO));
    if (OutputBatch* batch = OutputBatch::current()) {
      batch->stage(file);
      return;
    }
    giveTargetName(file);
  } catch (...) {
    discard(file);
    throw;
  }
}

}  // namespace mspline::io
