// The cone file reader.
#include <string>

#include "mspline/fuzz/fuzz_target.h"
#include "mspline/structure/ricci/cone_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mspline::fuzz::rejectOnlyAsInputError([&] {
    mspline::structure::parseConeList(std::string(mspline::fuzz::text(data, size)), "fuzz.cones");
  });
  return 0;
}
