#include "mspline/structure/topology/open_surface.h"

#include <algorithm>

namespace mspline::structure {

OpenedSurface openSurface(const TriMesh& surface, std::vector<int> cutEdges) {
  std::sort(cutEdges.begin(), cutEdges.end());
  cutEdges.erase(std::unique(cutEdges.begin(), cutEdges.end()), cutEdges.end());
  OpenedSurface opened{cutAlongEdges(surface, cutEdges), cutEdges, {}, {}};

  std::vector<int> degree(surface.n_vertices(), 0);
  std::vector<char> isCut(surface.n_edges(), 0);
  for (int e : cutEdges) isCut[e] = 1;
  for (auto e : surface.edges())
    if (isCut[e.idx()] || surface.is_boundary(e)) {
      ++degree[surface.from_vertex_handle(surface.halfedge_handle(e, 0)).idx()];
      ++degree[surface.to_vertex_handle(surface.halfedge_handle(e, 0)).idx()];
    }

  const TriMesh& disk = opened.cut.mesh;
  TriMesh::HalfedgeHandle start;
  for (auto h : disk.halfedges())
    if (disk.is_boundary(h)) {
      start = h;
      break;
    }
  if (!start.is_valid()) return opened;
  for (auto h = start;;) {
    opened.boundaryLoop.push_back(disk.from_vertex_handle(h).idx());
    h = disk.next_halfedge_handle(h);
    if (h == start) break;
  }
  auto isBranch = [&](int diskVertex) { return degree[opened.cut.sourceVertex[diskVertex]] != 2; };
  const auto firstBranch =
      std::find_if(opened.boundaryLoop.begin(), opened.boundaryLoop.end(), isBranch);
  if (firstBranch != opened.boundaryLoop.end())
    std::rotate(opened.boundaryLoop.begin(), firstBranch, opened.boundaryLoop.end());
  opened.segmentBegins.push_back(0);
  for (std::size_t p = 1; p < opened.boundaryLoop.size(); ++p)
    if (isBranch(opened.boundaryLoop[p])) opened.segmentBegins.push_back(p);
  return opened;
}

std::vector<int> segmentVertices(const OpenedSurface& opened, std::size_t k) {
  const std::size_t n = opened.boundaryLoop.size();
  const std::size_t begin = opened.segmentBegins[k];
  std::size_t end = k + 1 < opened.segmentBegins.size() ? opened.segmentBegins[k + 1] : n;
  if (opened.segmentBegins.size() == 1) end = begin + n;
  std::vector<int> vertices;
  for (std::size_t p = begin; p <= end; ++p)
    vertices.push_back(opened.cut.sourceVertex[opened.boundaryLoop[p % n]]);
  return vertices;
}

}  // namespace mspline::structure
