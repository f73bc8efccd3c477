#include "mspline/structure/core/sparse_cholesky.h"

#include <cholmod.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

namespace {

using Clock = std::chrono::steady_clock;
using SparseMatrix = Eigen::SparseMatrix<double>;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A CHOLMOD view of the lower triangle of an Eigen matrix; no copy (CHOLMOD only reads it).
cholmod_sparse lowerView(const SparseMatrix& m) {
  cholmod_sparse s{};
  s.nrow = std::size_t(m.rows());
  s.ncol = std::size_t(m.cols());
  s.nzmax = std::size_t(m.nonZeros());
  s.p = const_cast<int*>(m.outerIndexPtr());
  s.i = const_cast<int*>(m.innerIndexPtr());
  s.x = const_cast<double*>(m.valuePtr());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

[[noreturn]] void throwNotPositiveDefinite(long column, long n) {
  throw SolverError(
      "sparse Cholesky: matrix is not positive definite (non-positive pivot at column " +
      std::to_string(column) + " of " + std::to_string(n) + ")");
}

}  // namespace

struct SparseCholesky::Impl {
  CholeskyOptions options;
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  // Workspace of cholmod_solve2, kept between solves so Newton steps do not reallocate it.
  cholmod_dense* solution = nullptr;
  cholmod_dense* workY = nullptr;
  cholmod_dense* workE = nullptr;
  std::optional<Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower>> eigen;

  int n = 0;
  bool analyzed = false;
  bool factorized = false;
  std::vector<int> outer, inner;  // the analyzed pattern, to check factorize() against it
  long lnz = 0;
  double analyzeSeconds = 0;
  double factorizeSeconds = 0;

  explicit Impl(const CholeskyOptions& o) : options(o) {
    cholmod_start(&common);
    common.print = 0;  // failures are reported as exceptions, not printed
    common.supernodal = options.backend == CholeskyBackend::CholmodSupernodal ? CHOLMOD_SUPERNODAL
                                                                              : CHOLMOD_SIMPLICIAL;
  }
  ~Impl() {
    freeFactor();
    cholmod_finish(&common);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  bool usesCholmod() const { return options.backend != CholeskyBackend::EigenSimplicial; }

  void freeFactor() {
    cholmod_free_factor(&factor, &common);
    cholmod_free_dense(&solution, &common);
    cholmod_free_dense(&workY, &common);
    cholmod_free_dense(&workE, &common);
    eigen.reset();
  }

  void checkStatus(const char* what) const {
    if (common.status < CHOLMOD_OK)
      throw SolverError(std::string("sparse Cholesky: CHOLMOD ") + what + " failed (status " +
                        std::to_string(common.status) +
                        (common.status == CHOLMOD_OUT_OF_MEMORY ? ", out of memory)" : ")"));
  }

  // Permuted pivot index -> column of the caller's matrix.
  long originalColumn(long pivot) const {
    if (usesCholmod()) return static_cast<const int*>(factor->Perm)[pivot];
    return eigen->permutationPinv().indices()[pivot];
  }

  void factorizeCholmod(const SparseMatrix& m) {
    cholmod_sparse a = lowerView(m);
    cholmod_factorize(&a, factor, &common);
    if (common.status == CHOLMOD_NOT_POSDEF)
      throwNotPositiveDefinite(originalColumn(long(factor->minor)), n);
    checkStatus("factorization");
    if (!factor->is_ll) {
      // LDL^T proceeds through negative pivots, so check D (the diagonal of each column).
      const auto* p = static_cast<const int*>(factor->p);
      const auto* x = static_cast<const double*>(factor->x);
      for (int j = 0; j < n; ++j)
        if (!(x[p[j]] > 0)) throwNotPositiveDefinite(originalColumn(j), n);
    }
  }

  void factorizeEigen(const SparseMatrix& m) {
    eigen->factorize(m);
    // Eigen stops at a zero pivot but accepts negative ones; either way the first non-positive
    // entry of D is the failing pivot.
    const Eigen::VectorXd& d = eigen->vectorD();
    for (int k = 0; k < n; ++k)
      if (!(d[k] > 0)) throwNotPositiveDefinite(originalColumn(k), n);
    MSPLINE_ASSERT(eigen->info() == Eigen::Success, "Eigen LDL^T failed with positive pivots");
  }
};

SparseCholesky::SparseCholesky(const CholeskyOptions& options)
    : impl_(std::make_unique<Impl>(options)) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

void SparseCholesky::analyze(const SparseMatrix& pattern) {
  MSPLINE_ASSERT(impl_, "use of a moved-from SparseCholesky");
  Impl& s = *impl_;
  if (pattern.rows() != pattern.cols())
    throw InputError("sparse Cholesky: matrix is " + std::to_string(pattern.rows()) + " x " +
                     std::to_string(pattern.cols()) + ", not square");
  // CHOLMOD reads the arrays directly, which needs compressed storage.
  std::optional<SparseMatrix> compressed;
  if (!pattern.isCompressed()) {
    compressed.emplace(pattern);
    compressed->makeCompressed();
  }
  const SparseMatrix& m = compressed ? *compressed : pattern;

  auto start = Clock::now();
  s.freeFactor();
  s.analyzed = s.factorized = false;
  s.n = int(m.rows());
  s.outer.assign(m.outerIndexPtr(), m.outerIndexPtr() + m.cols() + 1);
  s.inner.assign(m.innerIndexPtr(), m.innerIndexPtr() + m.nonZeros());
  if (s.n > 0) {
    if (s.usesCholmod()) {
      cholmod_sparse a = lowerView(m);
      s.factor = cholmod_analyze(&a, &s.common);
      s.checkStatus("analysis");
      MSPLINE_ASSERT(s.factor, "cholmod_analyze returned no factor");
      s.lnz = long(s.common.lnz);
    } else {
      s.eigen.emplace();
      s.eigen->analyzePattern(m);
    }
  }
  s.analyzed = true;
  s.analyzeSeconds = secondsSince(start);
}

void SparseCholesky::factorize(const SparseMatrix& matrix) {
  MSPLINE_ASSERT(impl_, "use of a moved-from SparseCholesky");
  Impl& s = *impl_;
  MSPLINE_ASSERT(s.analyzed, "factorize() before analyze()");
  std::optional<SparseMatrix> compressed;
  if (!matrix.isCompressed()) {
    compressed.emplace(matrix);
    compressed->makeCompressed();
  }
  const SparseMatrix& m = compressed ? *compressed : matrix;
  MSPLINE_ASSERT(m.rows() == s.n && m.cols() == s.n && m.nonZeros() == long(s.inner.size()) &&
                     std::equal(s.outer.begin(), s.outer.end(), m.outerIndexPtr()) &&
                     std::equal(s.inner.begin(), s.inner.end(), m.innerIndexPtr()),
                 "factorize() needs the pattern given to analyze()");

  auto start = Clock::now();
  s.factorized = false;
  if (s.n > 0) {
    if (s.usesCholmod())
      s.factorizeCholmod(m);
    else
      s.factorizeEigen(m);
  }
  if (!s.usesCholmod() && s.eigen)
    s.lnz = long(s.eigen->matrixL().nestedExpression().nonZeros()) + s.n;
  s.factorized = true;
  s.factorizeSeconds = secondsSince(start);
}

void SparseCholesky::compute(const SparseMatrix& matrix) {
  analyze(matrix);
  factorize(matrix);
}

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& rhs) const {
  MSPLINE_ASSERT(impl_, "use of a moved-from SparseCholesky");
  Impl& s = *impl_;
  MSPLINE_ASSERT(s.factorized, "solve() without a successful factorize()");
  MSPLINE_ASSERT(rhs.size() == s.n, "solve(): right-hand side has the wrong size");
  if (s.n == 0) return {};
  if (!s.usesCholmod()) return s.eigen->solve(rhs);

  cholmod_dense b{};
  b.nrow = b.nzmax = b.d = std::size_t(s.n);
  b.ncol = 1;
  b.x = const_cast<double*>(rhs.data());
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  cholmod_solve2(CHOLMOD_A, s.factor, &b, nullptr, &s.solution, nullptr, &s.workY, &s.workE,
                 &s.common);
  s.checkStatus("solve");
  return Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(s.solution->x), s.n);
}

int SparseCholesky::size() const {
  return impl_ ? impl_->n : 0;
}
double SparseCholesky::lastAnalyzeSeconds() const {
  return impl_->analyzeSeconds;
}
double SparseCholesky::lastFactorizeSeconds() const {
  return impl_->factorizeSeconds;
}
long SparseCholesky::factorNonZeros() const {
  return impl_->lnz;
}
const CholeskyOptions& SparseCholesky::options() const {
  return impl_->options;
}

const char* choleskyBackendName(CholeskyBackend backend) {
  switch (backend) {
    case CholeskyBackend::CholmodSupernodal:
      return "CHOLMOD supernodal";
    case CholeskyBackend::CholmodSimplicial:
      return "CHOLMOD simplicial";
    case CholeskyBackend::EigenSimplicial:
      return "Eigen SimplicialLDLT";
  }
  return "unknown backend";
}

}  // namespace mspline::structure
