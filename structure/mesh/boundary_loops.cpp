#include "mspline/structure/mesh/boundary_loops.h"

namespace mspline::structure {

std::vector<std::vector<TriMesh::VertexHandle>> boundaryLoops(const TriMesh& mesh) {
  std::vector<std::vector<TriMesh::VertexHandle>> loops;
  std::vector<char> visited(mesh.n_halfedges(), 0);
  for (auto start : mesh.halfedges()) {
    if (!mesh.is_boundary(start) || visited[start.idx()]) continue;
    auto& loop = loops.emplace_back();
    for (auto h = start; !visited[h.idx()]; h = mesh.next_halfedge_handle(h)) {
      visited[h.idx()] = 1;
      loop.push_back(mesh.from_vertex_handle(h));
    }
  }
  return loops;
}

}  // namespace mspline::structure
