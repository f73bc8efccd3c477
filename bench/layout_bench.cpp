// Benchmark and data-set sweep of the seamless quad layout that T-spline and subd fits start
// from: per mesh, the same steps as `mspline fit --kind tspline` up to its first spline space
// (holes closed by fill patches, a coarse polyhedron split at its edge midpoints, the flat metric
// with quarter-turn cones, the motorcycle layout, its quantization and the T-mesh:
// spline/model/build_spline.h), and a table of
// what came out: the stage that failed and why, or the layout's figures (cones, extraordinary
// points, collapsed segments, the cells' anisotropy p99 and max) and its time against the
// flattening's (cones + Ricci flow + its layout).
// Targets (issue 19): a layout on every valid mesh; anisotropy p99 <= 3 and max <= 6; layout +
// quantization no slower than the flattening, on bunny00 and on a mesh of about 1M faces (bunny00
// subdivided, the last row).
// Each mesh runs in a child process (a crash or a hang costs one row; --limit seconds each).
// Usage: layout_bench [--control N] [--limit SECONDS] [--faces F] [--min-corner-valence 2|3]
//                     [MESH...]
//   MESH: files or names in data/meshes (default: every .off there); F: the size of the
//   subdivided bunny00 row (default 1000000, 0: none).
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "mspline/io/load_mesh.h"
#include "mspline/spline/model/build_spline.h"
#include "mspline/spline/model/quad_layout_flattening.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/flatten/flatten_surface.h"
#include "mspline/structure/mesh/cap_holes.h"
#include "mspline/structure/mesh/subdivide.h"
#include "mspline/structure/topology/topology.h"

using namespace mspline;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

namespace {

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// One mesh's outcome, sent from the child as one line of tab-separated fields.
struct Row {
  std::string name;
  std::string status = "ok";  // or "<stage>: <why>"
  long faces = 0;
  int holes = 0, subdivisions = 0, cones = 0, extraordinary = 0, traces = 0, collapsed = 0,
      cells = 0;
  double anisotropyP99 = 0.0, anisotropyMax = 0.0;
  double flattenSeconds = 0.0, layoutSeconds = 0.0;

  std::string encode() const {
    std::string why = status;
    std::replace(why.begin(), why.end(), '\t', ' ');
    std::replace(why.begin(), why.end(), '\n', ' ');
    std::ostringstream out;
    out.precision(17);
    out << why << '\t' << faces << '\t' << holes << '\t' << subdivisions << '\t' << cones << '\t'
        << extraordinary << '\t' << traces << '\t' << collapsed << '\t' << cells << '\t'
        << anisotropyP99 << '\t' << anisotropyMax << '\t' << flattenSeconds << '\t' << layoutSeconds
        << '\n';
    return out.str();
  }
  void decode(const std::string& line) {
    std::istringstream in(line);
    std::getline(in, status, '\t');
    std::string field;
    std::vector<std::string> fields;
    while (std::getline(in, field, '\t')) fields.push_back(field);
    if (fields.size() != 12) return;
    faces = std::stol(fields[0]);
    holes = std::stoi(fields[1]);
    subdivisions = std::stoi(fields[2]);
    cones = std::stoi(fields[3]);
    extraordinary = std::stoi(fields[4]);
    traces = std::stoi(fields[5]);
    collapsed = std::stoi(fields[6]);
    cells = std::stoi(fields[7]);
    anisotropyP99 = std::stod(fields[8]);
    anisotropyMax = std::stod(fields[9]);
    flattenSeconds = std::stod(fields[10]);
    layoutSeconds = std::stod(fields[11]);
  }
};

// The steps of fit up to its first space, on one mesh (in the child).
Row layOut(const std::string& path, long subdivideTo, int control, int minCornerValence) {
  Row row;
  std::optional<structure::TriMesh> loaded;
  try {
    loaded = io::loadMesh(path).mesh;
  } catch (const structure::Error& error) {
    row.status = std::string("input: ") + error.what();
    return row;
  }
  structure::TriMesh mesh = std::move(*loaded);
  if (subdivideTo > 0) mesh = structure::subdivideToAtLeast(mesh, std::size_t(subdivideTo));
  row.faces = long(mesh.n_faces());
  std::string stage = "holes";
  try {
    if (!structure::analyzeTopology(mesh).closed) {
      structure::CappedSurface capped = structure::capHoles(mesh);
      row.holes = int(capped.caps);
      mesh = std::move(capped.mesh);
    }
    spline::BuildSplineOptions build;
    build.kind = spline::SpaceKind::TSpline;
    build.control = control;
    const spline::QuadLayoutFlattening quad =
        spline::quadLayoutFlattening(mesh, minCornerValence, build);
    row.subdivisions = quad.midpointSubdivisions;
    for (int level = 0; level < row.subdivisions; ++level)
      mesh = structure::subdivideMidpoint(mesh);
    stage = "flatten";
    const auto start = Clock::now();
    const structure::Flattening flattening = structure::flattenSurface(mesh, quad.options);
    row.flattenSeconds = since(start);
    row.cones = int(flattening.cones.size());
    if (!flattening.converged) {
      row.status = "flatten: " + flattening.message;
      return row;
    }
    stage = "layout";
    const spline::SplineSpaceBuild space = spline::buildSpline(flattening, build);
    for (const auto& [name, seconds] : space.stageSeconds)
      if (name == "grid") row.layoutSeconds += seconds;
    row.extraordinary = space.grid.extraordinaryPoints;
    row.traces = space.grid.traces;
    row.collapsed = space.grid.collapsedSegments;
    row.cells = space.model.tmesh.numFaces();
    row.anisotropyP99 = space.grid.anisotropyP99;
    row.anisotropyMax = space.grid.anisotropy;
  } catch (const std::exception& error) {
    row.status = stage + ": " + error.what();
  }
  return row;
}

// Runs layOut in a child process; a crash or the time limit is the row's status.
Row runChild(const std::string& path, const std::string& name, long subdivideTo, int control,
             int minCornerValence, double limit) {
  Row row;
  row.name = name;
  std::fflush(stdout);
  int ends[2];
  if (pipe(ends) != 0) {
    row.status = "bench: no pipe";
    return row;
  }
  const auto start = Clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    close(ends[0]);
    const std::string line = layOut(path, subdivideTo, control, minCornerValence).encode();
    const ssize_t written = write(ends[1], line.data(), line.size());
    _exit(written == ssize_t(line.size()) ? 0 : 1);
  }
  close(ends[1]);
  std::string received;
  bool timedOut = false;
  for (;;) {
    const double left = limit - since(start);
    if (left <= 0) {
      kill(pid, SIGKILL);
      timedOut = true;
      break;
    }
    pollfd fd{ends[0], POLLIN, 0};
    if (poll(&fd, 1, int(std::min(left, 1.0) * 1000) + 1) <= 0) continue;
    char buffer[4096];
    const ssize_t n = read(ends[0], buffer, sizeof buffer);
    if (n <= 0) break;
    received.append(buffer, std::size_t(n));
  }
  close(ends[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (timedOut) {
    row.status = "bench: stopped at the time limit";
  } else if (received.empty()) {
    row.status = WIFSIGNALED(status) ? "crash: signal " + std::to_string(WTERMSIG(status))
                                     : "crash: no report";
  } else {
    row.decode(received.substr(0, received.find('\n')));
  }
  return row;
}

bool meetsAnisotropy(const Row& row) {
  return row.status == "ok" && row.anisotropyP99 <= 3.0 && row.anisotropyMax <= 6.0;
}

}  // namespace

int main(int argc, char** argv) {
  int control = 6000;
  int minCornerValence = 3;
  double limit = 900.0;
  long bigFaces = 1000000;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--control" || arg == "--limit" || arg == "--faces" ||
         arg == "--min-corner-valence") &&
        i + 1 < argc) {
      const std::string value = argv[++i];
      if (arg == "--min-corner-valence") minCornerValence = std::stoi(value);
      if (arg == "--control") control = std::stoi(value);
      if (arg == "--limit") limit = std::stod(value);
      if (arg == "--faces") bigFaces = std::stol(value);
    } else {
      paths.push_back(arg);
    }
  }
  if (minCornerValence < 2 || minCornerValence > 3) {
    std::fprintf(stderr, "layout_bench: --min-corner-valence must be 2 or 3\n");
    return 2;
  }
  const fs::path data = fs::path(MSPLINE_SOURCE_DIR) / "data" / "meshes";
  for (std::string& path : paths)
    if (!fs::exists(path) && fs::exists(data / path)) path = (data / path).string();
  if (paths.empty()) {
    if (!fs::is_directory(data)) {
      std::fprintf(stderr, "layout_bench: %s is missing: run scripts/fetch-data\n",
                   data.string().c_str());
      return 2;
    }
    for (const auto& entry : fs::directory_iterator(data))
      if (entry.path().extension() == ".off") paths.push_back(entry.path().string());
    std::sort(paths.begin(), paths.end());
  }
  std::printf(
      "layout of fit --kind tspline --min-corner-valence %d, %d control points wanted, %.0f s "
      "limit per mesh\n\n",
      minCornerValence, control, limit);
  std::printf("%-28s %9s %5s %3s %5s %6s %6s %5s %7s %7s %7s %8s %8s %6s  %s\n", "mesh", "faces",
              "holes", "sub", "cones", "extra", "traces", "coll", "cells", "aniso99", "anisoMx",
              "flat s", "layout s", "ratio", "status");
  std::vector<Row> rows;
  const auto print = [](const Row& row) {
    std::printf("%-28s %9ld %5d %3d %5d %6d %6d %5d %7d %7.2f %7.2f %8.2f %8.2f %6.2f  %s\n",
                row.name.c_str(), row.faces, row.holes, row.subdivisions, row.cones,
                row.extraordinary, row.traces, row.collapsed, row.cells, row.anisotropyP99,
                row.anisotropyMax, row.flattenSeconds, row.layoutSeconds,
                row.flattenSeconds > 0.0 ? row.layoutSeconds / row.flattenSeconds : 0.0,
                row.status.substr(0, 160).c_str());
    std::fflush(stdout);
  };
  for (const std::string& path : paths) {
    rows.push_back(
        runChild(path, fs::path(path).filename().string(), 0, control, minCornerValence, limit));
    print(rows.back());
  }
  std::optional<Row> big;
  if (bigFaces > 0) {
    big = runChild((data / "bunny00.off").string(),
                   "bunny00.off to " + std::to_string(bigFaces) + " faces", bigFaces, control,
                   minCornerValence, limit);
    print(*big);
  }

  int valid = 0, laidOut = 0, anisotropic = 0;
  std::vector<std::string> failures;
  for (const Row& row : rows) {
    if (row.status.rfind("input:", 0) == 0) continue;
    ++valid;
    if (row.status == "ok") {
      ++laidOut;
      anisotropic += !meetsAnisotropy(row);
    } else {
      failures.push_back(row.name + " (" + row.status.substr(0, row.status.find(':')) + ")");
    }
  }
  std::printf(
      "\n%zu files, %d valid; a layout on %d (target: all), the cells' anisotropy within "
      "p99 <= 3 and max <= 6 on %d of them\n",
      rows.size(), valid, laidOut, laidOut - anisotropic);
  std::string list;
  for (const std::string& failure : failures) list += (list.empty() ? "" : ", ") + failure;
  std::printf("no layout: %s\n", list.empty() ? "none" : list.c_str());
  for (const Row& row : rows)
    if (row.name == "bunny00.off")
      std::printf(
          "bunny00.off: layout + quantization %.2f s, flattening %.2f s, ratio %.2f "
          "(target <= 1)\n",
          row.layoutSeconds, row.flattenSeconds,
          row.layoutSeconds / std::max(row.flattenSeconds, 1e-9));
  if (big)
    std::printf("%s: layout + quantization %.2f s, flattening %.2f s, ratio %.2f (target <= 1)%s\n",
                big->name.c_str(), big->layoutSeconds, big->flattenSeconds,
                big->layoutSeconds / std::max(big->flattenSeconds, 1e-9),
                big->status == "ok" ? "" : (" [" + big->status + "]").c_str());
  return 0;
}
