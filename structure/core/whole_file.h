#pragma once
// Reading a file into memory in one piece, for the readers (meshes, models, atlases, cone, site
// and edit-script files).
#include <string>

namespace mspline::structure {

/// The whole file: one read is far faster than streaming, and lets parsers work on a contiguous
/// buffer. Only regular files: a FIFO would block on open and a device such as /dev/zero never
/// ends (InputError naming the file). IoError when it cannot be opened or read.
std::string readWholeFile(const std::string& path);

}  // namespace mspline::structure
