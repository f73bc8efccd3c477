// Benchmark: limit-surface evaluators, each timed on random surface points of its own net or
// spline: (a) a closed regular 256 x 256 torus quad net, (b) a real triangle mesh split into quads
// (each triangle -> 3 quads; extraordinary vertices everywhere), (c) a cubic manifold triangular
// B-spline (DMS spline, spline/tribspline/tri_bspline.h) with N control points on the mesh, against
// OpenSubdiv on a regular torus net and on an irregular net, both with about N control points.
// For every evaluator: setup time, peak and retained memory of the setup, and points per second of
// position + first derivatives at the sample points (serial). The first evaluator of a case
// (OpenSubdiv) is the reference the others' ratios are taken to. Each evaluator runs in a child
// process so that its memory figures are its own.
//
// Case (c): the spline model is made by `mspline spline MESH --quantize --control N` (in a
// temporary directory) and read back; the evaluator's setup builds the basis from it
// (TriBSplineSpace) and its evaluation is evaluateBatch at 1e6 domain points uniform by area. The
// irregular net is the triangle -> 3 quads split of a second domain triangulation of the same
// mesh, made the same way with about N / 6 vertices (V vertices of genus g give 6 V + 10 g - 10
// control points), on the mesh's positions of its vertices: a net of the same surface, with
// extraordinary vertices in every face (valence 3 at the centroids).
//
// Usage: spline_bench [MESH] [--control N] [--level L]
//   MESH: a file name in data/meshes or a path (default bunny00.off); N: control points of case
//   (c) (default 6000); L: OpenSubdiv's isolation level (default: the evaluator's).
#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mspline/io/load_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/subd/catmull_clark_limit.h"
#include "mspline/spline/subd/triangle_quad_split.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"

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

// Bytes allocated by malloc and not freed. Unlike the resident set it counts what a setup keeps
// even where malloc reuses memory the parent process had freed.
double heapBytes() {
  const struct mallinfo2 info = mallinfo2();
  return double(info.uordblks) + double(info.hblkhd);
}

struct QuadNet {
  Eigen::MatrixXd points;
  std::vector<std::vector<int>> faces;
};

// n x n quads on a torus (radii 1 and 0.4): every vertex has valence 4.
QuadNet torusNet(int n) {
  QuadNet net;
  net.points.resize(n * n, 3);
  const double pi = kPi;
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

QuadNet splitNet(const structure::TriMesh& mesh) {
  spline::TriangleQuadSplit split = spline::splitTrianglesIntoQuads(mesh);
  return {std::move(split.points), std::move(split.quads)};
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

// Random points of a spline domain, uniform by area in its flat metric.
std::vector<spline::SurfacePoint> randomDomainPoints(const spline::SplineDomain& domain,
                                                     unsigned seed) {
  std::vector<double> cumulative;
  double total = 0.0;
  for (const auto& l : domain.sideLengths) {
    total += structure::fourTimesArea(l[0], l[1], l[2]);
    cumulative.push_back(total);
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<spline::SurfacePoint> points;
  points.reserve(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    const auto at = std::upper_bound(cumulative.begin(), cumulative.end(), unit(rng) * total);
    const int face = std::min(int(at - cumulative.begin()), domain.faceCount() - 1);
    double s = unit(rng), t = unit(rng);
    if (s + t > 1.0) s = 1.0 - s, t = 1.0 - t;  // the reflected square's half: uniform
    points.push_back({face, Eigen::Vector3d(1.0 - s - t, s, t)});
  }
  return points;
}

std::string quoted(const std::string& text) {
  std::string result = "'";
  for (char c : text) result += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return result + "'";
}

// `mspline spline` on the mesh (cubic, quantized cones, about `control` control points), written
// to `path` and read back; `seconds` receives the command's wall time.
spline::SplineModel makeModel(const std::string& mesh, int control, const std::string& path,
                              double& seconds) {
  const std::string command = quoted(MSPLINE_CLI_PATH) + " spline " + quoted(mesh) +
                              " --quantize --quiet --control " + std::to_string(control) + " -o " +
                              quoted(path) + " > /dev/null";
  const auto start = Clock::now();
  if (std::system(command.c_str()) != 0) throw std::runtime_error(command + " failed");
  seconds = since(start);
  return io::readSplineModel(path);
}

int genus(const spline::SplineDomain& domain) {
  // A closed triangulation: E = 3 F / 2, and V - E + F = 2 - 2 g.
  return (2 - (domain.vertexCount() - domain.faceCount() / 2)) / 2;
}

// The triangle -> 3 quads split (as spline::splitTrianglesIntoQuads) of a model's domain
// triangulation, its vertices at their surface positions. From the faces' side adjacency rather
// than a TriMesh: a coarse triangulation may join two vertices by two sides.
QuadNet splitDomain(const spline::SplineModel& model) {
  const spline::SplineDomain& domain = model.domain;
  const int vertices = domain.vertexCount(), faces = domain.faceCount();
  std::vector<std::array<int, 3>> edge(std::size_t(faces), {-1, -1, -1});
  int edges = 0;
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k)
      if (edge[std::size_t(f)][std::size_t(k)] < 0) {
        edge[std::size_t(f)][std::size_t(k)] = edges;
        edge[std::size_t(domain.neighbour[std::size_t(f)][std::size_t(k)])]
            [std::size_t(domain.neighbourSide[std::size_t(f)][std::size_t(k)])] = edges++;
      }
  QuadNet net;
  net.points.resize(vertices + edges + faces, 3);
  for (int v = 0; v < vertices; ++v)
    net.points.row(v) = model.surfaceVertices.row(model.domainVertexSource[std::size_t(v)]);
  for (int f = 0; f < faces; ++f) {
    const auto& corner = domain.faces[std::size_t(f)];
    net.points.row(vertices + edges + f).setZero();
    for (int k = 0; k < 3; ++k) {
      const int a = corner[std::size_t(k)], b = corner[std::size_t((k + 1) % 3)];
      net.points.row(vertices + edge[std::size_t(f)][std::size_t(k)]) =
          (net.points.row(a) + net.points.row(b)) / 2.0;
      net.points.row(vertices + edges + f) += net.points.row(a) / 3.0;
    }
    for (int k = 0; k < 3; ++k)
      net.faces.push_back({corner[std::size_t(k)], vertices + edge[std::size_t(f)][std::size_t(k)],
                           vertices + edges + f,
                           vertices + edge[std::size_t(f)][std::size_t((k + 2) % 3)]});
  }
  return net;
}

// One evaluator of a case's surface. `build` constructs its tables (timed, memory measured) and
// returns a short description of them; `evaluate` then evaluates position and first derivatives
// at all sample points, serially, and returns how many lie on the surface.
struct Evaluator {
  std::string name;
  /// Control points of its surface, for the memory per control point.
  int controlPoints = 0;
  std::function<std::string()> build;
  std::function<std::size_t()> evaluate;
};

// Evaluators timed at the same number of random points. In cases (a) and (b) they are the same
// points: for a net split from a triangle mesh, quad 3 f + k covers corner k of triangle f, so
// sample (3 f + k, u, v) is the point of triangle f with barycentric coordinates
// spline::quadPointBarycentric(k, u, v), where an evaluator on the triangles evaluates.
struct Case {
  std::string name;
  std::size_t points = 0;
  std::vector<Evaluator> evaluators;
};

// OpenSubdiv's Far limit evaluation (double precision) of a quad net.
Evaluator openSubdivEvaluator(const std::string& name, const QuadNet& net,
                              const std::vector<spline::FaceParameter>& samples, int level) {
  auto limit = std::make_shared<std::unique_ptr<spline::CatmullClarkLimit>>();
  auto out = std::make_shared<spline::LimitPoints>();
  Evaluator e;
  e.name = name;
  e.controlPoints = int(net.points.rows());
  e.build = [&net, limit, level] {
    spline::CatmullClarkOptions options;
    if (level > 0) options.isolationLevel = level;
    *limit = std::make_unique<spline::CatmullClarkLimit>(net.points, net.faces, options);
    const spline::FaceCounts counts = (*limit)->faceCounts();
    return std::to_string(net.points.rows()) + " control points, level " +
           std::to_string(options.isolationLevel) + ", " + std::to_string(counts.regular) +
           " regular / " + std::to_string(counts.irregular) + " irregular faces, " +
           std::to_string((*limit)->numPatchPoints()) + " patch points";
  };
  e.evaluate = [&samples, limit, out] { return (*limit)->evaluate(samples, *out); };
  return e;
}

// The manifold triangular B-spline of a model: the basis built from its domain and knots, then
// evaluateBatch at the points.
Evaluator dmsEvaluator(const spline::SplineModel& model,
                       const std::vector<spline::SurfacePoint>& points) {
  auto space = std::make_shared<std::unique_ptr<spline::TriBSplineSpace>>();
  auto out = std::make_shared<spline::SplineSamples>();
  Evaluator e;
  e.name = "DMS degree " + std::to_string(model.degree) + " (evaluateBatch)";
  e.controlPoints = int(model.controlPoints.rows());
  e.build = [&model, space] {
    *space = std::make_unique<spline::TriBSplineSpace>(model.domain, model.knots);
    int cones = 0;
    for (char c : model.domain.cone) cones += c;
    return std::to_string((*space)->numBasis()) + " control points, " +
           std::to_string(model.domain.faceCount()) + " domain faces, " + std::to_string(cones) +
           " cones";
  };
  e.evaluate = [&model, &points, space, out] {
    (*space)->evaluateBatch(model.controlPoints, points, 1, *out);
    return points.size();
  };
  return e;
}

struct Measurement {
  double setupSeconds = 0, peakDeltaMiB = 0, retainedMiB = 0, heapBytes = 0, evaluateSeconds = 0;
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
    const double peakBefore = peakMiB(), residentBefore = residentMiB(), heapBefore = heapBytes();
    auto start = Clock::now();
    const std::string description = evaluator.build();
    r.setupSeconds = since(start);
    r.peakDeltaMiB = peakMiB() - peakBefore;
    r.retainedMiB = residentMiB() - residentBefore;
    r.heapBytes = heapBytes() - heapBefore;
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

bool runCase(const Case& c, std::vector<Measurement>& results) {
  std::printf("\n%s: %zu random points per evaluator\n", c.name.c_str(), c.points);
  std::printf("  %-30s %8s %9s %9s %9s %7s %10s %8s %8s  %s\n", "evaluator", "setup s", "peak MiB",
              "kept MiB", "heap MiB", "B/ctrl", "Mpoints/s", "speed", "setup", "tables");
  results.clear();
  for (const Evaluator& evaluator : c.evaluators) {
    Measurement m;
    if (!measure(evaluator, m)) {
      std::fprintf(stderr, "spline_bench: %s on %s failed\n", evaluator.name.c_str(),
                   c.name.c_str());
      return false;
    }
    results.push_back(m);
    const Measurement& reference = results.front();
    const double rate = double(c.points) / m.evaluateSeconds;
    const double referenceRate = double(c.points) / reference.evaluateSeconds;
    std::printf(
        "  %-30s %8.3f %9.1f %9.1f %9.1f %7.0f %10.3f %7.2fx %7.2fx  %s; %zu on the surface\n",
        evaluator.name.c_str(), m.setupSeconds, m.peakDeltaMiB, m.retainedMiB,
        m.heapBytes / (1024.0 * 1024.0), m.heapBytes / evaluator.controlPoints, rate / 1e6,
        rate / referenceRate, m.setupSeconds / reference.setupSeconds, m.description, m.onSurface);
  }
  return true;
}

struct Arguments {
  std::string mesh = "bunny00.off";
  int control = 6000;
  int level = 0;
};

bool parseArguments(int argc, char** argv, Arguments& a) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--control" || arg == "--level") && i + 1 < argc) {
      (arg == "--control" ? a.control : a.level) = std::atoi(argv[++i]);
    } else if (!arg.empty() && arg[0] != '-') {
      a.mesh = arg;
    } else {
      return false;
    }
  }
  return a.control >= 20 && a.level >= 0;
}

// The three cases; false when a measurement failed (a message is printed).
bool run(const Arguments& arguments) {
  // A bare file name is one of the real meshes.
  const std::string source = arguments.mesh.find('/') == std::string::npos
                                 ? MSPLINE_SOURCE_DIR "/data/meshes/" + arguments.mesh
                                 : arguments.mesh;
  const std::string meshName = source.substr(source.find_last_of('/') + 1);
  const int level = arguments.level;
  std::printf(
      "spline_bench: position + first derivatives, serial; speed and setup are ratios to the "
      "first evaluator of each case; peak = growth of the peak RSS during setup, kept = RSS "
      "growth that stays, heap = bytes the setup left allocated (B/ctrl: per control point)\n");

  std::vector<Measurement> results;
  const QuadNet torus = torusNet(256);
  const auto torusSamples = randomSamples(256 * 256, 1);
  Case torusCase{"(a) torus 256 x 256 (regular quad net)", kSamples, {}};
  torusCase.evaluators.push_back(
      openSubdivEvaluator("OpenSubdiv Far (double)", torus, torusSamples, level));
  if (!runCase(torusCase, results)) return false;

  const auto loaded = io::loadMesh(source);
  const structure::TriMesh& mesh = *loaded.mesh;
  const QuadNet quads = splitNet(mesh);
  const auto splitSamples = randomSamples(int(quads.faces.size()), 2);
  Case splitCase{"(b) " + meshName + " split into quads (" + std::to_string(mesh.n_faces()) +
                     " triangles -> " + std::to_string(quads.faces.size()) + " quads)",
                 kSamples,
                 {}};
  splitCase.evaluators.push_back(
      openSubdivEvaluator("OpenSubdiv Far (double)", quads, splitSamples, level));
  if (!runCase(splitCase, results)) return false;

  char pattern[] = "/tmp/spline_bench.XXXXXX";
  if (!mkdtemp(pattern)) {
    std::perror("spline_bench: mkdtemp");
    return false;
  }
  // Removed however run ends (the measuring children leave by _exit, which skips this).
  const struct TemporaryDirectory {
    std::string path;
    ~TemporaryDirectory() { std::filesystem::remove_all(path); }
  } temporary{pattern};
  const std::string& directory = temporary.path;
  double modelSeconds = 0.0, netSeconds = 0.0;
  const spline::SplineModel model =
      makeModel(source, arguments.control, directory + "/spline.msp", modelSeconds);
  // The irregular net: a domain triangulation with V vertices, 6 V + 10 g - 10 control points
  // after the split; `mspline spline` asks for n_F = (n + 1)(n + 2) / 2 control points per face
  // (cubic: 10) and makes (control / n_F + 4 - 4 g) / 2 vertices.
  const int g = genus(model.domain);
  const int vertices = std::max(4, (arguments.control + 10 - 10 * g + 3) / 6);
  const spline::SplineModel netModel =
      makeModel(source, 10 * (2 * vertices - 4 + 4 * g), directory + "/net.msp", netSeconds);
  const QuadNet irregular = splitDomain(netModel);
  const QuadNet regular = torusNet(std::max(3, int(std::lround(std::sqrt(arguments.control)))));
  std::printf(
      "\n(c) models made by mspline spline %s --quantize: the spline's in %.2f s (flatten, "
      "coarsen, knots, fit), the irregular net's domain (%d vertices) in %.2f s\n",
      meshName.c_str(), modelSeconds, netModel.domain.vertexCount(), netSeconds);

  const auto regularSamples = randomSamples(int(regular.faces.size()), 3);
  const auto irregularSamples = randomSamples(int(irregular.faces.size()), 4);
  const auto domainPoints = randomDomainPoints(model.domain, 5);
  Case dmsCase{"(c) " + meshName + ", about " + std::to_string(arguments.control) +
                   " control points: OpenSubdiv on a regular torus net and on the split of a "
                   "domain triangulation, the DMS spline (points uniform by area)",
               kSamples,
               {}};
  dmsCase.evaluators.push_back(
      openSubdivEvaluator("OpenSubdiv, regular torus", regular, regularSamples, level));
  dmsCase.evaluators.push_back(
      openSubdivEvaluator("OpenSubdiv, irregular net", irregular, irregularSamples, level));
  dmsCase.evaluators.push_back(dmsEvaluator(model, domainPoints));
  if (!runCase(dmsCase, results)) return false;
  const double dms = results[2].evaluateSeconds;
  std::printf(
      "  DMS / OpenSubdiv speed: %.2fx the regular net (target >= 0.25x), %.2fx the irregular "
      "net; memory per control point %.0f B against %.0f B and %.0f B\n",
      results[0].evaluateSeconds / dms, results[1].evaluateSeconds / dms,
      results[2].heapBytes / dmsCase.evaluators[2].controlPoints,
      results[0].heapBytes / dmsCase.evaluators[0].controlPoints,
      results[1].heapBytes / dmsCase.evaluators[1].controlPoints);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments arguments;
  if (!parseArguments(argc, argv, arguments)) {
    std::fprintf(stderr, "usage: spline_bench [MESH] [--control N (>= 20)] [--level L]\n");
    return 1;
  }
  try {
    return run(arguments) ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "spline_bench: %s\n", error.what());
    return 1;
  }
}
