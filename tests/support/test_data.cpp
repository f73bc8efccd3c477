#include "support/test_data.h"

#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mspline/io/load_mesh.h"
#include "mspline/io/spline_model_file.h"

namespace mspline::test {

namespace fs = std::filesystem;

std::string realMeshPath(const std::string& name) {
  const char* env = std::getenv("MSPLINE_DATA_DIR");
  fs::path dir = env ? fs::path(env) : fs::path(MSPLINE_SOURCE_DIR) / "data" / "meshes";
  fs::path path = dir / name;
  if (!fs::exists(path))
    FAIL("real mesh " << path.string() << " is missing: run scripts/fetch-data");
  return path.string();
}

structure::TriMesh realMesh(const std::string& name) {
  auto loaded = io::loadMesh(realMeshPath(name));
  REQUIRE(loaded.mesh.has_value());
  return *loaded.mesh;
}

std::string cliPath() {
  return MSPLINE_CLI_PATH;
}

std::string scratchDirectory(const std::string& testName) {
  fs::path dir = fs::temp_directory_path() / "mspline-tests" / testName;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string firstLine(const std::string& text) {
  return text.substr(0, text.find('\n'));
}

std::size_t countOf(const std::string& text, const std::string& word) {
  std::size_t count = 0;
  for (auto at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) ++count;
  return count;
}

std::string fileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

CommandResult runCommand(const std::string& commandLine) {
  fs::path dir = fs::temp_directory_path() / "mspline-tests" / "commands";
  fs::create_directories(dir);
  static int counter = 0;
  std::string stem = (dir / std::to_string(::getpid())).string() + "-" + std::to_string(counter++);
  std::string full = commandLine + " > " + stem + ".out 2> " + stem + ".err < /dev/null";
  int status = std::system(full.c_str());
  CommandResult result;
  if (WIFEXITED(status)) {
    result.exitCode = WEXITSTATUS(status);
  } else {
    result.exitCode = -1;
  }
  // The shell reports a child killed by a signal as 128 + signal.
  if (result.exitCode > 128) result.exitCode = -1;
  result.out = fileText(stem + ".out");
  result.err = fileText(stem + ".err");
  fs::remove(stem + ".out");
  fs::remove(stem + ".err");
  return result;
}

nlohmann::json runJson(const std::string& arguments, int expectedExit) {
  const CommandResult result = runCommand(cliPath() + " " + arguments + " --json");
  INFO(arguments << "\nstderr: " << result.err);
  REQUIRE(result.exitCode == expectedExit);
  return nlohmann::json::parse(result.out);
}

std::string fitModel(const std::string& meshName, const std::string& kind, const std::string& path,
                     const std::string& arguments) {
  const CommandResult fit = runCommand(cliPath() + " fit " + realMeshPath(meshName) + " --kind " +
                                       kind + " " + arguments + " -q -o " + path);
  INFO("fit " << meshName << " " << kind << ": " << fit.err);
  REQUIRE(fit.exitCode == 0);
  return path;
}

const spline::SplineModel& fittedModel(const std::string& meshName, const std::string& kind,
                                       const std::string& arguments) {
  static std::map<std::string, spline::SplineModel> models;
  const std::string key =
      meshName + "-" + kind + "-" + std::to_string(std::hash<std::string>()(arguments));
  const auto found = models.find(key);
  if (found != models.end()) return found->second;
  // Shared by the test processes, as long as the command is the same build (its size and time):
  // a fit under the sanitizers takes many seconds, and a dozen test cases read the same models.
  // Fitted in a directory of this process's own, then renamed: a reader never sees half a file.
  const fs::path command(cliPath());
  const std::string build = std::to_string(fs::file_size(command)) + "-" +
                            std::to_string(fs::last_write_time(command).time_since_epoch().count());
  const fs::path cache = fs::temp_directory_path() / "mspline-tests" / "fitted";
  fs::create_directories(cache);
  const fs::path cached = cache / (key + "-" + build + ".msp");
  if (!fs::exists(cached)) {
    const std::string dir = scratchDirectory("fitted_" + key + "_" + std::to_string(getpid()));
    fs::rename(fitModel(meshName, kind, dir + "/model.msp", arguments), cached);
    fs::remove_all(dir);
  }
  return models[key] = io::readSplineModel(cached.string());
}

const spline::SplineModel& headModel(const std::string& kind) {
  return fittedModel("head.off", kind, kSmallFit);
}

}  // namespace mspline::test
