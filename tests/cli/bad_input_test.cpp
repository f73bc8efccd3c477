// Every kind of bad input gives exit 2, a first stderr line naming the file and the problem,
// no crash, and no output file.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/test_data.h"

namespace fs = std::filesystem;
using mspline::test::cliPath;
using mspline::test::runCommand;

namespace {

struct BadInput {
  const char* name;
  const char* fileName;
  const char* content;
  const char* expectedInMessage;
};

// A clean tetrahedron is the base that most cases spoil in one way.
const BadInput kCases[] = {
    {"empty file", "empty.off", "", "empty"},
    {"unknown format", "mesh.xyz", "1 2 3\n", "format"},
    {"garbage", "garbage.off", "OFF\nthis is not a mesh\n", "garbage.off"},
    {"truncated", "truncated.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n", "truncated.off"},
    {"lying header", "lying.off", "OFF\n999999999999 1 0\n0 0 0\n", "lying.off"},
    {"face index out of range", "range.off",
     "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 7\n", "range"},
    {"nan coordinates", "nan.off",
     "OFF\n4 4 0\n0 0 0\n1 0 nan\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", "finite"},
    {"non-manifold edge", "nmedge.off",
     "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n",
     "non-manifold edge"},
    {"bow-tie vertex", "bowtie.off",
     "OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n-1 0 0\n0 -1 0\n3 0 1 2\n3 0 3 4\n", "non-manifold vertex"},
    {"degenerate face", "degenerate.off",
     "OFF\n5 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 0 0\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"
     "3 0 4 1\n",
     "degenerate"},
    {"duplicate face", "duplicate.off",
     "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n3 0 2 1\n",
     "duplicate"},
    {"inconsistent orientation", "orientation.off",
     "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", "orient"},
    {"unreferenced vertex", "unreferenced.off",
     "OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n5 5 5\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n",
     "unreferenced"},
    {"several components", "components.off",
     "OFF\n6 2 0\n0 0 0\n1 0 0\n0 1 0\n5 0 0\n6 0 0\n5 1 0\n3 0 1 2\n3 3 4 5\n", "component"},
    {"binary garbage", "binary.ply",
     "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
     "property float x\nproperty float y\nproperty float z\nelement face 1\n"
     "property list uchar int vertex_indices\nend_header\n\x01\x02",
     "binary.ply"},
};

std::string lowercase(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace

TEST_CASE("bad_input: every case exits 2 with a clear message and writes nothing", "[cli]") {
  std::string dir = mspline::test::scratchDirectory("bad_input");
  for (const BadInput& bad : kCases) {
    SECTION(bad.name) {
      fs::path input = fs::path(dir) / bad.fileName;
      std::ofstream(input, std::ios::binary) << bad.content;
      fs::path output = fs::path(dir) / "out.obj";

      auto info = runCommand(cliPath() + " info " + input.string());
      INFO("stderr: " << info.err);
      CHECK(info.exitCode == 2);
      std::string message = lowercase(mspline::test::firstLine(info.err));
      CHECK(message.find(lowercase(bad.expectedInMessage)) != std::string::npos);
      CHECK(message.find(bad.fileName) != std::string::npos);

      auto json = runCommand(cliPath() + " info --json " + input.string());
      CHECK(json.exitCode == 2);
      CHECK_NOTHROW(nlohmann::json::parse(json.out));

      auto repair = runCommand(cliPath() + " repair " + input.string() + " -o " + output.string());
      INFO("repair stderr: " << repair.err);
      CHECK(repair.exitCode == 2);
      CHECK_FALSE(fs::exists(output));

      for (const char* command : {" cut ", " flatten ", " fit "}) {
        auto result = runCommand(cliPath() + command + input.string() + " -o " + output.string());
        INFO(command << "stderr: " << result.err);
        CHECK(result.exitCode == 2);
        CHECK_FALSE(fs::exists(output));
      }
      // No temporary file is left behind either.
      CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);
      fs::remove(input);
    }
  }
}

TEST_CASE("bad_input: missing file, directory, device and FIFO instead of a file", "[cli]") {
  std::string dir = mspline::test::scratchDirectory("bad_input_missing");
  auto missing = runCommand(cliPath() + " info " + dir + "/nowhere.off");
  CHECK(missing.exitCode == 2);
  CHECK(mspline::test::firstLine(missing.err).find("nowhere.off") != std::string::npos);

  fs::create_directories(fs::path(dir) / "folder.off");
  auto folder = runCommand(cliPath() + " info " + dir + "/folder.off");
  CHECK(folder.exitCode == 2);
  CHECK(mspline::test::firstLine(folder.err).find("folder.off") != std::string::npos);

  // Devices and FIFOs would never end or block on open: refused at once.
  fs::create_symlink("/dev/zero", fs::path(dir) / "zero.off");
  auto device = runCommand("timeout 20 " + cliPath() + " info " + dir + "/zero.off");
  CHECK(device.exitCode == 2);
  CHECK(mspline::test::firstLine(device.err).find("not a regular file") != std::string::npos);
  REQUIRE(runCommand("mkfifo " + dir + "/fifo.off").exitCode == 0);
  auto fifo = runCommand("timeout 20 " + cliPath() + " info " + dir + "/fifo.off");
  CHECK(fifo.exitCode == 2);
}

TEST_CASE("bad_input: usage errors exit 1, help exits 0", "[cli]") {
  CHECK(runCommand(cliPath()).exitCode == 1);
  CHECK(runCommand(cliPath() + " frobnicate").exitCode == 1);
  CHECK(runCommand(cliPath() + " info").exitCode == 1);
  CHECK(runCommand(cliPath() + " info --no-such-flag x.off").exitCode == 1);
  auto help = runCommand(cliPath() + " --help");
  CHECK(help.exitCode == 0);
  CHECK(help.out.find("info") != std::string::npos);
  CHECK(runCommand(cliPath() + " cut --help").exitCode == 0);
}

TEST_CASE("bad_input: a missing output directory or unknown output format fails cleanly", "[cli]") {
  std::string dir = mspline::test::scratchDirectory("bad_output");
  fs::path input = fs::path(dir) / "tet.off";
  std::ofstream(input) << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n"
                          "3 0 3 2\n";
  auto result =
      runCommand(cliPath() + " repair " + input.string() + " -o " + dir + "/no/such/dir/out.off");
  CHECK(result.exitCode == 2);
  CHECK(mspline::test::firstLine(result.err).find("out.off") != std::string::npos);

  for (const char* command : {" repair ", " cut "}) {
    auto unknown = runCommand(cliPath() + command + input.string() + " -o " + dir + "/out.xyz");
    CHECK(unknown.exitCode == 2);
    CHECK(mspline::test::firstLine(unknown.err).find("out.xyz") != std::string::npos);
    CHECK_FALSE(fs::exists(dir + "/out.xyz"));
  }
}
