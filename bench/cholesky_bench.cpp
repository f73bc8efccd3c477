// Benchmark: sparse Cholesky of the cotangent Laplacian (one vertex pinned) of a real scan
// subdivided to about 100k and about 1M faces, for each backend: analyze, factorize, solve.
// The Ricci-flow bench compares its total time to one such factorization.
//
// Usage: cholesky_bench [MESH [FACES...]]  (default: bunny00.off, 100000 1000000)
// CHOLMOD's supernodal factorization runs on whatever libblas.so.3 resolves to; the bench prints
// it. To measure Debian's reference BLAS instead of OpenBLAS, run with
// LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/blas.
#include <dlfcn.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "mspline/io/load_mesh.h"
#include "mspline/structure/core/index_map.h"
#include "mspline/structure/core/sparse_cholesky.h"
#include "mspline/structure/mesh/cotan_laplacian.h"
#include "mspline/structure/mesh/subdivide.h"

using namespace mspline;
using structure::CholeskyBackend;
using structure::choleskyBackendName;

namespace {

// The BLAS and LAPACK libraries mapped into this process, and OpenBLAS's thread count if loaded.
std::string loadedBlas() {
  std::ifstream maps("/proc/self/maps");
  std::set<std::string> libraries;
  for (std::string line; std::getline(maps, line);) {
    auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    std::string path = line.substr(slash);
    if (path.find("blas") != std::string::npos || path.find("lapack") != std::string::npos)
      libraries.insert(path);
  }
  std::string result;
  for (const auto& path : libraries) result += (result.empty() ? "" : ", ") + path;
  if (result.empty()) result = "none";
  using ThreadsFn = int (*)();
  if (auto threads = reinterpret_cast<ThreadsFn>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads")))
    result += "; OpenBLAS threads: " + std::to_string(threads());
  return result;
}

double peakMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // KiB on Linux
}

void benchSize(const structure::TriMesh& base, std::size_t targetFaces) {
  // Subdivision levels differ by 4x: take the level nearest the target (at least half of it).
  structure::TriMesh mesh = structure::subdivideToAtLeast(base, targetFaces / 2);
  auto start = std::chrono::steady_clock::now();
  Eigen::SparseMatrix<double> laplacian = structure::cotanLaplacian(mesh);
  double laplacianSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The Laplacian is singular (constants); pinning one vertex makes it definite.
  std::vector<char> pinned(mesh.n_vertices(), 0);
  pinned[0] = 1;
  structure::IndexMap map(mesh.n_vertices(), pinned);
  Eigen::SparseMatrix<double> a = map.restrict(laplacian);

  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b(a.rows());
  for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = normal(rng);

  std::printf(
      "\ncholesky_bench: target %zu faces -> %zu vertices, %zu faces; %d unknowns, "
      "nnz(A) %ld; cotanLaplacian %.3f s\n",
      targetFaces, mesh.n_vertices(), mesh.n_faces(), map.size(), long(a.nonZeros()),
      laplacianSeconds);
  for (CholeskyBackend backend :
       {CholeskyBackend::CholmodSupernodal, CholeskyBackend::CholmodSimplicial,
        CholeskyBackend::EigenSimplicial}) {
    structure::SparseCholesky solver(structure::CholeskyOptions{backend});
    solver.analyze(a);
    double bestFactorize = 1e30, solveSeconds = 1e30;
    Eigen::VectorXd x;
    for (int repeat = 0; repeat < 3; ++repeat) {
      solver.factorize(a);
      bestFactorize = std::min(bestFactorize, solver.lastFactorizeSeconds());
      auto solveStart = std::chrono::steady_clock::now();
      x = solver.solve(b);
      solveSeconds = std::min(
          solveSeconds,
          std::chrono::duration<double>(std::chrono::steady_clock::now() - solveStart).count());
    }
    double residual = (a * x - b).norm() / b.norm();
    std::printf(
        "  %-21s analyze %7.3f s  factorize %7.3f s (best of 3)  solve %6.3f s  "
        "nnz(L) %6.2f M  residual %.1e  peak RSS so far %.0f MiB\n",
        choleskyBackendName(backend), solver.lastAnalyzeSeconds(), bestFactorize, solveSeconds,
        solver.factorNonZeros() / 1e6, residual, peakMiB());
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string source = argc > 1 ? argv[1] : MSPLINE_SOURCE_DIR "/data/meshes/bunny00.off";
  std::vector<std::size_t> targets;
  for (int i = 2; i < argc; ++i) targets.push_back(std::stoul(argv[i]));
  if (targets.empty()) targets = {100000, 1000000};

  auto loaded = io::loadMesh(source);
  std::printf("cholesky_bench: %s (%zu faces)\n", source.c_str(), loaded.mesh->n_faces());
  // CHOLMOD is linked, so its BLAS is mapped from the start.
  std::printf("cholesky_bench: BLAS loaded: %s\n", loadedBlas().c_str());
  for (std::size_t target : targets) benchSize(*loaded.mesh, target);
  return 0;
}
