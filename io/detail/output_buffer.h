#pragma once
// Internal to the writers: formats into a string and hands it to the stream in large chunks,
// which is much faster than formatted stream output per number.
#include <array>
#include <charconv>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "mspline/io/detail/byte_order.h"

namespace mspline::io::detail {

class OutputBuffer {
 public:
  explicit OutputBuffer(std::ostream& out) : out_(out) { buffer_.reserve(kChunk + 64); }

  void text(std::string_view s) {
    buffer_.append(s);
    drainIfFull();
  }
  void character(char c) {
    buffer_ += c;
    drainIfFull();
  }
  /// Shortest decimal form that reads back to the same double ("nan", "inf", "-inf" included).
  void number(double value) {
    char digits[32];
    auto result = std::to_chars(digits, digits + sizeof digits, value);
    buffer_.append(digits, result.ptr);
    drainIfFull();
  }
  void integer(std::int64_t value) {
    char digits[24];
    auto result = std::to_chars(digits, digits + sizeof digits, value);
    buffer_.append(digits, result.ptr);
    drainIfFull();
  }
  /// "x y z\n", the vertex line of every text format (after its own prefix, if any).
  void pointLine(const std::array<double, 3>& p) {
    number(p[0]);
    character(' ');
    number(p[1]);
    character(' ');
    number(p[2]);
    character('\n');
  }
  /// "n i1 ... in\n", the face line of OFF and ASCII PLY.
  void countedIndexLine(const std::vector<std::int64_t>& indices) {
    integer(static_cast<std::int64_t>(indices.size()));
    for (std::int64_t index : indices) {
      character(' ');
      integer(index);
    }
    character('\n');
  }
  template <typename T>
  void littleEndian(T value) {
    appendLittleEndian(buffer_, value);
    drainIfFull();
  }
  /// Writes what is buffered; call once at the end.
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kChunk = std::size_t(1) << 20;
  void drainIfFull() {
    if (buffer_.size() >= kChunk) flush();
  }

  std::ostream& out_;
  std::string buffer_;
};

}  // namespace mspline::io::detail
