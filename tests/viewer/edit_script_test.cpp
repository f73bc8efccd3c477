#include "mspline/viewer/edit_script.h"

#include <catch2/catch.hpp>
#include <fstream>

#include "mspline/structure/core/errors.h"
#include "support/test_data.h"

using namespace mspline;

namespace {

std::string writeScript(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST_CASE("edit_script: every kind of edit is read", "[viewer]") {
  const std::string dir = test::scratchDirectory("edit_script_read");
  const auto edits =
      viewer::readEditScript(writeScript(dir, "all.json",
                                         R"({"edits": [{"points": [3], "pixels": [10, -4]},
                     {"points": [1, 2], "offset": [0, 0.5, 1], "steps": 3},
                     {"points": [4], "normal": -0.25}, {"undo": 2}, {"redo": 1},
                     {"save": true}, {"wait": 0.1}]})"),
                             5);
  using Kind = viewer::ScriptedEdit::Kind;
  REQUIRE(edits.size() == 7);
  CHECK(edits[0].kind == Kind::Pixels);
  CHECK(edits[0].points == std::vector<int>{3});
  CHECK(edits[0].vector == Eigen::Vector3d(10, -4, 0));
  CHECK(edits[0].steps == 8);
  CHECK(edits[1].kind == Kind::Offset);
  CHECK(edits[1].vector == Eigen::Vector3d(0, 0.5, 1));
  CHECK(edits[1].steps == 3);
  CHECK(edits[2].kind == Kind::Normal);
  CHECK(edits[2].amount == -0.25);
  CHECK(edits[3].kind == Kind::Undo);
  CHECK(edits[3].count == 2);
  CHECK(edits[4].kind == Kind::Redo);
  CHECK(edits[5].kind == Kind::Save);
  CHECK(edits[6].kind == Kind::Wait);
  CHECK(edits[6].amount == 0.1);
}

TEST_CASE("edit_script: bad scripts are input errors naming the file and the edit", "[viewer]") {
  const std::string dir = test::scratchDirectory("edit_script_bad");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{\"edits\": [", "not JSON"},
      {"[1, 2]", "an array \"edits\""},
      {R"({"edits": [{"points": [7], "offset": [0, 0, 1]}]})", "edit 1: control point 7"},
      {R"({"edits": [{"undo": 1}, {"points": [1], "offset": [0, 1]}]})", "edit 2: \"offset\""},
      {R"({"edits": [{"points": [1]}]})", "edit 1: expected one of"},
      {R"({"edits": [{"offset": [0, 0, 1]}]})", "edit 1: a move needs \"points\""},
      {R"({"edits": [{"points": [1], "normal": 1, "steps": 0}]})", "edit 1: \"steps\""},
      {R"({"edits": [{"wait": -1}]})", "edit 1: \"wait\""},
      // Numbers that would hang the viewer, wrap around int or overflow to infinity.
      {R"({"edits": [{"points": [1], "normal": 1e999}]})", "not JSON"},
      {R"({"edits": [{"wait": 1e9}]})", "edit 1: \"wait\""},
      {R"({"edits": [{"points": [1], "normal": 1, "steps": 4294967297}]})", "edit 1: \"steps\""},
      {R"({"edits": [{"points": [1], "normal": 1, "steps": 100000000}]})", "edit 1: \"steps\""},
      {R"({"edits": [{"undo": 2147483647}]})", "edit 1: \"undo\""},
      {R"({"edits": [{"points": [18446744073709551615], "normal": 1}]})",
       "edit 1: control point 18446744073709551615"},
      {R"({"edits": [{"points": [1.5], "normal": 1}]})", "edit 1: control point 1.5"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = writeScript(dir, "bad" + std::to_string(i) + ".json", cases[i].first);
    INFO(cases[i].first);
    CHECK_THROWS_AS(viewer::readEditScript(path, 5), structure::InputError);
    CHECK_THROWS_WITH(viewer::readEditScript(path, 5),
                      Catch::Contains(path) && Catch::Contains(cases[i].second));
  }
  CHECK_THROWS_AS(viewer::readEditScript(dir + "/missing.json", 5), structure::IoError);
}
