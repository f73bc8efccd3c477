#pragma once
// Internal to the readers and writers: fixed-endian encoding of binary PLY and STL values,
// assembled byte by byte so that the result does not depend on the host's byte order.
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

namespace mspline::io::detail {

template <typename T>
using UnsignedOfSize = std::conditional_t<
    sizeof(T) == 1, std::uint8_t,
    std::conditional_t<sizeof(T) == 2, std::uint16_t,
                       std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;

/// Decodes a T stored at `bytes` in little-endian (or big-endian) order.
template <typename T>
T decode(const char* bytes, bool bigEndian) {
  using U = UnsignedOfSize<T>;
  U bits = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    std::size_t k = bigEndian ? i : sizeof(T) - 1 - i;
    bits = static_cast<U>((bits << 8) | static_cast<unsigned char>(bytes[k]));
  }
  T value;
  std::memcpy(&value, &bits, sizeof(T));
  return value;
}

/// Appends `value` to `out` in little-endian order.
template <typename T>
void appendLittleEndian(std::string& out, T value) {
  using U = UnsignedOfSize<T>;
  U bits;
  std::memcpy(&bits, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    out += static_cast<char>(bits & 0xff);
    bits = static_cast<U>(bits >> 8);
  }
}

}  // namespace mspline::io::detail
