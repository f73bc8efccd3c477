// `mspline view` end to end: screenshots, scripted edits and a crash, through the command (the
// OpenGL tests need a display: scripts/test runs the suite under xvfb-run when there is none).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "mspline/io/read_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/model_surface.h"
#include "mspline/viewer/controller.h"
#include "support/test_data.h"

using namespace mspline;

namespace {

// Also turns LeakSanitizer off for the commands run from here (in a sanitized build): Mesa's
// drivers are unloaded at exit and leave allocations it cannot attribute ("<unknown module>").
// The viewer's own state is leak-checked in process by the other viewer tests.
void requireDisplay() {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    FAIL(
        "no display: run the viewer tests under xvfb-run (scripts/test does when DISPLAY is "
        "unset)");
  const char* asan = std::getenv("ASAN_OPTIONS");
  const std::string options = std::string(asan ? asan : "") + ":detect_leaks=0";
  setenv("ASAN_OPTIONS", options.c_str(), 1);
}

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  bool background(std::size_t i) const {
    return rgb[3 * i] == 255 && rgb[3 * i + 1] == 255 && rgb[3 * i + 2] == 255;
  }
  bool same(const Image& o, std::size_t i) const {
    return rgb[3 * i] == o.rgb[3 * i] && rgb[3 * i + 1] == o.rgb[3 * i + 1] &&
           rgb[3 * i + 2] == o.rgb[3 * i + 2];
  }
};

Image readPng(const std::string& path) {
  Image image;
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &image.width, &image.height, &channels, 3);
  INFO(path);
  REQUIRE(data != nullptr);
  image.rgb.assign(data, data + std::size_t(image.width) * std::size_t(image.height) * 3);
  stbi_image_free(data);
  return image;
}

Image screenshot(const std::string& model, const std::string& path, const std::string& show) {
  const test::CommandResult r =
      test::runCommand(test::cliPath() + " view " + model + " --screenshot " + path +
                       " --width 480 --height 360 --show " + show + " -q");
  INFO(r.err);
  REQUIRE(r.exitCode == 0);
  return readPng(path);
}

std::string writeText(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

// The camera `mspline view` starts with at width x height: the model in view, azimuth 30,
// elevation 20.
viewer::Camera defaultCamera(const viewer::EditSession& session, int width, int height) {
  viewer::Camera camera;
  camera.width = width;
  camera.height = height;
  camera.fitTo(session.positions().colwise().minCoeff().transpose(),
               session.positions().colwise().maxCoeff().transpose());
  return camera;
}

std::vector<std::array<double, 3>> exportedVertices(const std::string& model,
                                                    const std::string& out) {
  const test::CommandResult r =
      test::runCommand(test::cliPath() + " export " + model + " -o " + out + " --resolution 4");
  INFO(r.err);
  REQUIRE(r.exitCode == 0);
  return io::readMesh(out).soup.positions;
}

}  // namespace

TEST_CASE("view: screenshots of bunny00's fitted model show the surface, the net, the checker",
          "[viewer][slow]") {
  requireDisplay();
  const std::string dir = test::scratchDirectory("view_bunny");
  const std::string model = test::fitModel("bunny00.off", "tribspline", dir + "/bunny.msp",
                                           "--control 1500 --max-control 2000 --rounds 1 "
                                           "--max-refinements 0");
  const Image surface = screenshot(model, dir + "/surface.png", "surface");
  const Image withNet = screenshot(model, dir + "/net.png", "surface,net");
  const Image netOnly = screenshot(model, dir + "/net-only.png", "net");
  const Image checker = screenshot(model, dir + "/checker.png", "surface,checker");
  const std::size_t pixels = std::size_t(surface.width) * std::size_t(surface.height);
  REQUIRE(surface.width == 480);
  REQUIRE(surface.height == 360);

  std::size_t covered = 0, netPixels = 0, changedByNet = 0, changedOnNet = 0, changedByChecker = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    covered += !surface.background(i);
    const bool onNet = !netOnly.background(i);
    netPixels += onNet;
    if (!surface.same(withNet, i)) {
      ++changedByNet;
      // The net drawn alone, widened by a pixel (antialiased edges): where the changes are.
      bool near = false;
      const int x = int(i % std::size_t(surface.width)), y = int(i / std::size_t(surface.width));
      for (int dy = -1; dy <= 1 && !near; ++dy)
        for (int dx = -1; dx <= 1 && !near; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u >= 0 && v >= 0 && u < surface.width && v < surface.height)
            near =
                !netOnly.background(std::size_t(v) * std::size_t(surface.width) + std::size_t(u));
        }
      changedOnNet += near;
    }
    changedByChecker += !surface.same(checker, i);
  }
  const double share = double(covered) / double(pixels);
  INFO("covered " << share << ", net pixels " << netPixels << ", changed by the net "
                  << changedByNet << " (" << changedOnNet << " on it), by the checker "
                  << changedByChecker);
  CHECK(share > 0.08);
  CHECK(share < 0.9);
  CHECK(netPixels > 0.02 * double(pixels));
  CHECK(changedByNet > 0.01 * double(pixels));
  CHECK(double(changedOnNet) >= 0.98 * double(changedByNet));
  CHECK(changedByChecker > 0.2 * double(covered));
}

TEST_CASE("view: a scripted drag moves one control point, the surface only in its support",
          "[viewer]") {
  requireDisplay();
  const std::string dir = test::scratchDirectory("view_scripted_edit");
  const std::string model = test::fitModel("knot1.off", "tspline", dir + "/knot.msp");
  const spline::SplineModel original = io::readSplineModel(model);
  const std::string bytes = test::fileText(model);
  // A control point the pointer picks at its place in the starting view, as a person would.
  viewer::EditSession session(original, model);
  viewer::Camera camera = defaultCamera(session, 640, 480);
  viewer::Controller controller(camera, &session);
  int row = -1;
  for (int candidate : session.net().points) {
    const Eigen::Vector3d s = camera.project(original.controlPoints.row(candidate).transpose());
    if (s.x() > 50 && s.x() < 590 && s.y() > 50 && s.y() < 430 &&
        controller.pick(s.x(), s.y()) == candidate) {
      row = candidate;
      break;
    }
  }
  REQUIRE(row >= 0);
  const std::string script =
      writeText(dir + "/drag.json", R"({"edits": [{"points": [)" + std::to_string(row) +
                                        R"(], "pixels": [25, -15], "steps": 6}]})");
  const nlohmann::json report = test::runJson("view " + model + " --apply " + script + " -o " +
                                              dir + "/edited.msp --width 640 --height 480 -q");
  INFO(report.dump(2));
  CHECK(report["edits"]["applied"] == 1);
  CHECK(report["edits"]["drag_frames"] == 6);
  CHECK(report["edits"]["evaluate_ms"]["max"].get<double>() > 0.0);
  const spline::SplineModel edited = io::readSplineModel(dir + "/edited.msp");
  REQUIRE(edited.controlPoints.rows() == original.controlPoints.rows());
  for (Eigen::Index r = 0; r < original.controlPoints.rows(); ++r) {
    if (r == row)
      CHECK(edited.controlPoints.row(r) != original.controlPoints.row(r));
    else
      REQUIRE(edited.controlPoints.row(r) == original.controlPoints.row(r));
  }
  CHECK(edited.weights == original.weights);
  CHECK(edited.surfaceVertices == original.surfaceVertices);
  CHECK(test::fileText(model) == bytes);  // saved elsewhere (-o): the model file untouched

  // The exported surfaces differ only at vertices the moved point's basis function reaches.
  const auto before = exportedVertices(model, dir + "/before.obj");
  const auto after = exportedVertices(dir + "/edited.msp", dir + "/after.obj");
  REQUIRE(before.size() == after.size());
  const spline::ModelSurface surface(original, model);
  const spline::SurfaceSamples samples =
      surface.samples(surface.tessellate(original.controlPoints, 4));
  REQUIRE(std::size_t(samples.value.rows()) == before.size());
  const Eigen::SparseMatrix<double> byColumn = samples.value;
  std::vector<char> inSupport(before.size(), 0);
  for (Eigen::SparseMatrix<double>::InnerIterator it(byColumn, row); it; ++it)
    inSupport[std::size_t(it.row())] = 1;
  int movedInside = 0, movedOutside = 0;
  for (std::size_t v = 0; v < before.size(); ++v)
    if (before[v] != after[v]) (inSupport[v] ? movedInside : movedOutside)++;
  CHECK(movedInside > 0);
  CHECK(movedOutside == 0);
}

TEST_CASE("view: undo in a script restores the model bit for bit", "[viewer]") {
  requireDisplay();
  const std::string dir = test::scratchDirectory("view_undo");
  const std::string model = test::fitModel("knot1.off", "subd", dir + "/knot.msp");
  const std::string bytes = test::fileText(model);
  const std::string script = writeText(
      dir + "/edits.json",
      R"({"edits": [{"points": [4], "offset": [0.1, 0.2, -0.3]}, {"points": [4, 9], "normal": 0.05},
                    {"undo": 2}, {"redo": 1}, {"undo": 1}]})");
  const nlohmann::json report = test::runJson("view " + model + " --apply " + script + " -q");
  CHECK(report["edits"]["undo_steps"] == 0);
  CHECK(test::fileText(model) == bytes);  // saved over itself: the same bytes
  CHECK(test::fileText(model + ".bak") == bytes);
}

TEST_CASE("view: killed during scripted edits, the autosave holds the edits before it",
          "[viewer]") {
  requireDisplay();
  namespace fs = std::filesystem;
  const std::string dir = test::scratchDirectory("view_crash");
  const std::string model = test::fitModel("knot1.off", "subd", dir + "/knot.msp");
  const std::string bytes = test::fileText(model);
  const spline::SplineModel original = io::readSplineModel(model);
  constexpr int kEdits = 80;
  REQUIRE(original.controlPoints.rows() > kEdits);
  const auto offsetOf = [](int i) { return Eigen::RowVector3d(0.0, 0.001 * (i + 1), 0.0); };
  nlohmann::json edits = nlohmann::json::array();
  for (int i = 0; i < kEdits; ++i) {
    const Eigen::RowVector3d o = offsetOf(i);
    edits.push_back({{"points", {i}}, {"offset", {o[0], o[1], o[2]}}, {"steps", 2}});
    edits.push_back({{"wait", 0.05}});
  }
  const std::string script =
      writeText(dir + "/edits.json", nlohmann::json{{"edits", edits}}.dump());
  const std::string autosave = dir + "/knot.autosave.msp";

  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    const std::string log = dir + "/view.log";
    if (!freopen(log.c_str(), "w", stderr) || !freopen("/dev/null", "w", stdout)) _exit(126);
    execl(test::cliPath().c_str(), "mspline", "view", model.c_str(), "--apply", script.c_str(),
          "--autosave", "0.2", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Kill it a little after its first autosave, well before its last edit.
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(autosave) &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  INFO(test::fileText(dir + "/view.log"));
  REQUIRE(WIFSIGNALED(status));
  REQUIRE(fs::exists(autosave));

  // The autosave loads and holds the first k edits, exactly, and nothing else.
  const spline::SplineModel saved = io::readSplineModel(autosave);
  REQUIRE(saved.controlPoints.rows() == original.controlPoints.rows());
  int k = 0;
  while (k < kEdits && saved.controlPoints.row(k) == original.controlPoints.row(k) + offsetOf(k))
    ++k;
  INFO("edits in the autosave: " << k);
  CHECK(k >= 1);
  CHECK(k < kEdits);
  for (Eigen::Index r = k; r < original.controlPoints.rows(); ++r)
    REQUIRE(saved.controlPoints.row(r) == original.controlPoints.row(r));
  CHECK(test::fileText(model) == bytes);  // never saved: the model file untouched
  viewer::EditSession recovered(saved, autosave);
  CHECK(recovered.positions().allFinite());
}

TEST_CASE("view: bad files and scripts are clear errors, nothing written", "[viewer]") {
  const std::string dir = test::scratchDirectory("view_bad_input");
  const test::CommandResult missing = test::runCommand(
      test::cliPath() + " view " + dir + "/missing.msp --screenshot " + dir + "/x.png");
  CHECK(missing.exitCode == 2);
  CHECK(missing.err.find(dir + "/missing.msp") != std::string::npos);
  const std::string garbage = writeText(dir + "/garbage.msp", "not a model");
  const test::CommandResult bad = test::runCommand(test::cliPath() + " view " + garbage);
  CHECK(bad.exitCode == 2);
  CHECK(bad.err.find(garbage) != std::string::npos);
  const std::string model = test::fitModel("knot1.off", "subd", dir + "/knot.msp");
  const std::string bytes = test::fileText(model);
  const std::string script =
      writeText(dir + "/bad.json", R"({"edits": [{"points": [99999], "offset": [0, 0, 1]}]})");
  const test::CommandResult badScript =
      test::runCommand(test::cliPath() + " view " + model + " --apply " + script);
  CHECK(badScript.exitCode == 2);
  CHECK(badScript.err.find(script) != std::string::npos);
  CHECK(badScript.err.find("edit 1") != std::string::npos);
  CHECK(test::fileText(model) == bytes);
  CHECK(!std::filesystem::exists(model + ".bak"));
  const test::CommandResult twoModels =
      test::runCommand(test::cliPath() + " view " + model + " " + model);
  CHECK(twoModels.exitCode == 2);
  const test::CommandResult badCamera = test::runCommand(
      test::cliPath() + " view " + model + " --screenshot " + dir + "/y.png --camera 1,2");
  CHECK(badCamera.exitCode == 2);
  CHECK(!std::filesystem::exists(dir + "/y.png"));
}

TEST_CASE("view: a mesh without a model is shown shaded, its report says what was loaded",
          "[viewer]") {
  requireDisplay();
  const std::string dir = test::scratchDirectory("view_mesh");
  const nlohmann::json report =
      test::runJson("view " + test::realMeshPath("knot1.off") + " --screenshot " + dir +
                    "/knot.png --width 320 --height 240 -q");
  CHECK(report["mesh"]["vertices"] == 3200);
  CHECK(!report.contains("model"));
  const Image image = readPng(dir + "/knot.png");
  std::size_t covered = 0;
  std::set<int> shades;
  for (std::size_t i = 0; i < image.rgb.size() / 3; ++i) {
    if (image.background(i)) continue;
    ++covered;
    shades.insert(image.rgb[3 * i] * 65536 + image.rgb[3 * i + 1] * 256 + image.rgb[3 * i + 2]);
  }
  CHECK(double(covered) / double(image.rgb.size() / 3) > 0.1);
  CHECK(shades.size() > 50);  // shaded, not one flat color
  CHECK(report["screenshot"]["covered"].get<double>() ==
        Approx(double(covered) / double(image.rgb.size() / 3)));
}
