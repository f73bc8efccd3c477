#pragma once
// The lines of the plain-text lists mspline reads (cone files, site files): blank-separated
// fields, '#' starting a comment that runs to the end of the line, blank lines ignored.
#include <string>
#include <vector>

namespace mspline::structure {

struct TextRecord {
  /// 1-based line number, for messages "path:line".
  int line = 0;
  /// The line without its comment and trailing blanks (shown in messages).
  std::string content;
  /// Its blank-separated fields (at least one).
  std::vector<std::string> fields;
};

/// The lines of `text` that hold a field.
std::vector<TextRecord> textRecords(const std::string& text);

}  // namespace mspline::structure
