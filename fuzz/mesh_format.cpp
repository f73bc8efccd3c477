// One mesh format's reader (the format of the name MSPLINE_FUZZ_SOURCE: fuzz.off, .obj, .ply or
// .stl), then validation of what it read: the soup of any file the reader accepts must be fit for
// validate().
#include "mspline/fuzz/fuzz_target.h"
#include "mspline/io/read_mesh.h"
#include "mspline/structure/mesh/validate.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mspline;
  static const io::MeshFormat kFormat = io::meshFormatFromPath(MSPLINE_FUZZ_SOURCE);
  fuzz::rejectOnlyAsInputError([&] {
    const io::MeshReadResult read =
        io::parseMesh(fuzz::text(data, size), kFormat, MSPLINE_FUZZ_SOURCE);
    structure::validate(read.soup);
  });
  return 0;
}
