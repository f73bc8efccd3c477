#include "mspline/structure/topology/topology.h"

#include <vector>

namespace mspline::structure {

TopologyReport analyzeTopology(const TriMesh& mesh) {
  TopologyReport report;
  report.vertices = mesh.n_vertices();
  report.edges = mesh.n_edges();
  report.faces = mesh.n_faces();

  // Components over vertices, so that an isolated vertex counts as its own component.
  std::vector<char> seen(mesh.n_vertices(), 0);
  std::vector<TriMesh::VertexHandle> stack;
  for (auto start : mesh.vertices()) {
    if (seen[start.idx()]) continue;
    ++report.components;
    seen[start.idx()] = 1;
    stack.push_back(start);
    while (!stack.empty()) {
      auto v = stack.back();
      stack.pop_back();
      for (auto w : mesh.vv_range(v)) {
        if (seen[w.idx()]) continue;
        seen[w.idx()] = 1;
        stack.push_back(w);
      }
    }
  }

  std::vector<char> visited(mesh.n_halfedges(), 0);
  for (auto h : mesh.halfedges()) {
    if (!mesh.is_boundary(h) || visited[h.idx()]) continue;
    ++report.boundaryLoops;
    auto walk = h;
    do {
      visited[walk.idx()] = 1;
      walk = mesh.next_halfedge_handle(walk);
    } while (walk != h && !visited[walk.idx()]);
  }

  report.euler = static_cast<long>(report.vertices) - static_cast<long>(report.edges) +
                 static_cast<long>(report.faces);
  report.genus = (2 * static_cast<long>(report.components) - report.euler -
                  static_cast<long>(report.boundaryLoops)) /
                 2;
  report.closed = report.boundaryLoops == 0;
  report.orientable = true;
  return report;
}

}  // namespace mspline::structure
