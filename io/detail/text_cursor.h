#pragma once
// Internal to the readers: a cursor over a whole text file held in memory. Numbers are parsed in
// place with std::from_chars, which is what makes large OFF/OBJ files fast to read.
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

#include "mspline/structure/core/errors.h"

namespace mspline::io::detail {

/// Throws InputError "source: message".
[[noreturn]] inline void failIn(const std::string& source, const std::string& message) {
  throw structure::InputError(source + ": " + message);
}

/// Throws InputError "source:line: message".
[[noreturn]] inline void failAt(const std::string& source, std::size_t line,
                                const std::string& message) {
  throw structure::InputError(source + ":" + std::to_string(line) + ": " + message);
}

/// The start of `text` as it should appear in a message: up to the first whitespace, at most
/// 24 bytes, non-printable bytes escaped (binary garbage must not mess up a terminal).
inline std::string quoteToken(std::string_view text) {
  std::string quoted = "'";
  std::size_t shown = 0;
  for (char c : text) {
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') break;
    if (shown++ == 24) {
      quoted += "...";
      break;
    }
    auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f) {
      quoted += c;
    } else {
      static const char* hex = "0123456789abcdef";
      quoted += "\\x";
      quoted += hex[byte >> 4];
      quoted += hex[byte & 15];
    }
  }
  return quoted + "'";
}

/// A number from_chars rejects as out of range ("1e999"): strtod rounds it to infinity or zero,
/// which is what the file's writer meant.
inline double outOfRangeValue(const char* begin, const char* end) {
  return std::strtod(std::string(begin, end).c_str(), nullptr);
}

/// The text without a leading UTF-8 byte order mark, which some Windows tools write.
inline std::string_view withoutByteOrderMark(std::string_view text) {
  constexpr std::string_view mark = "\xEF\xBB\xBF";
  return text.substr(0, mark.size()) == mark ? text.substr(mark.size()) : text;
}

class TextCursor {
 public:
  /// `comment` starts a comment that runs to the end of the line ('\0' when the format has none).
  TextCursor(std::string_view text, const std::string& source, char comment)
      : p_(text.data()), end_(text.data() + text.size()), source_(source), comment_(comment) {}

  std::size_t line() const { return line_; }
  bool atEnd() const { return p_ == end_; }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  const char* position() const { return p_; }

  /// Skips spaces, tabs and carriage returns, and a comment up to the line break.
  void skipBlanks() {
    while (p_ != end_ && isBlank(*p_)) ++p_;
    if (p_ != end_ && comment_ != '\0' && *p_ == comment_) {
      const void* newline = std::memchr(p_, '\n', remaining());
      p_ = newline ? static_cast<const char*>(newline) : end_;
    }
  }

  /// Whether only blanks and a comment remain on the current line.
  bool atLineEnd() {
    skipBlanks();
    return p_ == end_ || *p_ == '\n';
  }

  /// Moves to the start of the next line (or to the end of the text).
  void nextLine() {
    const void* newline = std::memchr(p_, '\n', remaining());
    if (!newline) {
      p_ = end_;
      return;
    }
    p_ = static_cast<const char*>(newline) + 1;
    ++line_;
  }

  /// Skips whitespace, line breaks and comments; false when the text ends first.
  bool skipWhitespace() {
    for (;;) {
      skipBlanks();
      if (p_ == end_) return false;
      if (*p_ != '\n') return true;
      ++p_;
      ++line_;
    }
  }

  /// The characters up to the next whitespace or comment on this line; empty at the line end.
  std::string_view word() {
    skipBlanks();
    const char* start = p_;
    while (p_ != end_ && !isDelimiter(*p_)) ++p_;
    return {start, static_cast<std::size_t>(p_ - start)};
  }

  /// The rest of the current line without the line break (comments included).
  std::string_view restOfLine() {
    const char* start = p_;
    const void* newline = std::memchr(p_, '\n', remaining());
    const char* stop = newline ? static_cast<const char*>(newline) : end_;
    return {start, static_cast<std::size_t>(stop - start)};
  }

  /// Reads a number on the current line (also "nan", "inf", "-inf"); `what` names it in errors.
  double number(const char* what) {
    skipBlanks();
    const char* start = numberStart(what);
    double value = 0;
    auto [stop, error] = std::from_chars(start, end_, value);
    if (stop == start || (stop != end_ && !isDelimiter(*stop))) failExpected(what);
    if (error == std::errc::result_out_of_range) value = outOfRangeValue(start, stop);
    p_ = stop;
    return value;
  }

  /// Reads an integer on the current line. It may also end at `terminator` (OBJ's '/').
  std::int64_t integer(const char* what, char terminator = '\0') {
    skipBlanks();
    const char* start = numberStart(what);
    std::int64_t value = 0;
    auto [stop, error] = std::from_chars(start, end_, value);
    bool ends = stop == end_ || isDelimiter(*stop) || (terminator != '\0' && *stop == terminator);
    if (stop == start || !ends) failExpected(what);
    if (error == std::errc::result_out_of_range) fail(std::string(what) + " is too large");
    p_ = stop;
    return value;
  }

  /// The current character, or '\0' at the end.
  char peek() const { return p_ == end_ ? '\0' : *p_; }
  void advance() { ++p_; }

  /// Throws InputError naming the source and the current line.
  [[noreturn]] void fail(const std::string& message) const { failAt(source_, line_, message); }

  /// "expected <what>, found '<token>'", or the end of line/file in its place.
  [[noreturn]] void failExpected(const char* what) const {
    if (p_ == end_) fail(std::string("file ends where ") + what + " was expected (truncated?)");
    if (*p_ == '\n') fail(std::string("expected ") + what + ", found the end of the line");
    if (isBlank(*p_)) fail(std::string("expected ") + what + ", found a space");
    fail(std::string("expected ") + what + ", found " + quoteToken(restOfLineFrom(p_)));
  }

 private:
  static bool isBlank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  }
  bool isDelimiter(char c) const {
    return isBlank(c) || c == '\n' || (comment_ != '\0' && c == comment_);
  }
  std::string_view restOfLineFrom(const char* from) const {
    return {from, static_cast<std::size_t>(end_ - from)};
  }
  // from_chars rejects a leading '+', which some writers emit.
  const char* numberStart(const char* what) const {
    if (p_ == end_ || *p_ == '\n') failExpected(what);
    if (*p_ != '+') return p_;
    if (p_ + 1 == end_ || p_[1] == '+' || p_[1] == '-') failExpected(what);
    return p_ + 1;
  }

  const char* p_;
  const char* end_;
  const std::string& source_;
  char comment_;
  std::size_t line_ = 1;
};

}  // namespace mspline::io::detail
