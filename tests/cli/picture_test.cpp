// `mspline picture` end to end: a PNG of the requested size, and clear errors for bad requests.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/test_data.h"

namespace fs = std::filesystem;
using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;

namespace {

// Big-endian 32-bit number at `offset` of a byte string.
unsigned long bigEndian(const std::string& bytes, std::size_t offset) {
  unsigned long value = 0;
  for (std::size_t i = 0; i < 4; ++i)
    value = value << 8 | static_cast<unsigned char>(bytes[offset + i]);
  return value;
}

}  // namespace

TEST_CASE("picture: a checkerboard PNG of the knot", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_picture_knot");
  const std::string out = dir + "/knot1.png";
  auto result = runCommand(cliPath() + " picture --json -q " + realMeshPath("knot1.off") +
                           " --kind checker --cones none --width 640 --height 480 -o " + out);
  INFO("stderr: " << result.err);
  REQUIRE(result.exitCode == 0);
  const auto report = nlohmann::json::parse(result.out);
  CHECK(report["kind"] == "checker");
  CHECK(report["output"] == out);
  CHECK(report["width"] == 640);
  CHECK(report["height"] == 480);
  CHECK(report["converged"] == true);
  CHECK(report["cones"].empty());

  // PNG signature, then the IHDR chunk: length, "IHDR", width, height (big-endian).
  std::ifstream file(out, std::ios::binary);
  std::string head(24, '\0');
  REQUIRE(file.read(head.data(), head.size()));
  CHECK(head.substr(0, 8) == "\x89PNG\r\n\x1a\n");
  CHECK(head.substr(12, 4) == "IHDR");
  CHECK(bigEndian(head, 16) == 640);
  CHECK(bigEndian(head, 20) == 480);
}

TEST_CASE("picture: from an atlas file, without flattening again", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_picture_atlas");
  const std::string atlas = dir + "/knot1.json";
  REQUIRE(
      runCommand(cliPath() + " atlas -q " + realMeshPath("knot1.off") + " --cones none -o " + atlas)
          .exitCode == 0);
  const std::string out = dir + "/cover.png";
  auto result = runCommand(cliPath() + " picture --json -q " + atlas +
                           " --kind cover --width 300 --height 200 -o " + out);
  INFO("stderr: " << result.err);
  REQUIRE(result.exitCode == 0);
  const auto report = nlohmann::json::parse(result.out);
  CHECK(report["kind"] == "cover");
  CHECK(report["file"] == atlas);
  CHECK(!report.contains("converged"));  // nothing was flattened
  std::ifstream file(out, std::ios::binary);
  std::string head(24, '\0');
  REQUIRE(file.read(head.data(), head.size()));
  CHECK(bigEndian(head, 16) == 300);
  CHECK(bigEndian(head, 20) == 200);

  std::ofstream(dir + "/broken.json") << "{\"format\": \"something else\"}";
  auto broken = runCommand(cliPath() + " picture -q " + dir + "/broken.json --kind checker -o " +
                           dir + "/broken.png");
  CHECK(broken.exitCode == 2);
  CHECK_THAT(broken.err, Catch::Contains("broken.json"));
  CHECK(!fs::exists(dir + "/broken.png"));
}

TEST_CASE("picture: a surface that needs intrinsic flips (its overlay is drawn)", "[cli]") {
  // The laid-out surface is the overlay the flattening owns; it must survive being returned.
  const std::string dir = mspline::test::scratchDirectory("cli_picture_flips");
  auto result =
      runCommand(cliPath() + " picture --json -q " + realMeshPath("eight.off") +
                 " --quantize --kind checker --width 200 --height 200 -o " + dir + "/eight.png");
  INFO("stderr: " << result.err);
  REQUIRE(result.exitCode == 0);
  const auto report = nlohmann::json::parse(result.out);
  CHECK(report["flips"].get<int>() > 0);
  CHECK(fs::exists(dir + "/eight.png"));
}

TEST_CASE("picture: bad requests exit 2 naming the file, writing nothing", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_picture_bad");
  auto cover = runCommand(cliPath() + " picture -q " + realMeshPath("bunny00.off") +
                          " --kind cover -o " + dir + "/bunny.png");
  CHECK(cover.exitCode == 2);
  CHECK_THAT(cover.err, Catch::Contains("bunny00.off") && Catch::Contains("genus-1"));

  auto cones = runCommand(cliPath() + " picture -q " + realMeshPath("knot1.off") +
                          " --kind cover --cones 2 -o " + dir + "/knot1.png");
  CHECK(cones.exitCode == 2);
  CHECK_THAT(cones.err, Catch::Contains("knot1.off") && Catch::Contains("--cones none"));

  auto jpeg = runCommand(cliPath() + " picture -q " + realMeshPath("knot1.off") +
                         " --kind checker -o " + dir + "/x.jpg");
  CHECK(jpeg.exitCode == 2);
  CHECK_THAT(jpeg.err, Catch::Contains("x.jpg") && Catch::Contains(".png"));
  CHECK(fs::is_empty(dir));
}
