// Benchmark: limit-surface evaluators on two control nets, each timed on the same random surface
// points: (a) a closed regular 256 x 256 torus quad net, (b) a real triangle mesh split into
// quads (each triangle -> 3 quads; extraordinary vertices everywhere). For every evaluator: setup
// time, peak and retained memory of the setup, and points per second of position + first
// derivatives at the sample points (serial). The first evaluator of a case (OpenSubdiv) is the
// reference the others' ratios are taken to. Each evaluator runs in a child process so that its
// memory figures are its own.
// Usage: spline_bench [MESH [ISOLATION_LEVEL]]  (default: bunny00.off, the evaluator's default
// level)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "io/load_mesh.h"
#include "spline/catmull_clark_limit.h"
#include "spline/triangle_quad_split.h"

using namespace mspline;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kSamples = 1000000;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double peakMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // KiB on Linux
}

double residentMiB() {
  std::ifstream statm("/proc/self/statm");
  long size = 0, resident = 0;
  statm >> size >> resident;
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

struct QuadNet {
  Eigen::MatrixXd points;
  std::vector<std::vector<int>> faces;
};

// n x n quads on a torus (radii 1 and 0.4): every vertex has valence 4.
QuadNet torusNet(int n) {
  QuadNet net;
  net.points.resize(n * n, 3);
  const double pi = 3.14159265358979323846;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * pi * i / n, b = 2 * pi * j / n, r = 1.0 + 0.4 * std::cos(b);
      net.points.row(j * n + i) << r * std::cos(a), r * std::sin(a), 0.4 * std::sin(b);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      net.faces.push_back(
          {j * n + i, j * n + (i + 1) % n, ((j + 1) % n) * n + (i + 1) % n, ((j + 1) % n) * n + i});
  return net;
}

// Uniformly random (face, u, v) on a quad net of `faces` faces.
std::vector<spline::FaceParameter> randomSamples(int faces, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> face(0, faces - 1);
  std::uniform_real_distribution<double> uv(0.0, 1.0);
  std::vector<spline::FaceParameter> samples;
  samples.reserve(kSamples);
  for (int i = 0; i < kSamples; ++i) samples.push_back({face(rng), uv(rng), uv(rng)});
  return samples;
}

// One evaluator of a case's surface. `build` constructs its tables (timed, memory measured) and
// returns a short description of them; `evaluate` then evaluates position and first derivatives
// at all sample points, serially, and returns how many lie on the surface.
struct Evaluator {
  std::string name;
  std::function<std::string()> build;
  std::function<std::size_t()> evaluate;
};

// A surface and the evaluators timed on it, all at the same points. For a net split from a
// triangle mesh, quad 3 f + k covers corner k of triangle f, so sample (3 f + k, u, v) is the
// point of triangle f with barycentric coordinates spline::quadPointBarycentric(k, u, v): an
// evaluator on the triangles evaluates there.
struct Case {
  std::string name;
  std::vector<spline::FaceParameter> samples;
  std::vector<Evaluator> evaluators;
};

// OpenSubdiv's Far limit evaluation (double precision) of a quad net.
Evaluator openSubdivEvaluator(const QuadNet& net, const std::vector<spline::FaceParameter>& samples,
                              int level) {
  auto limit = std::make_shared<std::unique_ptr<spline::CatmullClarkLimit>>();
  auto out = std::make_shared<spline::LimitPoints>();
  Evaluator e;
  e.name = "OpenSubdiv Far (double)";
  e.build = [&net, limit, level] {
    spline::CatmullClarkOptions options;
    if (level > 0) options.isolationLevel = level;
    *limit = std::make_unique<spline::CatmullClarkLimit>(net.points, net.faces, options);
    const spline::FaceCounts counts = (*limit)->faceCounts();
    return "level " + std::to_string(options.isolationLevel) + ", " +
           std::to_string(counts.regular) + " regular / " + std::to_string(counts.irregular) +
           " irregular faces, " + std::to_string((*limit)->numPatchPoints()) + " patch points";
  };
  e.evaluate = [&samples, limit, out] { return (*limit)->evaluate(samples, *out); };
  return e;
}

struct Measurement {
  double setupSeconds = 0, peakDeltaMiB = 0, retainedMiB = 0, evaluateSeconds = 0;
  std::size_t onSurface = 0;
  char description[200] = {};
};

// Builds and runs the evaluator in a child process; the best of two evaluation runs counts.
bool measure(const Evaluator& evaluator, Measurement& m) {
  std::fflush(stdout);
  int channel[2];
  if (pipe(channel) != 0) return false;
  const pid_t pid = fork();
  if (pid == 0) {
    close(channel[0]);
    Measurement r;
    const double peakBefore = peakMiB(), residentBefore = residentMiB();
    auto start = Clock::now();
    const std::string description = evaluator.build();
    r.setupSeconds = since(start);
    r.peakDeltaMiB = peakMiB() - peakBefore;
    r.retainedMiB = residentMiB() - residentBefore;
    std::snprintf(r.description, sizeof r.description, "%s", description.c_str());
    r.evaluateSeconds = 1e30;
    for (int run = 0; run < 2; ++run) {
      start = Clock::now();
      r.onSurface = evaluator.evaluate();
      r.evaluateSeconds = std::min(r.evaluateSeconds, since(start));
    }
    const bool written = write(channel[1], &r, sizeof r) == ssize_t(sizeof r);
    _exit(written ? 0 : 1);
  }
  close(channel[1]);
  const bool received = read(channel[0], &m, sizeof m) == ssize_t(sizeof m);
  close(channel[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return received && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

bool runCase(const Case& c) {
  std::printf("\n%s: %zu random points\n", c.name.c_str(), c.samples.size());
  std::printf("  %-26s %9s %9s %9s %10s %9s %9s  %s\n", "evaluator", "setup s", "peak MiB",
              "kept MiB", "Mpoints/s", "speed", "setup", "tables");
  Measurement reference;
  for (std::size_t i = 0; i < c.evaluators.size(); ++i) {
    Measurement m;
    if (!measure(c.evaluators[i], m)) {
      std::fprintf(stderr, "spline_bench: %s on %s failed\n", c.evaluators[i].name.c_str(),
                   c.name.c_str());
      return false;
    }
    if (i == 0) reference = m;
    const double rate = double(c.samples.size()) / m.evaluateSeconds;
    const double referenceRate = double(c.samples.size()) / reference.evaluateSeconds;
    std::printf("  %-26s %9.3f %9.1f %9.1f %10.3f %8.2fx %8.2fx  %s; %zu on the surface\n",
                c.evaluators[i].name.c_str(), m.setupSeconds, m.peakDeltaMiB, m.retainedMiB,
                rate / 1e6, rate / referenceRate, m.setupSeconds / reference.setupSeconds,
                m.description, m.onSurface);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string source = argc > 1 ? argv[1] : MSPLINE_SOURCE_DIR "/data/meshes/bunny00.off";
  const int level = argc > 2 ? std::stoi(argv[2]) : 0;
  std::printf(
      "spline_bench: position + first derivatives, serial; speed and setup are ratios to the "
      "first evaluator of each case; peak = growth of the peak RSS during setup, kept = RSS "
      "growth that stays\n");

  const QuadNet torus = torusNet(256);
  Case torusCase{"torus 256 x 256 (regular quad net)", randomSamples(256 * 256, 1), {}};
  torusCase.evaluators.push_back(openSubdivEvaluator(torus, torusCase.samples, level));
  if (!runCase(torusCase)) return 1;

  const auto loaded = io::loadMesh(source);
  const structure::TriMesh& mesh = *loaded.mesh;
  spline::TriangleQuadSplit split = spline::splitTrianglesIntoQuads(mesh);
  const QuadNet quads{std::move(split.points), std::move(split.quads)};
  Case splitCase{source.substr(source.find_last_of('/') + 1) + " split into quads (" +
                     std::to_string(mesh.n_faces()) + " triangles -> " +
                     std::to_string(quads.faces.size()) + " quads)",
                 randomSamples(int(quads.faces.size()), 2),
                 {}};
  splitCase.evaluators.push_back(openSubdivEvaluator(quads, splitCase.samples, level));
  return runCase(splitCase) ? 0 : 1;
}
