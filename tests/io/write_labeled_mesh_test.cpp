#include "mspline/io/write_labeled_mesh.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "mspline/io/read_mesh.h"
#include "mspline/structure/core/errors.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

namespace {

using mspline::io::LabeledPolyline;
using mspline::io::writeLabeledObj;

}  // namespace

TEST_CASE("write_labeled_mesh: groups by label and polylines", "[io]") {
  const std::string dir = mspline::test::scratchDirectory("io_write_labeled_mesh");
  const std::string path = dir + "/labeled.obj";
  const auto mesh = mspline::test::gridDisk(2);  // 9 vertices, 8 faces
  const std::vector<int> labels = {3, 0, 3, 0, 7, 7, 0, 3};
  const std::vector<LabeledPolyline> lines = {
      {"open", {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}}},
      {"closed", {{0, 0, 2}, {1, 0, 2}, {1, 1, 2}, {0, 0, 2}}}};
  writeLabeledObj(path, mesh, labels, "cell_", lines);
  const std::string expectedTail =
      "g open\nv 0 0 1\nv 1 0 1\nv 1 1 1\nl 10 11 12\n"
      "g closed\nv 0 0 2\nv 1 0 2\nv 1 1 2\nl 13 14 15 13\n";
  const std::string text = mspline::test::fileText(path);
  CHECK(text.size() > expectedTail.size());
  CHECK(text.compare(text.size() - expectedTail.size(), expectedTail.size(), expectedTail) == 0);
  // Groups in ascending label order, each face once, under its label.
  std::istringstream in(text);
  std::string line, group;
  std::vector<std::string> groups;
  std::vector<int> faceCount(8, 0);
  int facesInGroups = 0;
  while (std::getline(in, line)) {
    if (line.rfind("g ", 0) == 0) groups.push_back(group = line.substr(2));
    if (line.rfind("f ", 0) != 0) continue;
    ++facesInGroups;
    int a, b, c;
    std::istringstream(line.substr(2)) >> a >> b >> c;
    for (auto f : mesh.faces()) {
      std::vector<int> v;
      for (auto w : mesh.fv_range(f)) v.push_back(w.idx() + 1);
      if (v == std::vector<int>{a, b, c}) {
        ++faceCount[f.idx()];
        CHECK(group == "cell_" + std::to_string(labels[f.idx()]));
      }
    }
  }
  CHECK(groups == std::vector<std::string>{"cell_0", "cell_3", "cell_7", "open", "closed"});
  CHECK(facesInGroups == 8);
  CHECK(faceCount == std::vector<int>(8, 1));
  // The reader takes the faces back (groups and lines are ignored; the extra vertices are
  // unreferenced, which validation names).
  CHECK(mspline::io::readMesh(path).soup.faces.size() == 8);
}

TEST_CASE("write_labeled_mesh: bad input", "[io]") {
  const std::string dir = mspline::test::scratchDirectory("io_write_labeled_mesh_bad");
  const auto mesh = mspline::test::gridDisk(2);
  using mspline::structure::InputError;
  CHECK_THROWS_AS(writeLabeledObj(dir + "/a.obj", mesh, {0, 1}, "c", {}), InputError);
  CHECK_THROWS_AS(writeLabeledObj(dir + "/a.obj", mesh, std::vector<int>(8, -1), "c", {}),
                  InputError);
  CHECK_THROWS_AS(
      writeLabeledObj(dir + "/a.obj", mesh, std::vector<int>(8, 0), "c", {{"short", {{0, 0, 0}}}}),
      InputError);
  CHECK_THROWS_AS(writeLabeledObj(dir + "/a.ply", mesh, std::vector<int>(8, 0), "c", {}),
                  InputError);
  CHECK_FALSE(std::filesystem::exists(dir + "/a.obj"));
}
