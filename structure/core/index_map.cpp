#include "mspline/structure/core/index_map.h"

#include <algorithm>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

IndexMap::IndexMap(std::size_t count, const std::vector<char>& excluded) : unknownOf_(count, -1) {
  MSPLINE_ASSERT(excluded.empty() || excluded.size() == count,
                 "IndexMap: the exclusion flags must cover every element");
  for (std::size_t i = 0; i < count; ++i) {
    if (!excluded.empty() && excluded[i]) continue;
    unknownOf_[i] = int(elementOf_.size());
    elementOf_.push_back(i);
  }
}

Eigen::VectorXd IndexMap::gather(const Eigen::Ref<const Eigen::VectorXd>& perElement) const {
  MSPLINE_ASSERT(std::size_t(perElement.size()) == count(), "gather: wrong per-element size");
  Eigen::VectorXd result(size());
  for (int k = 0; k < size(); ++k) result[k] = perElement[Eigen::Index(element(k))];
  return result;
}

void IndexMap::scatter(const Eigen::Ref<const Eigen::VectorXd>& unknowns,
                       Eigen::Ref<Eigen::VectorXd> perElement) const {
  MSPLINE_ASSERT(unknowns.size() == size(), "scatter: wrong unknown vector size");
  MSPLINE_ASSERT(std::size_t(perElement.size()) == count(), "scatter: wrong per-element size");
  for (int k = 0; k < size(); ++k) perElement[Eigen::Index(element(k))] = unknowns[k];
}

Eigen::SparseMatrix<double> IndexMap::restrict(
    const Eigen::SparseMatrix<double>& perElement) const {
  MSPLINE_ASSERT(
      std::size_t(perElement.rows()) == count() && std::size_t(perElement.cols()) == count(),
      "restrict: matrix size differs from the element count");
  // Columns of unknowns in order; within a column the kept rows stay sorted because the map is
  // increasing, so the result is built directly in compressed form.
  Eigen::SparseMatrix<double> result(size(), size());
  std::vector<int> outer(std::size_t(size()) + 1, 0);
  std::vector<int> inner;
  std::vector<double> values;
  for (int k = 0; k < size(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(perElement, Eigen::Index(element(k))); it;
         ++it) {
      int row = unknown(std::size_t(it.row()));
      if (row < 0) continue;
      inner.push_back(row);
      values.push_back(it.value());
    }
    outer[std::size_t(k) + 1] = int(inner.size());
  }
  result.resizeNonZeros(Eigen::Index(inner.size()));
  std::copy(outer.begin(), outer.end(), result.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), result.innerIndexPtr());
  std::copy(values.begin(), values.end(), result.valuePtr());
  return result;
}

}  // namespace mspline::structure
