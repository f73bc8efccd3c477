#include "mspline/structure/topology/cut_graph.h"

#include <algorithm>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

CutGraph computeCutGraph(const TriMesh& mesh, const HomotopyBasis& basis) {
  std::vector<char> cut(mesh.n_edges(), 0);
  auto mark = [&](const std::vector<int>& path) {
    for (std::size_t k = 0; k + 1 < path.size(); ++k) {
      const auto h =
          mesh.find_halfedge(TriMesh::VertexHandle(path[k]), TriMesh::VertexHandle(path[k + 1]));
      MSPLINE_ASSERT(h.is_valid(), "path vertices are not adjacent");
      cut[mesh.edge_handle(h).idx()] = 1;
    }
  };
  for (const auto& loop : basis.loops) mark(loop);
  for (int anchor : basis.boundaryAnchors) mark(treePath(basis, anchor));

  if (basis.loops.empty() && basis.boundaryLoops.empty()) {
    const TriMesh::VertexHandle base(basis.baseVertex);
    const auto first = *mesh.cvoh_begin(base);
    const auto middle = mesh.to_vertex_handle(first);
    for (auto h : mesh.voh_range(middle)) {
      if (mesh.to_vertex_handle(h) == base) continue;
      cut[mesh.edge_handle(first).idx()] = 1;
      cut[mesh.edge_handle(h).idx()] = 1;
      break;
    }
  }

  // Prune dangling trees: an interior leaf of the cut only adds a slit that leads nowhere.
  std::vector<int> degree(mesh.n_vertices(), 0);
  for (auto e : mesh.edges())
    if (cut[e.idx()]) {
      ++degree[mesh.from_vertex_handle(mesh.halfedge_handle(e, 0)).idx()];
      ++degree[mesh.to_vertex_handle(mesh.halfedge_handle(e, 0)).idx()];
    }
  const bool sphere = basis.loops.empty() && basis.boundaryLoops.empty();
  std::vector<int> leaves;
  for (auto v : mesh.vertices())
    if (degree[v.idx()] == 1 && !mesh.is_boundary(v) && !sphere) leaves.push_back(v.idx());
  while (!leaves.empty()) {
    const TriMesh::VertexHandle v(leaves.back());
    leaves.pop_back();
    if (degree[v.idx()] != 1) continue;
    for (auto h : mesh.voh_range(v)) {
      const auto e = mesh.edge_handle(h);
      if (!cut[e.idx()]) continue;
      cut[e.idx()] = 0;
      --degree[v.idx()];
      const auto w = mesh.to_vertex_handle(h);
      if (--degree[w.idx()] == 1 && !mesh.is_boundary(w)) leaves.push_back(w.idx());
      break;
    }
  }

  CutGraph graph;
  for (auto e : mesh.edges())
    if (cut[e.idx()]) graph.edges.push_back(e.idx());
  return graph;
}

}  // namespace mspline::structure
