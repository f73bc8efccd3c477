#pragma once
// All-or-nothing file output. Data goes into an unnamed file in the target's directory (O_TMPFILE)
// that a kill cannot leave behind; it gets the target's name only when complete. A command's
// outputs can be made all-or-nothing together with an OutputBatch.
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace mspline::io {

struct StagedFile;

/// While an OutputBatch is alive (innermost one of the thread), writeFileAtomically keeps every
/// finished file unnamed until commit(); destroying the batch without commit() discards them, so
/// either every output of a batch replaces its target or none does. A batch inside another one
/// hands its files to the outer batch on commit().
class OutputBatch {
 public:
  OutputBatch();
  ~OutputBatch();
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;

  /// Gives every staged file its target's name, in the order written; throws IoError naming the
  /// first target that cannot be replaced (files before it are already in place).
  void commit();

  /// The innermost live batch of this thread, or nullptr.
  static OutputBatch* current();

  /// Takes ownership of a finished file (used by writeFileAtomically).
  void stage(StagedFile file);

  /// A path to read what this batch or an outer one holds for `target` before the commit (the
  /// staged file, through /proc/self/fd); `target` itself when nothing is staged for it.
  std::string readablePath(const std::string& target) const;

 private:
  std::vector<StagedFile> staged_;
  OutputBatch* outer_;
};

/// Calls `write` with a binary stream on an unnamed file in the target's directory, checks the
/// stream, and gives the file the target's name (at once, or at the current OutputBatch's
/// commit). If `write` throws or any step fails, nothing is left, `path` is untouched, and the
/// exception (IoError for system failures) propagates.
/// The target's permissions and owner are kept when it exists; a symbolic link at `path` is
/// written through (its final target is replaced, the link kept); an existing target that is not
/// a regular file (a device, a pipe) is written in place. Files a killed run left named
/// (`.NAME.mspline-PID-N.tmp` of a process that is gone) are removed by the next write of NAME.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace mspline::io
