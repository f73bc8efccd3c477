#include "structure/cut_along_edges.h"

#include <numeric>

#include "structure/errors.h"

namespace mspline::structure {

CutMesh cutAlongEdges(const TriMesh& surface, const std::vector<int>& cutEdges) {
  std::vector<char> cut(surface.n_edges(), 0);
  for (int e : cutEdges) cut.at(e) = 1;

  // A corner is named by the face halfedge pointing at its vertex; corners of one vertex glued
  // across an uncut edge belong to the same copy.
  std::vector<int> root(surface.n_halfedges());
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  auto unite = [&](TriMesh::HalfedgeHandle a, TriMesh::HalfedgeHandle b) {
    root[find(a.idx())] = find(b.idx());
  };
  for (auto e : surface.edges()) {
    if (cut[e.idx()] || surface.is_boundary(e)) continue;
    const auto h0 = surface.halfedge_handle(e, 0);
    const auto h1 = surface.halfedge_handle(e, 1);
    unite(h0, surface.prev_halfedge_handle(h1));
    unite(surface.prev_halfedge_handle(h0), h1);
  }

  CutMesh result;
  std::vector<int> copyOf(surface.n_halfedges(), -1);
  for (auto v : surface.vertices()) {
    for (auto h : surface.vih_range(v)) {
      if (surface.is_boundary(h)) continue;
      const int r = find(h.idx());
      if (copyOf[r] != -1) continue;
      copyOf[r] = static_cast<int>(result.sourceVertex.size());
      result.sourceVertex.push_back(v.idx());
      result.mesh.add_vertex(surface.point(v));
    }
  }
  for (auto f : surface.faces()) {
    std::vector<TriMesh::VertexHandle> corners;
    for (auto h : surface.fh_range(f)) corners.emplace_back(copyOf[find(h.idx())]);
    const auto added = result.mesh.add_face(corners);
    MSPLINE_ASSERT(added.is_valid() && added.idx() == f.idx(),
                   "cutting produced a face OpenMesh cannot add (face " + std::to_string(f.idx()) + ")");
  }
  return result;
}

}  // namespace mspline::structure
