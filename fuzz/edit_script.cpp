// The viewer's edit script reader, for a model of 100 control points.
#include "mspline/viewer/edit_script.h"
#include "mspline/fuzz/fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mspline::fuzz::rejectOnlyAsInputError(
      [&] { mspline::viewer::parseEditScript(mspline::fuzz::text(data, size), "fuzz.json", 100); });
  return 0;
}
