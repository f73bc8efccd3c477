// Benchmark: how long a frame of dragging control points takes in the viewer (issue 8: under
// 16 ms with at least 5,000 control points). Two parts, measured separately:
//  - CPU: viewer::EditSession re-evaluating the moved control point's support (positions and
//    normals) for every drag frame, then packing the changed vertices' floats as the renderer
//    does before its upload; no OpenGL.
//  - OpenGL (only when a display is there, e.g. under xvfb-run): `mspline view MODEL --apply` with
//    scripted drags, whose report separates re-evaluation, buffer upload and drawing (Mesa).
//
// Usage: viewer_bench [MODEL.msp] [--points N] [--frames F] [--resolution R]
//        (default: build/demo/bunny.msp from scripts/demo, 200 control points, 10 frames each,
//        resolution 6 as the viewer)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mspline/io/spline_model_file.h"
#include "mspline/viewer/edit_session.h"

using namespace mspline;
using Clock = std::chrono::steady_clock;

namespace {

double seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct Stats {
  double mean = 0, median = 0, p99 = 0, max = 0;
};

Stats statsOf(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  for (double x : v) s.mean += x / double(v.size());
  s.median = v[v.size() / 2];
  s.p99 = v[std::min(v.size() - 1, std::size_t(0.99 * double(v.size())))];
  s.max = v.back();
  return s;
}

void print(const char* what, const Stats& s, const char* unit) {
  std::printf("  %-34s mean %8.3f  median %8.3f  p99 %8.3f  max %8.3f %s\n", what, s.mean, s.median,
              s.p99, s.max, unit);
}

}  // namespace

int main(int argc, char** argv) {
  std::string modelPath = MSPLINE_SOURCE_DIR "/build/demo/bunny.msp";
  int points = 200, frames = 10, resolution = 6;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--points" && i + 1 < argc)
      points = std::atoi(argv[++i]);
    else if (a == "--frames" && i + 1 < argc)
      frames = std::atoi(argv[++i]);
    else if (a == "--resolution" && i + 1 < argc)
      resolution = std::atoi(argv[++i]);
    else
      modelPath = a;
  }
  if (!std::filesystem::exists(modelPath)) {
    std::cerr << "viewer_bench: " << modelPath
              << " does not exist (run scripts/demo, or give a .msp model)\n";
    return 1;
  }
  const auto loadStart = Clock::now();
  viewer::EditSession session(io::readSplineModel(modelPath), modelPath, {resolution});
  const double loadSeconds = seconds(loadStart);
  const int rows = int(session.model().controlPoints.rows());
  std::printf(
      "viewer_bench: %s: %s, %d control points, surface %lld vertices (resolution %d); "
      "set-up (tessellation, basis rows) %.2f s\n",
      modelPath.c_str(), session.surface().kindName().c_str(), rows,
      static_cast<long long>(session.positions().rows()), resolution, loadSeconds);

  // CPU: drag `points` control points spread over the rows, `frames` steps each.
  std::vector<double> evaluate, pack, vertices;
  std::vector<float> mirror(std::size_t(session.positions().rows()) * 6, 0.0f);
  const double size =
      (session.positions().colwise().maxCoeff() - session.positions().colwise().minCoeff()).norm();
  for (int k = 0; k < points; ++k) {
    const int row = int((long long)(k)*rows / points);
    session.beginDrag({row});
    for (int f = 1; f <= frames; ++f) {
      const auto start = Clock::now();
      session.dragTo({Eigen::Vector3d(0.002, -0.001, 0.0015) * size * f});
      evaluate.push_back(seconds(start) * 1e3);
      const auto packStart = Clock::now();
      for (int v : session.changedVertices())
        for (int c = 0; c < 3; ++c) {
          mirror[6 * std::size_t(v) + std::size_t(c)] = float(session.positions()(v, c));
          mirror[6 * std::size_t(v) + 3 + std::size_t(c)] = float(session.normals()(v, c));
        }
      pack.push_back(seconds(packStart) * 1e3);
      vertices.push_back(double(session.changedVertices().size()));
    }
    session.endDrag();
  }
  const Stats e = statsOf(evaluate), p = statsOf(pack), n = statsOf(vertices);
  std::printf("CPU, %zu drag frames (one control point each):\n", evaluate.size());
  print("re-evaluation", e, "ms");
  print("packing floats for the upload", p, "ms");
  print("vertices re-evaluated per frame", n, "");
  std::printf("  worst frame %.3f ms = %.1f%% of the 16 ms budget\n", e.max + p.max,
              100.0 * (e.max + p.max) / 16.0);

  const char* display = std::getenv("DISPLAY");
  if (!display || !*display) {
    std::printf("OpenGL: no display (run under xvfb-run for the upload and drawing times)\n");
    return 0;
  }
  // OpenGL: the real viewer, scripted drags of the same kind, into a scratch copy of the model.
  const std::string dir =
      (std::filesystem::temp_directory_path() / "mspline-viewer-bench").string();
  std::filesystem::create_directories(dir);
  nlohmann::json edits = nlohmann::json::array();
  for (int k = 0; k < std::min(points, 50); ++k)
    edits.push_back({{"points", {int((long long)(k)*rows / std::min(points, 50))}},
                     {"offset", {0.01 * size, 0.0, 0.0}},
                     {"steps", frames}});
  std::ofstream(dir + "/edits.json") << nlohmann::json{{"edits", edits}}.dump();
  const std::string command = std::string(MSPLINE_CLI_PATH) + " view " + modelPath + " --apply " +
                              dir + "/edits.json -o " + dir + "/edited.msp --resolution " +
                              std::to_string(resolution) + " --json -q > " + dir + "/report.json";
  if (std::system(command.c_str()) != 0) {
    std::cerr << "viewer_bench: `" << command << "` failed\n";
    return 1;
  }
  nlohmann::json report;
  std::ifstream(dir + "/report.json") >> report;
  const nlohmann::json& r = report["edits"];
  std::printf("OpenGL (mspline view --apply, %d drag frames, Mesa %s):\n",
              r["drag_frames"].get<int>(), "software rendering unless a GPU driver is loaded");
  for (const char* key : {"evaluate_ms", "upload_ms", "render_ms"})
    std::printf("  %-34s mean %8.3f  median %8.3f  max %8.3f ms\n", key,
                r[key]["mean"].get<double>(), r[key]["median"].get<double>(),
                r[key]["max"].get<double>());
  const double cpu = r["evaluate_ms"]["max"].get<double>() + r["upload_ms"]["max"].get<double>();
  std::printf(
      "  re-evaluation + upload, worst frame: %.3f ms = %.1f%% of 16 ms; drawing (Mesa) "
      "median %.1f ms\n",
      cpu, 100.0 * cpu / 16.0, r["render_ms"]["median"].get<double>());
  return 0;
}
