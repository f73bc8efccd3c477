// The atlas file reader.
#include "mspline/fuzz/fuzz_target.h"
#include "mspline/io/atlas_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mspline::fuzz::rejectOnlyAsInputError(
      [&] { mspline::io::parseAtlas(mspline::fuzz::text(data, size), "fuzz.json"); });
  return 0;
}
