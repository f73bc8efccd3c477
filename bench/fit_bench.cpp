// Benchmark: `mspline fit` (issue 7) on scans of about 10k to 1M+ vertices, to give the fitting
// time per scan vertex and how it grows with the scan. The scans are a real closed scan subdivided
// 1-to-4 (structure/mesh/subdivide.h) to at least 90% of each size asked; sizes below the scan come
// from a smaller real scan subdivided the same way. Every size runs the real command as a child
// process (`mspline fit SCAN -o MODEL --kind KIND
// --tolerance 1e-3 --max-control 8000 --json`) so the figures are what a user sees: its JSON
// report, its peak resident memory, and its progress lines on stderr, timestamped here, which show
// where a run that fails or passes the time limit spent its time.
//
// Usage: fit_bench [--limit SECONDS] [SCAN [KIND [VERTICES...]]]
//        (defaults: 600 s per size, bunny00.off, tspline, 10000 40000 160000 640000 1000000)
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mspline/io/load_mesh.h"
#include "mspline/io/write_mesh.h"
#include "mspline/structure/mesh/subdivide.h"

namespace fs = std::filesystem;
using namespace mspline;
using Clock = std::chrono::steady_clock;

namespace {

// The smaller scan that sizes below the main scan are made from: closed, genus 0, 3,643 vertices.
// Not elephant.off (genus 3: its T-spline grid has 96,541 cells for a budget of 8000), cow.off (no
// valid layout), homer.off (tessellation fails) or mushroom.off (it has a hole).
constexpr const char* kSmallScan = MSPLINE_SOURCE_DIR "/data/meshes/retinal.off";

struct ChildRun {
  int exitCode = -1;                                  // -1: killed (by the time limit or a signal)
  bool timedOut = false;                              // killed at the time limit
  double seconds = 0;                                 // wall time of the child
  double peakMiB = 0;                                 // the child's peak resident memory
  std::vector<std::pair<double, std::string>> lines;  // stderr lines, seconds after the start
};

// Runs argv[0] with its stdout into `stdoutPath`, reading its stderr line by line; kills it after
// `limit` seconds.
ChildRun runChild(const std::vector<std::string>& argv, const std::string& stdoutPath,
                  double limit) {
  std::fflush(stdout);  // the child must not inherit (and print again) what is still buffered
  int pipeEnds[2];
  if (pipe(pipeEnds) != 0) return {};
  const auto start = Clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    close(pipeEnds[0]);
    if (!freopen(stdoutPath.c_str(), "w", stdout)) _exit(127);
    dup2(pipeEnds[1], STDERR_FILENO);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  close(pipeEnds[1]);
  ChildRun run;
  std::string pending;
  const auto since = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  for (;;) {
    const double left = limit - since();
    if (left <= 0) {
      kill(pid, SIGKILL);
      run.timedOut = true;
      break;
    }
    pollfd fd{pipeEnds[0], POLLIN, 0};
    if (poll(&fd, 1, int(std::min(left, 1.0) * 1000) + 1) <= 0) continue;
    char buffer[4096];
    const ssize_t n = read(pipeEnds[0], buffer, sizeof buffer);
    if (n <= 0) break;  // end of file: the child has exited
    pending.append(buffer, std::size_t(n));
    for (std::size_t end; (end = pending.find('\n')) != std::string::npos;) {
      run.lines.emplace_back(since(), pending.substr(0, end));
      pending.erase(0, end + 1);
    }
  }
  close(pipeEnds[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  run.seconds = since();
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.peakMiB = usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
  return run;
}

// One row of the table: a scan size and what fit reported on it.
struct Row {
  std::size_t vertices = 0;
  std::string source;  // "bunny00.off x2": the mesh and its subdivision count
  ChildRun run;
  std::optional<nlohmann::json> report;  // fit's JSON report, when it succeeded
};

// The main scan subdivided to at least 0.9 * `target` vertices; the small scan instead when the
// main scan alone has more than twice the target (sizes below the main scan).
std::pair<structure::TriMesh, std::string> scanOfSize(
    const std::vector<std::pair<structure::TriMesh, std::string>>& scans, std::size_t target) {
  const std::size_t which = scans[0].first.n_vertices() > 2 * target ? 1 : 0;
  structure::TriMesh mesh = scans[which].first;
  int levels = 0;
  for (; double(mesh.n_vertices()) < 0.9 * double(target); ++levels)
    mesh = structure::subdivideMidpoint(mesh);
  return {std::move(mesh), scans[which].second + " x" + std::to_string(levels)};
}

double stage(const nlohmann::json& report, const char* name) {
  const auto& stages = report.at("stage_seconds");
  return stages.contains(name) ? stages.at(name).get<double>() : 0.0;
}

// The stage that took longest (the atlas' own sub-stages are inside "atlas").
std::string dominantStage(const nlohmann::json& report) {
  std::string best;
  double bestSeconds = -1.0;
  for (const auto& [name, seconds] : report.at("stage_seconds").items()) {
    if (name == "cones" || name == "ricci_flow" || name == "layout" || name == "flips" ||
        name == "holonomy")
      continue;
    if (seconds.get<double>() > bestSeconds) best = name, bestSeconds = seconds.get<double>();
  }
  char text[96];
  std::snprintf(text, sizeof text, "%s %.0f%%", best.c_str(),
                100.0 * bestSeconds / report.at("seconds").get<double>());
  return text;
}

void printStages(const Row& row) {
  if (row.report) {
    std::printf("  %zu vertices: stage seconds", row.vertices);
    for (const auto& [name, seconds] : row.report->at("stage_seconds").items())
      std::printf(" %s %.2f", name.c_str(), seconds.get<double>());
    std::printf("; refinement rounds %zu; space %s\n", row.report->at("refinement").size(),
                row.report->at("space").dump().c_str());
    return;
  }
  // No report: the timestamped progress lines say which stage the time went to.
  std::printf("  %zu vertices: %s after %.1f s; its progress (seconds from the start):\n",
              row.vertices,
              row.run.timedOut ? "killed at the time limit"
                               : ("failed, exit " + std::to_string(row.run.exitCode)).c_str(),
              row.run.seconds);
  for (const auto& [at, line] : row.run.lines) std::printf("    %8.1f  %s\n", at, line.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  double limit = 600.0;
  int next = 1;
  if (argc > 2 && std::string(argv[1]) == "--limit") limit = std::stod(argv[2]), next = 3;
  const std::string source =
      argc > next ? argv[next] : MSPLINE_SOURCE_DIR "/data/meshes/bunny00.off";
  const std::string kind = argc > next + 1 ? argv[next + 1] : "tspline";
  std::vector<std::size_t> targets;
  for (int i = next + 2; i < argc; ++i) targets.push_back(std::stoul(argv[i]));
  if (targets.empty()) targets = {10000, 40000, 160000, 640000, 1000000};
  const std::string mspline = MSPLINE_CLI_PATH;

  std::vector<std::pair<structure::TriMesh, std::string>> scans;
  for (const std::string& path : {source, std::string(kSmallScan)})
    scans.emplace_back(*io::loadMesh(path).mesh, fs::path(path).filename().string());
  const fs::path dir =
      fs::temp_directory_path() / ("mspline-fit-bench-" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::printf(
      "fit_bench: mspline fit --kind %s --tolerance 1e-3 --max-control 8000 on %s (%zu vertices) "
      "subdivided, sizes below it from %s; %.0f s limit per size\n",
      kind.c_str(), scans[0].second.c_str(), scans[0].first.n_vertices(), scans[1].second.c_str(),
      limit);

  std::vector<Row> rows;
  for (std::size_t target : targets) {
    Row row;
    {
      auto [mesh, name] = scanOfSize(scans, target);
      row.vertices = mesh.n_vertices();
      row.source = name;
      io::writeMesh((dir / "scan.off").string(), mesh);
    }
    row.run =
        runChild({mspline, "fit", (dir / "scan.off").string(), "-o", (dir / "model.msp").string(),
                  "--kind", kind, "--tolerance", "1e-3", "--max-control", "8000", "--json"},
                 (dir / "report.json").string(), limit);
    if (row.run.exitCode == 0) {
      std::ifstream in(dir / "report.json");
      row.report = nlohmann::json::parse(in);
    }
    std::printf("fit_bench: %zu vertices (%s): %s in %.1f s, peak %.0f MiB\n", row.vertices,
                row.source.c_str(),
                row.report         ? "done"
                : row.run.timedOut ? "TIME LIMIT"
                                   : "FAILED",
                row.run.seconds, row.run.peakMiB);
    printStages(row);
    rows.push_back(std::move(row));
  }
  fs::remove_all(dir);

  // Growth exponents log(t2 / t1) / log(n2 / n1) against the previous size that succeeded.
  std::printf("\n%9s %-17s %9s %9s %8s %8s %8s %9s %9s %6s %5s %5s %8s  %s\n", "vertices", "scan",
              "total s", "fit s", "atlas s", "us/v", "fit us/v", "rms", "max", "ctrl", "exp",
              "fit e", "peak MiB", "dominant stage");
  const Row* previous = nullptr;
  for (const Row& row : rows) {
    if (!row.report) {
      std::printf("%9zu %-17s %9s after %.0f s (see above)%41s %8.0f\n", row.vertices,
                  row.source.c_str(), row.run.timedOut ? "TIMEOUT" : "FAILED", row.run.seconds, "",
                  row.run.peakMiB);
      continue;
    }
    const nlohmann::json& r = *row.report;
    const double total = r.at("seconds").get<double>(), fit = stage(r, "fit");
    const double n = double(row.vertices);
    std::string growth = "    -     -";
    if (previous) {
      const double ratio = std::log(n / double(previous->vertices));
      char text[32];
      std::snprintf(text, sizeof text, "%5.2f %5.2f",
                    std::log(total / previous->report->at("seconds").get<double>()) / ratio,
                    std::log(fit / stage(*previous->report, "fit")) / ratio);
      growth = text;
    }
    std::printf("%9zu %-17s %9.2f %9.2f %8.2f %8.1f %8.1f %9.2e %9.2e %6d %s %8.0f  %s%s\n",
                row.vertices, row.source.c_str(), total, fit, stage(r, "atlas"), 1e6 * total / n,
                1e6 * fit / n, r.at("rms_error").get<double>(), r.at("max_error").get<double>(),
                r.at("control_points").get<int>(), growth.c_str(), row.run.peakMiB,
                dominantStage(r).c_str(),
                r.at("reached_tolerance").get<bool>() ? "" : " (tolerance not reached)");
    previous = &row;
  }
  return 0;
}
