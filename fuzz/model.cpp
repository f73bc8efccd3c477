// The spline model reader, then what `check` and `export` do with a model it accepts (at a low
// resolution and a few samples): whatever the reader accepts must evaluate without crashing.
#include "mspline/fuzz/fuzz_target.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/check_model.h"
#include "mspline/spline/model/export_surface.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mspline;
  fuzz::rejectOnlyAsInputError([&] {
    const spline::SplineModel model = io::parseSplineModel(fuzz::text(data, size), "fuzz.msp");
    spline::ExportOptions exportOptions;
    exportOptions.resolution = 2;
    exportOptions.controlNet = true;
    spline::exportSurface(model, "fuzz.msp", exportOptions);
    spline::CheckOptions checkOptions;
    checkOptions.samples = 16;
    checkOptions.knotSamples = 2;
    spline::checkModel(model, "fuzz.msp", checkOptions);
  });
  return 0;
}
