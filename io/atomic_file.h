#pragma once
// All-or-nothing file output: write into a temporary file beside the target, then rename.
#include <functional>
#include <ostream>
#include <string>

namespace mspline::io {

/// Calls `write` with a binary stream on a temporary file in the target's directory, checks the
/// stream, and renames it onto `path`. If `write` throws or any step fails, the temporary file is
/// removed, `path` is untouched, and the exception (IoError for system failures) propagates.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace mspline::io
