// Benchmark: `mspline info` on a mesh of about 1M faces made by subdividing a real scan.
// Target (issue 2): under 2 s and under 1 GB. Runs the real command as a child process so the
// figures are what a user sees: wall time and the child's peak resident memory.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "mspline/io/load_mesh.h"
#include "mspline/io/write_mesh.h"
#include "mspline/structure/mesh/subdivide.h"

namespace fs = std::filesystem;
using namespace mspline;

namespace {

struct ChildRun {
  int exitCode = -1;
  double seconds = 0;
  double peakMiB = 0;
};

ChildRun runChild(const std::vector<std::string>& argv) {
  // The child must not inherit (and print again) what is still buffered.
  std::fflush(stdout);
  auto start = std::chrono::steady_clock::now();
  pid_t pid = fork();
  if (pid == 0) {
    if (!freopen("/dev/null", "w", stdout)) _exit(127);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  ChildRun run;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.peakMiB = usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  std::string source = argc > 1 ? argv[1] : MSPLINE_SOURCE_DIR "/data/meshes/bunny00.off";
  std::size_t targetFaces = argc > 2 ? std::stoul(argv[2]) : 1000000;
  std::string mspline = MSPLINE_CLI_PATH;

  auto base = io::loadMesh(source);
  structure::TriMesh big = structure::subdivideToAtLeast(*base.mesh, targetFaces);
  fs::path dir = fs::temp_directory_path() / "mspline-bench";
  fs::create_directories(dir);
  std::printf("info_bench: %s subdivided to %zu vertices, %zu faces\n", source.c_str(),
              big.n_vertices(), big.n_faces());

  const double timeTarget = 2.0, memoryTargetMiB = 1024.0;
  for (const char* format : {"off", "ply"}) {
    fs::path file = dir / (std::string("big.") + format);
    io::writeMesh(file.string(), big);
    double best = 1e30, peak = 0;
    for (int repeat = 0; repeat < 3; ++repeat) {
      ChildRun run = runChild({mspline, "info", "--json", file.string()});
      if (run.exitCode != 0) {
        std::fprintf(stderr, "info_bench: mspline info failed on %s (exit %d)\n", file.c_str(),
                     run.exitCode);
        return 1;
      }
      best = std::min(best, run.seconds);
      peak = std::max(peak, run.peakMiB);
    }
    std::printf(
        "info_bench: %-3s %8.1f MB file: best of 3 %.3f s (target %.1f s, ratio %.2f), "
        "peak %.0f MiB (target %.0f MiB, ratio %.2f)\n",
        format, fs::file_size(file) / 1e6, best, timeTarget, best / timeTarget, peak,
        memoryTargetMiB, peak / memoryTargetMiB);
    fs::remove(file);
  }
  return 0;
}
