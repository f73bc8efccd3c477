// Benchmark: the whole flatten pipeline (cone placement, Newton on the Ricci energy, layout) on a
// real scan subdivided to larger sizes, against one sparse Cholesky factorization (analysis +
// numeric) of the same mesh's cotangent Laplacian, measured in the same run.
// Targets (issue 3): total flatten time at most 10x that factorization; 1M faces in under 20 s and
// under 2 GB. Each size runs in a child process so the peak memory is that size's alone.
// Usage: flatten_bench [MESH [FACES...]]   (default: bunny00.off at its own size and ~1M faces)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mspline/io/load_mesh.h"
#include "mspline/structure/atlas/affine_atlas.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/index_map.h"
#include "mspline/structure/core/sparse_cholesky.h"
#include "mspline/structure/intrinsic/intrinsic_overlay.h"
#include "mspline/structure/intrinsic/ricci_flips.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/mesh/cotan_laplacian.h"
#include "mspline/structure/mesh/subdivide.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/ricci_newton.h"

using namespace mspline;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void runSize(const structure::TriMesh& base, std::size_t faces) {
  structure::TriMesh mesh = structure::subdivideToAtLeast(base, faces);

  auto start = Clock::now();
  std::vector<char> pinned(mesh.n_vertices(), 0);
  pinned[0] = 1;  // the Laplacian of a closed surface is singular only along constants
  structure::IndexMap map(mesh.n_vertices(), pinned);
  Eigen::SparseMatrix<double> laplacian = map.restrict(structure::cotanLaplacian(mesh));
  structure::SparseCholesky cholesky;
  auto factorStart = Clock::now();
  cholesky.analyze(laplacian);
  cholesky.factorize(laplacian);
  double factorization = since(factorStart);
  double assembly = std::chrono::duration<double>(factorStart - start).count();

  start = Clock::now();
  structure::ConePlacementOptions coneOptions;
  coneOptions.quantize = true;
  auto cones = structure::placeCones(mesh, coneOptions);
  double coneSeconds = since(start);
  auto target = structure::flatTarget(mesh, cones.cones);
  auto newtonStart = Clock::now();
  auto flow = structure::solveVertexScaling(mesh, target);
  double newtonSeconds = since(newtonStart);
  double layoutSeconds = 0;
  int flipped = -1;
  structure::FlatLayout layout;
  if (flow.converged) {
    auto layoutStart = Clock::now();
    layout = structure::layoutFlatMetric(mesh, flow.edgeLengths);
    layoutSeconds = since(layoutStart);
    flipped = layout.flippedTriangles;
  }
  double total = since(start);

  // The affine atlas on top of that flattening (issue 4: at most 2x the flatten time).
  double atlasSeconds = 0;
  std::string atlasSummary = "not built";
  if (flow.converged) {
    auto atlasStart = Clock::now();
    const auto atlas = structure::buildAffineAtlas(mesh, flow.edgeLengths, layout);
    atlasSeconds = since(atlasStart);
    char summary[160];
    double quarterTurnError = 0.0;
    for (const auto& t : atlas.transitions) {
      const double quarters = t.motion.angle / (kPi / 2);
      quarterTurnError = std::max(quarterTurnError, std::abs(quarters - std::round(quarters)));
    }
    std::snprintf(summary, sizeof summary,
                  "%zu charts, %s (quarter turns to %.1e rad, flatness defect %.1e), residuals "
                  "%.1e / %.1e",
                  atlas.charts.size(), structure::transitionKindName(atlas.kind),
                  quarterTurnError * kPi / 2, atlas.flatnessDefect, atlas.maxTransitionResidual,
                  atlas.maxCocycleResidual);
    atlasSummary = summary;
  }

  // The same metric by Newton with intrinsic Delaunay flips (what flatten falls back to when the
  // input triangulation degenerates), plus the common subdivision it is laid out on.
  auto flipsStart = Clock::now();
  auto withFlips = structure::solveVertexScalingWithFlips(mesh, target);
  double flipsNewton = since(flipsStart);
  auto overlayStart = Clock::now();
  std::size_t overlayFaces = 0;
  if (withFlips.ricci.converged)
    overlayFaces =
        structure::intrinsicOverlay(mesh, withFlips.triangulation.flippedEdges(), withFlips.ricci.u,
                                    withFlips.triangulation.lengths(withFlips.ricci.u))
            .mesh.n_faces();
  double overlaySeconds = since(overlayStart);

  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf(
      "flatten_bench: %zu faces, %zu vertices\n"
      "  one factorization (analyze + factorize): %.3f s (Laplacian assembly %.3f s)\n"
      "  flatten: cones %.3f s (%zu cones), Newton %.3f s (%d steps, %s, error %.2e), "
      "layout %.3f s (%d flipped)\n"
      "  total %.3f s = %.1fx one factorization (target <= 10x); peak %.0f MiB\n"
      "  Newton with flips: %.3f s (%d steps, %s, %ld flips), overlay %.3f s (%zu faces); "
      "cones + that + overlay + layout = %.1fx one factorization\n"
      "  atlas: %.3f s (%s) = %.2fx the flatten time (target <= 2x)\n",
      mesh.n_faces(), mesh.n_vertices(), factorization, assembly, coneSeconds, cones.cones.size(),
      newtonSeconds, flow.iterations, flow.converged ? "converged" : "NOT converged",
      flow.maxCurvatureError, layoutSeconds, flipped, total, total / factorization,
      usage.ru_maxrss / 1024.0, flipsNewton, withFlips.ricci.iterations,
      withFlips.ricci.converged ? "converged" : "NOT converged", withFlips.flips, overlaySeconds,
      overlayFaces, (coneSeconds + flipsNewton + overlaySeconds + layoutSeconds) / factorization,
      atlasSeconds, atlasSummary.c_str(), atlasSeconds / total);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string source = argc > 1 ? argv[1] : MSPLINE_SOURCE_DIR "/data/meshes/bunny00.off";
  std::vector<std::size_t> sizes;
  for (int i = 2; i < argc; ++i) sizes.push_back(std::stoul(argv[i]));
  if (sizes.empty()) sizes = {0, 1000000};
  auto base = io::loadMesh(source);
  std::printf("flatten_bench: %s (%zu faces)\n", source.c_str(), base.mesh->n_faces());
  std::fflush(stdout);
  for (std::size_t faces : sizes) {
    pid_t pid = fork();
    if (pid == 0) {
      runSize(*base.mesh, faces);
      _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::fprintf(stderr, "flatten_bench: the run at %zu faces failed\n", faces);
      return 1;
    }
  }
  return 0;
}
