// The README's error policy, checked on every subcommand: exit 1 usage, 2 input to change (the file
// named), 3 a computation that failed (the stage named); the first stderr line is the error; under
// --json stdout is exactly one JSON object; nothing is written.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/test_data.h"

namespace fs = std::filesystem;
using mspline::test::cliPath;
using mspline::test::CommandResult;
using mspline::test::runCommand;

namespace {

// A tetrahedron whose apex is a hundred times farther from its base than the base is wide: the
// apex's cone angle is below pi/4 and no other vertex can take its curvature.
const char* const kNeedle =
    "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0.2 0.2 100\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

std::string quoted(const fs::path& path) {
  return "'" + path.string() + "'";
}

void writeFile(const fs::path& path, const std::string& content) {
  std::ofstream(path, std::ios::binary) << content;
}

std::size_t filesIn(const fs::path& dir) {
  return std::size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// Stdout of a --json run as its one JSON object (the test fails when it is anything else).
nlohmann::json onlyObject(const CommandResult& result) {
  INFO("stdout: " << result.out);
  nlohmann::json object;
  REQUIRE_NOTHROW(object = nlohmann::json::parse(result.out));
  REQUIRE(object.is_object());
  return object;
}

// Runs `mspline COMMAND ARGUMENTS` with and without --json and checks the failure: its exit code,
// the first stderr line `mspline COMMAND: error: ...` naming `named`, one JSON object with
// error.kind and error.message, and no file added to `dir`. Returns the JSON object.
nlohmann::json checkFailure(const std::string& command, const std::string& arguments, int exitCode,
                            const std::string& named, const fs::path& dir) {
  const std::size_t before = filesIn(dir);
  const std::string line = cliPath() + " " + command + " " + arguments;
  const CommandResult text = runCommand(line);
  INFO(line << "\nstderr: " << text.err);
  CHECK(text.exitCode == exitCode);
  CHECK_THAT(mspline::test::firstLine(text.err),
             Catch::StartsWith("mspline " + command + ": error: ") && Catch::Contains(named));
  CHECK(filesIn(dir) == before);

  const CommandResult json = runCommand(line + " --json");
  INFO("--json stderr: " << json.err);
  CHECK(json.exitCode == exitCode);
  CHECK_THAT(mspline::test::firstLine(json.err),
             Catch::StartsWith("mspline " + command + ": error: "));
  const nlohmann::json object = onlyObject(json);
  REQUIRE(object.contains("error"));
  CHECK(object["error"]["kind"].is_string());
  CHECK_THAT(object["error"]["message"].get<std::string>(), Catch::Contains(named));
  CHECK(filesIn(dir) == before);
  return object;
}

}  // namespace

TEST_CASE("error_policy: every subcommand on a bad input exits 2 naming the file", "[cli]") {
  const fs::path dir = mspline::test::scratchDirectory("error_policy_bad_input");
  const fs::path truncated = dir / "truncated.off";
  writeFile(truncated, "OFF\n4 4 0\n0 0 0\n1 0 0\n");
  // The header of a T-spline model, then the end of the file inside a count.
  const fs::path model = dir / "malformed.msp";
  writeFile(model, std::string("MSPLINE\x1a\x02\0\0\0\x02\0\0\0\x05\0", 18));
  const fs::path missing = dir / "missing.off";

  const std::vector<std::pair<std::string, std::string>> meshCommands = {
      {"info", ""},
      {"repair", "-o " + quoted(dir / "out.off")},
      {"cut", "-o " + quoted(dir / "out.off")},
      {"flatten", "-o " + quoted(dir / "out.obj")},
      {"voronoi", "--sites 3 -o " + quoted(dir / "out.obj")},
      {"atlas", "-o " + quoted(dir / "out.json")},
      {"picture", "--kind layout -o " + quoted(dir / "out.png")},
      {"spline", "-o " + quoted(dir / "out.msp")},
      {"fit", "-o " + quoted(dir / "out.msp")},
      {"view", "--screenshot " + quoted(dir / "out.png")},
  };
  for (const auto& [command, options] : meshCommands) {
    for (const fs::path& input : {missing, truncated}) {
      SECTION(command + " " + input.filename().string()) {
        checkFailure(command, quoted(input) + " " + options, 2, input.filename().string(), dir);
      }
    }
  }
  const std::vector<std::pair<std::string, std::string>> modelCommands = {
      {"check", ""},
      {"export", "-o " + quoted(dir / "out.obj")},
      {"compare-osd", ""},
      {"view", "--screenshot " + quoted(dir / "out.png")},
  };
  for (const auto& [command, options] : modelCommands) {
    for (const fs::path& input : {missing, truncated, model}) {
      SECTION(command + " model " + input.filename().string()) {
        const nlohmann::json report =
            checkFailure(command, quoted(input) + " " + options, 2, input.filename().string(), dir);
        CHECK(report["error"]["kind"] != "internal");
      }
    }
  }
}

TEST_CASE("error_policy: bytes that are not UTF-8 keep the JSON valid", "[cli]") {
  const fs::path dir = mspline::test::scratchDirectory("error_policy_utf8");
  // A file name that is not UTF-8 (Latin-1 e acute).
  const fs::path path = dir / "bad\xe9.off";
  writeFile(path, "OFF\n");
  const nlohmann::json report = checkFailure("info", quoted(path), 2, "bad", dir);
  // U+FFFD in JSON, the bytes as they are in text.
  CHECK_THAT(report["error"]["message"].get<std::string>(), Catch::Contains("bad\xef\xbf\xbd.off"));
  CHECK_THAT(mspline::test::firstLine(runCommand(cliPath() + " info " + quoted(path)).err),
             Catch::Contains("bad\xe9.off"));

  // A PLY element named by the byte 0xff, quoted in the error message.
  const fs::path ply = dir / "element.ply";
  writeFile(
      ply,
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement \xff 2\nproperty float w\nend_header\n0 0 0\n1 0 0\n0 1 0\n1\n");
  const CommandResult json = runCommand(cliPath() + " info --json " + quoted(ply));
  CHECK(json.exitCode == 2);
  CHECK_THAT(onlyObject(json)["error"]["message"].get<std::string>(),
             Catch::Contains("element.ply"));
  // Text mode shows the bytes as they are.
  const CommandResult text = runCommand(cliPath() + " info " + quoted(ply));
  CHECK_THAT(mspline::test::firstLine(text.err), Catch::Contains("2 \xff elements"));
}

TEST_CASE("error_policy: usage errors under --json print one JSON object", "[cli]") {
  const CommandResult json = runCommand(cliPath() + " info --no-such-flag x.off --json");
  CHECK(json.exitCode == 1);
  const nlohmann::json object = onlyObject(json);
  CHECK(object.size() == 1);
  CHECK(object["error"]["kind"] == "usage");
  CHECK_THAT(object["error"]["message"].get<std::string>(), Catch::Contains("--no-such-flag"));
  CHECK_THAT(json.err, Catch::Contains("--no-such-flag"));

  const CommandResult missing = runCommand(cliPath() + " fit --json");
  CHECK(missing.exitCode == 1);
  CHECK(onlyObject(missing)["error"]["kind"] == "usage");

  // Without --json stdout stays empty; help still exits 0 with its text on stdout.
  const CommandResult text = runCommand(cliPath() + " info --no-such-flag x.off");
  CHECK(text.exitCode == 1);
  CHECK(text.out.empty());
  const CommandResult help = runCommand(cliPath() + " info --help --json");
  CHECK(help.exitCode == 0);
  CHECK_THAT(help.out, Catch::Contains("MESH"));
}

TEST_CASE("error_policy: failed computations exit 3 naming the stage, whatever the stage",
          "[cli]") {
  const fs::path dir = mspline::test::scratchDirectory("error_policy_computation");
  const fs::path tetrahedron = dir / "tet.off";
  writeFile(tetrahedron, kNeedle);
  // Automatic cone placement finds no cones of angle pi that flatten a needle: a failure of the
  // computation, as a flow out of steps is. (With corners of valence 3 it is split at its edge
  // midpoints and flattened.)
  for (const char* command : {"flatten", "spline", "fit"}) {
    SECTION(command) {
      const bool flatten = std::string(command) == "flatten";
      const std::string output = quoted(dir / (flatten ? "o.obj" : "o.msp"));
      const nlohmann::json report = checkFailure(
          command,
          quoted(tetrahedron) + (flatten ? "" : " --min-corner-valence 2") + " -o " + output, 3,
          "tet.off", dir);
      CHECK(report["error"]["kind"] == "solver");
      CHECK_THAT(report["error"]["message"].get<std::string>(),
                 Catch::Contains("cone placement") && Catch::Contains("cannot flatten"));
    }
  }
  SECTION("the Ricci flow out of steps") {
    const nlohmann::json report =
        checkFailure("flatten",
                     mspline::test::realMeshPath("knot1.off") +
                         " -q --cones none --max-iterations 1 -o " + quoted(dir / "o.obj"),
                     3, "knot1.off", dir);
    CHECK(report["error"]["kind"] == "solver");
    CHECK_THAT(report["error"]["message"].get<std::string>(), Catch::Contains("Ricci flow"));
  }
  SECTION("a cone count the user asked for is the user's to change") {
    const nlohmann::json report =
        checkFailure("flatten", quoted(tetrahedron) + " --cones 0 -o " + quoted(dir / "o.obj"), 2,
                     "tet.off", dir);
    CHECK(report["error"]["kind"] == "input");
    CHECK_THAT(report["error"]["message"].get<std::string>(), Catch::Contains("Gauss-Bonnet"));
  }
}

TEST_CASE("error_policy: the error comes first, warnings after, and info reports it in JSON",
          "[cli]") {
  const fs::path dir = mspline::test::scratchDirectory("error_policy_order");
  // A quad (triangulated, with a warning) and a vertex no face uses (invalid).
  const fs::path scan = dir / "quad.obj";
  writeFile(scan, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\nf 1 2 3 4\n");
  const nlohmann::json repaired =
      checkFailure("repair", quoted(scan) + " -o " + quoted(dir / "out.obj"), 2, "quad.obj", dir);
  CHECK_THAT(repaired["error"]["message"].get<std::string>(), Catch::Contains("unreferenced"));
  const CommandResult repair =
      runCommand(cliPath() + " repair " + quoted(scan) + " -o " + quoted(dir / "out.obj"));
  CHECK_THAT(repair.err, Catch::Contains("\nwarning: 1 polygon was triangulated"));

  const nlohmann::json info = checkFailure("info", quoted(scan), 2, "quad.obj", dir);
  CHECK(info["valid"] == false);
  CHECK_FALSE(info["problems"].empty());
  CHECK(info["error"]["kind"] == "input");
  CHECK_THAT(info["error"]["message"].get<std::string>(), Catch::Contains("unreferenced"));
}

TEST_CASE("error_policy: an error map of a scan with a NaN vertex is refused", "[cli]") {
  const fs::path dir = mspline::test::scratchDirectory("error_policy_nan_scan");
  const std::string model = (dir / "t.msp").string();
  mspline::test::runJson("spline -q " + mspline::test::realMeshPath("knot1.off") +
                         " --kind tspline --cones none --control 500 -o " + model);
  const fs::path scan = dir / "nan.off";
  writeFile(scan, "OFF\n4 4 0\n0 0 0\n1 0 nan\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n");
  const CommandResult result =
      runCommand(cliPath() + " export " + model + " -o " + quoted(dir / "s.obj") + " --error-map " +
                 quoted(scan) + " " + quoted(dir / "err.ply") + " --json");
  CHECK(result.exitCode == 2);
  CHECK_THAT(onlyObject(result)["error"]["message"].get<std::string>(),
             Catch::Contains("nan.off") && Catch::Contains("finite"));
  CHECK_FALSE(fs::exists(dir / "err.ply"));
}
