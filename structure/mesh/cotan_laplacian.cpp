#include "mspline/structure/mesh/cotan_laplacian.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/exact_scale.h"

namespace mspline::structure {

Eigen::SparseMatrix<double> cotanLaplacian(const TriMesh& mesh) {
  // Half the cotangent of the angle opposite each halfedge (0 for boundary halfedges), so an
  // edge's weight is the sum over its two halfedges.
  std::vector<double> halfCot(mesh.n_halfedges(), 0.0);
  for (auto f : mesh.faces()) {
    for (auto h : mesh.fh_range(f)) {
      auto a = mesh.point(mesh.from_vertex_handle(h));
      auto b = mesh.point(mesh.to_vertex_handle(h));
      auto c = mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h)));
      // A cotangent has no unit: computed on edges scaled by a power of two (exact, so the same
      // bits at an ordinary unit), it neither overflows nor underflows at any unit.
      const double scale = exactUnitScale(std::max((a - c).max_abs(), (b - c).max_abs()));
      const auto u = (a - c) * scale, v = (b - c) * scale;
      double doubleArea = OpenMesh::cross(u, v).norm();
      if (!(doubleArea > 0))
        throw InputError("cotangent Laplacian: face " + std::to_string(f.idx()) + " has zero area");
      halfCot[std::size_t(h.idx())] = 0.5 * OpenMesh::dot(u, v) / doubleArea;
    }
  }

  // Built column by column in compressed form: the column of v holds v's neighbours and v itself.
  const int n = int(mesh.n_vertices());
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.resizeNonZeros(Eigen::Index(n + 2 * mesh.n_edges()));
  int* outer = laplacian.outerIndexPtr();
  int* inner = laplacian.innerIndexPtr();
  double* values = laplacian.valuePtr();
  std::vector<std::pair<int, double>> column;
  int next = 0;
  for (int v = 0; v < n; ++v) {
    column.clear();
    double diagonal = 0;
    for (auto h : mesh.voh_range(TriMesh::VertexHandle(v))) {
      double w = halfCot[std::size_t(h.idx())] +
                 halfCot[std::size_t(mesh.opposite_halfedge_handle(h).idx())];
      column.emplace_back(mesh.to_vertex_handle(h).idx(), -w);
      diagonal += w;
    }
    column.emplace_back(v, diagonal);
    std::sort(column.begin(), column.end());
    outer[v] = next;
    for (const auto& [row, value] : column) {
      inner[next] = row;
      values[next] = value;
      ++next;
    }
  }
  outer[n] = next;
  MSPLINE_ASSERT(next == laplacian.nonZeros(), "cotangent Laplacian: edge count mismatch");
  return laplacian;
}

}  // namespace mspline::structure
