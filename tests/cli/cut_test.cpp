// `mspline cut` end to end: the written disk, read back by `mspline info`, is a disk, and closed
// surfaces of genus g give 4g boundary segments in canonical order.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/test_data.h"

using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;

namespace {

std::string canonicalWord(int genus) {
  std::string word;
  for (int k = 1; k <= genus; ++k) {
    std::string a = "a" + std::to_string(k), b = "b" + std::to_string(k);
    word += (k > 1 ? " " : "") + a + " " + b + " " + a + "^-1 " + b + "^-1";
  }
  return word;
}

}  // namespace

TEST_CASE("cut: real closed surfaces give canonical 4g-gons", "[cli]") {
  std::string dir = mspline::test::scratchDirectory("cli_cut");
  struct Case {
    const char* mesh;
    int genus;
  };
  for (Case c : {Case{"knot1.off", 1}, Case{"eight.off", 2}, Case{"elephant.off", 3}}) {
    INFO(c.mesh);
    std::string disk = dir + "/" + c.mesh + ".obj";
    auto cut = runCommand(cliPath() + " cut --json -q " + realMeshPath(c.mesh) + " -o " + disk);
    INFO("stderr: " << cut.err);
    REQUIRE(cut.exitCode == 0);
    auto result = nlohmann::json::parse(cut.out);
    CHECK(result["genus"] == c.genus);
    CHECK(result["segments"] == 4 * c.genus);
    CHECK(result["word"] == canonicalWord(c.genus));
    CHECK(result["canonical"] == true);

    // The file on disk, read back independently, is one disk.
    auto info = runCommand(cliPath() + " info --json " + disk);
    INFO("info stderr: " << info.err);
    REQUIRE(info.exitCode == 0);
    auto topology = nlohmann::json::parse(info.out);
    CHECK(topology["euler"] == 1);
    CHECK(topology["boundaries"] == 1);
    CHECK(topology["components"] == 1);
    CHECK(topology["genus"] == 0);
  }
}

TEST_CASE("cut: bounded and genus-0 surfaces open into one disk", "[cli]") {
  std::string dir = mspline::test::scratchDirectory("cli_cut_bounded");
  for (const char* mesh : {"head.off", "mannequin-devil.off", "bunny00.off"}) {
    INFO(mesh);
    std::string disk = dir + "/" + mesh + ".ply";
    auto cut = runCommand(cliPath() + " cut -q " + realMeshPath(mesh) + " -o " + disk);
    REQUIRE(cut.exitCode == 0);
    auto info = runCommand(cliPath() + " info --json " + disk);
    REQUIRE(info.exitCode == 0);
    auto topology = nlohmann::json::parse(info.out);
    CHECK(topology["euler"] == 1);
    CHECK(topology["boundaries"] == 1);
  }
}
