#include "mspline/structure/topology/cut_along_edges.h"

#include <cstdint>
#include <numeric>
#include <string>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/polygon_soup.h"

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

  // The copies and faces go through a soup; toTriMesh keeps the face order.
  PolygonSoup soup;
  std::vector<int> sourceVertex;
  std::vector<int> copyOf(surface.n_halfedges(), -1);
  for (auto v : surface.vertices()) {
    for (auto h : surface.vih_range(v)) {
      if (surface.is_boundary(h)) continue;
      const int r = find(h.idx());
      if (copyOf[r] != -1) continue;
      copyOf[r] = static_cast<int>(sourceVertex.size());
      sourceVertex.push_back(v.idx());
      const auto& p = surface.point(v);
      soup.positions.push_back({p[0], p[1], p[2]});
    }
  }
  for (auto f : surface.faces()) {
    std::vector<std::int64_t> corners;
    for (auto h : surface.fh_range(f)) corners.push_back(copyOf[find(h.idx())]);
    soup.faces.push_back(std::move(corners));
  }
  try {
    CutMesh result{toTriMesh(soup), std::move(sourceVertex)};
    return result;
  } catch (const TopologyError& error) {
    throw InternalError(std::string("cutting produced a mesh OpenMesh cannot hold: ") +
                        error.what());
  }
}

}  // namespace mspline::structure
