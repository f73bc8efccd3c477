#pragma once
// What the fuzz targets share: libFuzzer's bytes as text, and the rule that a reader may only
// reject its input with an InputError. Anything else (a crash, a sanitizer report, any other
// exception, an InternalError from a broken invariant) reaches libFuzzer as a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "mspline/structure/core/errors.h"

namespace mspline::fuzz {

inline std::string_view text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

template <class Read>
void rejectOnlyAsInputError(const Read& read) {
  try {
    read();
  } catch (const structure::InputError&) {
  }
}

}  // namespace mspline::fuzz
