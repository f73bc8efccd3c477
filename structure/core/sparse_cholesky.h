#pragma once
// Sparse Cholesky factorization for symmetric positive definite systems solved many times with
// the same sparsity pattern (Newton's method): the ordering and symbolic factorization are computed
// once by analyze(), each new set of values costs only the numeric factorize().
#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace mspline::structure {

enum class CholeskyBackend {
  /// CHOLMOD supernodal LL^T: dense BLAS kernels on blocks of columns; fastest on meshes.
  CholmodSupernodal,
  /// CHOLMOD simplicial LDL^T: column by column, no BLAS.
  CholmodSimplicial,
  /// Eigen::SimplicialLDLT with its AMD ordering: no external library.
  EigenSimplicial,
};

/// "CHOLMOD supernodal", "CHOLMOD simplicial" or "Eigen SimplicialLDLT", for reports.
const char* choleskyBackendName(CholeskyBackend backend);

struct CholeskyOptions {
  /// Default: CHOLMOD supernodal, the fastest on mesh Laplacians of 10^5 unknowns and more.
  CholeskyBackend backend = CholeskyBackend::CholmodSupernodal;
};

/// Factors symmetric positive definite matrices (column-major, int indices). Only the lower
/// triangle (diagonal included) is read, so either the full symmetric matrix or its lower triangle
/// may be passed. A semidefinite matrix (e.g. a Laplacian with its constant null space) must be
/// made definite first, by pinning an unknown (see IndexMap) or a diagonal shift.
///
/// Usage: analyze(A) once, then factorize(A') and solve(b) as often as needed while A' has A's
/// pattern. Not copyable (it owns the solver's workspace); movable.
class SparseCholesky {
 public:
  explicit SparseCholesky(const CholeskyOptions& options = {});
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Fill-reducing ordering and symbolic factorization of `pattern` (its values are not used).
  /// Throws InputError when the matrix is not square.
  void analyze(const Eigen::SparseMatrix<double>& pattern);

  /// Numeric factorization of `matrix`, which must have the pattern given to analyze() (checked:
  /// InternalError otherwise). Throws SolverError naming the column when the matrix is not
  /// positive definite; the object then needs another successful factorize() before solve().
  void factorize(const Eigen::SparseMatrix<double>& matrix);

  /// Convenience: analyze(matrix) followed by factorize(matrix).
  void compute(const Eigen::SparseMatrix<double>& matrix);

  /// Solves A x = rhs with the last factorized A. Throws InternalError without a valid factor.
  /// Reuses workspace kept in the object, so concurrent solves need one object per thread.
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const;

  /// Number of rows (and columns) of the analyzed matrix; 0 before analyze().
  int size() const;
  /// Wall-clock seconds of the last analyze() and factorize() calls (for benchmarks).
  double lastAnalyzeSeconds() const;
  double lastFactorizeSeconds() const;
  /// Entries of the factor L (diagonal included), after factorize(); a measure of fill-in.
  long factorNonZeros() const;

  const CholeskyOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mspline::structure
