// The site file reader, its points checked against a tetrahedron.
#include <string>

#include "mspline/fuzz/fuzz_target.h"
#include "mspline/io/site_file.h"

namespace {

mspline::structure::TriMesh tetrahedron() {
  mspline::structure::TriMesh mesh;
  const auto a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({1, 0, 0}),
             c = mesh.add_vertex({0, 1, 0}), d = mesh.add_vertex({0, 0, 1});
  mesh.add_face(a, c, b);
  mesh.add_face(a, b, d);
  mesh.add_face(b, c, d);
  mesh.add_face(a, d, c);
  return mesh;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mspline::structure::TriMesh kMesh = tetrahedron();
  mspline::fuzz::rejectOnlyAsInputError([&] {
    mspline::io::parseSiteList(std::string(mspline::fuzz::text(data, size)), "fuzz.sites", kMesh);
  });
  return 0;
}
