#pragma once
// The one way to build Eigen systems over mesh elements: element indices (e.g. vertex idx()) map
// to unknown indices 0..size()-1, skipping the excluded (fixed, pinned) elements, in increasing
// element order.
#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace mspline::structure {

class IndexMap {
 public:
  /// `count` elements; element i is excluded when excluded[i] != 0. An empty `excluded` excludes
  /// none; otherwise its size must be `count` (InternalError otherwise).
  IndexMap(std::size_t count, const std::vector<char>& excluded);

  /// Number of elements (unknowns plus excluded).
  std::size_t count() const { return unknownOf_.size(); }
  /// Number of unknowns.
  int size() const { return int(elementOf_.size()); }
  /// Unknown index of element `i`, or -1 when it is excluded.
  int unknown(std::size_t i) const { return unknownOf_[i]; }
  bool excluded(std::size_t i) const { return unknownOf_[i] < 0; }
  /// Element of unknown `k`.
  std::size_t element(int k) const { return elementOf_[std::size_t(k)]; }

  /// The unknowns' entries of a per-element vector (size count()) -> vector of size size().
  Eigen::VectorXd gather(const Eigen::Ref<const Eigen::VectorXd>& perElement) const;
  /// Writes an unknown vector into the unknowns' entries of a per-element vector; the excluded
  /// entries keep their values.
  void scatter(const Eigen::Ref<const Eigen::VectorXd>& unknowns,
               Eigen::Ref<Eigen::VectorXd> perElement) const;
  /// The rows and columns of an element-indexed count() x count() matrix that belong to unknowns.
  Eigen::SparseMatrix<double> restrict(const Eigen::SparseMatrix<double>& perElement) const;

 private:
  std::vector<int> unknownOf_;
  std::vector<std::size_t> elementOf_;
};

}  // namespace mspline::structure
